// SPDX-License-Identifier: GPL-2.0
// Timing benchmark in the guest (run under QEMU -icount, where guest time
// is reproducible): lateness of x4step's step timer during a 4-axis 20 kHz
// move, next to a bare hrtimer at the same rate in the same boot
// (tests/qemu/fixtures/x4hrbench), and the edges a 20 kHz move leaves on the
// virtual port (tests/qemu/fixtures/x4vport): none missed, none merged.
#include <fcntl.h>
#include <linux/x4step.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bench.hpp"
#include "check.hpp"
#include "engine_ref.h"

namespace {

using guest::Check;
using guest::Percentile;
using guest::Slurp;
using guest::Spin;

bool RunMove(const char *dev, x4step_move m, x4step_timing *timing) {
  const int fd = open(dev, O_RDWR);
  if (fd < 0) return false;
  x4step_timing t;
  ioctl(fd, X4STEP_GET_TIMING, &t);  // reset
  bool ok = ioctl(fd, X4STEP_LOAD, &m) == 0 && ioctl(fd, X4STEP_START) == 0;
  pollfd p{fd, POLLIN, 0};
  ok = ok && poll(&p, 1, 60000) == 1;
  if (timing) ok = ok && ioctl(fd, X4STEP_GET_TIMING, timing) == 0;
  close(fd);
  return ok;
}

// The CPU time one timer event costs (interrupt, hrtimer, engine, port
// write), from how much a spinner loses while moves need `events_per_s`.
// `start` starts the moves on fd; they must run for longer than 0.5 s.
double EventCostNs(const char *dev, double events_per_s, uint64_t idle_loops, bool (*start)(int fd)) {
  const int fd = open(dev, O_RDWR);
  if (fd < 0 || !start(fd)) {
    if (fd >= 0) close(fd);
    return -1;
  }
  usleep(20000);  // past the ramp
  const uint64_t busy = Spin(400000000);
  ioctl(fd, X4STEP_STOP);
  close(fd);
  const double lost = 1.0 - double(busy) / double(idle_loops);
  return lost / events_per_s * 1e9;
}

bool StartTwo45k(int fd) {
  bool ok = true;
  for (int a = 1; a <= 2; a++) {
    x4step_profile p{};
    p.axis = a;
    p.vm = 45000;
    p.a0 = p.ae = 1000000;
    x4step_goto g{};
    g.axes = 1u << (a - 1);
    g.flags = X4STEP_GOTO_RELATIVE;
    g.target[a - 1] = 100000;
    ok = ok && ioctl(fd, X4STEP_SET_PROFILE, &p) == 0 && ioctl(fd, X4STEP_GOTO, &g) == 0;
  }
  return ok;
}

bool StartOne20k(int fd) {
  x4step_endless e{1, 1, 20000, 0, 0, 0, {0, 0}};
  return ioctl(fd, X4STEP_MOVE_ENDLESS, &e) == 0;
}

}  // namespace

int main() {
  setvbuf(stdout, nullptr, _IOLBF, 0);
  // 1. Lateness of the engine's timer, and of a bare hrtimer.
  x4step_timing t{};
  Check(RunMove("/dev/x4step0", {{20000, 15000, -10000, 5000}, 20000, 50, 0, 0}, &t), "4-axis 20 kHz move");
  const uint64_t p50 = Percentile(t, 500), p99 = Percentile(t, 990);
  std::printf("x4step timer:  %llu events, lateness p50 %llu ns, p99 %llu ns, max %llu ns\n",
              (unsigned long long)t.events, (unsigned long long)p50, (unsigned long long)p99,
              (unsigned long long)t.late_max_ns);
  {
    std::ofstream run("/sys/kernel/debug/x4hrbench/run");
    run << "25000 " << t.events << std::endl;  // 2 events per 20 kHz step
  }
  const std::string bare = Slurp("/sys/kernel/debug/x4hrbench/run");
  unsigned long long n = 0, b50 = 0, b99 = 0, bmax = 0;
  Check(std::sscanf(bare.c_str(), "events %llu p50 %llu p99 %llu max %llu", &n, &b50, &b99, &bmax) == 4,
        "bare hrtimer baseline ran");
  std::printf("bare hrtimer:  %llu events at 40000/s, lateness p50 %llu ns, p99 %llu ns, max %llu ns\n", n,
              b50, b99, bmax);
  if (b50 && b99)
    std::printf("ratio x4step/bare: p50 %.2f, p99 %.2f, max %.2f\n", double(p50) / b50, double(p99) / b99,
                bmax ? double(t.late_max_ns) / bmax : 0.0);

  // 2. Edges of a 20 kHz move on the virtual port, in guest time.
  const std::string port = Slurp("/sys/kernel/debug/x4vport/port");
  const std::string dev = "/dev/x4step" + std::to_string(std::atoi(port.c_str()));
  { std::ofstream("/sys/kernel/debug/x4vport/clear") << "1" << std::endl; }
  Check(RunMove(dev.c_str(), {{20000, 0, 0, 0}, 20000, 0, 0, 0}, nullptr), "20 kHz move on the virtual port");
  std::istringstream trace(Slurp("/sys/kernel/debug/x4vport/trace"));
  unsigned long long ts, last_rise = 0, last_fall = 0, min_high = ~0ull, min_low = ~0ull;
  char reg;
  std::string val;
  unsigned prev = 0, rises = 0;
  while (trace >> ts >> reg >> val) {
    if (reg != 'd') continue;
    const unsigned v = std::strtoul(val.c_str(), nullptr, 16);
    const bool clk = v & 2, was = prev & 2;
    if (clk && !was) {
      if (rises && ts - last_fall < min_low) min_low = ts - last_fall;
      last_rise = ts;
      rises++;
    } else if (!clk && was) {
      if (ts - last_rise < min_high) min_high = ts - last_rise;
      last_fall = ts;
    }
    prev = v;
  }
  std::printf("20 kHz on the virtual port: %u rising edges, min high %llu ns, min low %llu ns\n", rises,
              min_high, min_low);
  Check(rises == 20000, "no step missed or merged at 20 kHz");
  Check(min_high >= 20000 && min_low >= 20000, "every pulse and gap at least 20 us");

  // 3. The manual's example on the virtual port: direction setup, and
  //    every leader step against the double-precision profile.
  { std::ofstream("/sys/kernel/debug/x4vport/clear") << "1" << std::endl; }
  Check(RunMove(dev.c_str(), {{1000, 800, -600, 400}, 1000, 50, 0, 0}, nullptr),
        "manual example on the virtual port");
  std::istringstream trace2(Slurp("/sys/kernel/debug/x4vport/trace"));
  std::vector<unsigned long long> rise_t;
  unsigned long long dir_t = 0;
  prev = 0;
  bool first = true;
  while (trace2 >> ts >> reg >> val) {
    if (reg != 'd') continue;
    const unsigned v = std::strtoul(val.c_str(), nullptr, 16);
    if (!first && ((v ^ prev) & 0x55) && rise_t.empty()) dir_t = ts;
    if ((v & 2) && !(prev & 2) && !first) rise_t.push_back(ts);
    if (first && (v & 0x55) != 0) dir_t = ts;  // directions in the first write
    first = false;
    prev = v;
  }
  double worst = 0;
  for (size_t i = 0; i < rise_t.size(); i++) {
    const double ideal = x4test::ref_step_time(1000, 1000, 50, i) * 1e9;
    const double d = std::abs(double(rise_t[i] - rise_t[0]) - ideal);
    if (d > worst) worst = d;
  }
  const unsigned long long setup = rise_t.empty() ? 0 : rise_t[0] - dir_t;
  std::printf(
      "manual example: %zu leader steps, direction setup %llu ns, max step-time deviation from the profile "
      "%.0f ns\n",
      rise_t.size(), setup, worst);
  Check(rise_t.size() == 1000, "1000 leader steps");
  Check(setup >= 100000, "direction set at least 100 us before the first step");
  Check(worst < 10000, "every step within 10 us of the profile");

  // 4. Configured step timing, measured in guest time.
  {
    const int cfd = open(dev.c_str(), O_RDWR);
    x4step_step_timing st{5000, 3000, 20000, 40000, {0, 0, 0, 0}};
    Check(ioctl(cfd, X4STEP_SET_STEP_TIMING, &st) == 0, "set step timing 5/3/20/40 us");
    // Three moves, there and back and there: the module's timer is now and
    // then a microsecond late, which only lengthens a time, so the
    // shortest setup and hold of the three are the engine's.
    long long setup = 1LL << 60, hold = 1LL << 60, pulse_min = 1LL << 60, pulse_max = 0;
    bool moved = true;
    for (int k = 0; k < 3; k++) {
      { std::ofstream("/sys/kernel/debug/x4vport/clear") << "1" << std::endl; }
      const int sign = k % 2 ? -1 : 1;
      x4step_move m{{300 * sign, 100 * sign, 0, 0}, 10000, 20, 0, 0};
      pollfd p{cfd, POLLIN, 0};
      moved = moved && ioctl(cfd, X4STEP_LOAD, &m) == 0 && ioctl(cfd, X4STEP_START) == 0 &&
              poll(&p, 1, 10000) == 1;
      std::istringstream tr(Slurp("/sys/kernel/debug/x4vport/trace"));
      long long rise = -1, dir = -1, last_fall = -1, aktiv_off = -1, first_rise = -1;
      unsigned pv = 0;
      while (tr >> ts >> reg >> val) {
        const unsigned v = std::strtoul(val.c_str(), nullptr, 16);
        // AKTIV (pin 17, C3 inverted) goes high with the directions.
        if (reg == 'c' && !(v & 8) && dir < 0) dir = ts;
        if (reg == 'c' && last_fall >= 0 && (v & 8)) aktiv_off = ts;
        if (reg != 'd') continue;
        if ((v & 2) && !(pv & 2)) {
          rise = ts;
          if (first_rise < 0) first_rise = ts;
        }
        if (!(v & 2) && (pv & 2) && rise >= 0) {
          pulse_min = std::min(pulse_min, (long long)ts - rise);
          pulse_max = std::max(pulse_max, (long long)ts - rise);
          last_fall = ts;
        }
        pv = v;
      }
      setup = std::min(setup, first_rise - dir);
      hold = std::min(hold, aktiv_off - last_fall);
    }
    Check(moved, "three moves with the step timing");
    std::printf(
        "step timing 5/3/20/40 us: pulse %lld..%lld ns, direction setup %lld ns, hold %lld ns "
        "(the shortest of three moves)\n",
        pulse_min, pulse_max, setup, hold);
    Check(pulse_min >= 5000 - 1000 && pulse_max <= 5000 + 1000, "every pulse 5 us within 1 us");
    Check(setup >= 20000 - 1000 && setup <= 20000 + 1000, "direction setup 20 us within 1 us");
    Check(hold >= 40000 - 1000 && hold <= 40000 + 1000, "direction hold 40 us within 1 us");
    x4step_step_timing def{0, 0, 100000, 0, {0, 0, 0, 0}};
    ioctl(cfd, X4STEP_SET_STEP_TIMING, &def);
    close(cfd);
  }

  // 5. What one timer event costs the CPU, and what the write budget
  //    (X4_WRITE_BUDGET, 200000 writes/s per port) takes of it.
  {
    const uint64_t idle = Spin(400000000);
    const double one = EventCostNs(dev.c_str(), 40000, idle, StartOne20k);
    const double two = EventCostNs(dev.c_str(), 180000, idle, StartTwo45k);
    std::printf(
        "timer event cost: %.0f ns at 40000 events/s (one 20 kHz axis), %.0f ns at 180000 events/s "
        "(two axes at 45000 steps/s)\n",
        one, two);
    std::printf("write budget 200000 events/s per port: %.0f%% of this CPU at the measured cost\n",
                200000 * std::max(one, two) / 1e7);
    Check(one > 0 && two > 0, "the timer's cost measured");
  }

  // 6. Outputs land on their pins (control register, hardware inversions).
  const int fd = open(dev.c_str(), O_RDWR);
  x4step_output out{X4STEP_OUT_SIGNAL1, 1};
  ioctl(fd, X4STEP_SET_OUTPUT, &out);
  unsigned c = std::strtoul(Slurp("/sys/kernel/debug/x4vport/control").c_str(), nullptr, 16);
  Check(!(c & 1) && (c & 2) && !(c & 4) && (c & 8), "signal 1 on: pin 1 high, pins 14, 16, 17 low");
  out = {X4STEP_OUT_SIGNAL2, 1};
  ioctl(fd, X4STEP_SET_OUTPUT, &out);
  out = {X4STEP_OUT_SIGNAL1, 0};
  ioctl(fd, X4STEP_SET_OUTPUT, &out);
  c = std::strtoul(Slurp("/sys/kernel/debug/x4vport/control").c_str(), nullptr, 16);
  Check((c & 1) && !(c & 2), "signal 2 on, 1 off: pin 14 high, pin 1 low");
  close(fd);
  return guest::Finish("timing_bench");
}
