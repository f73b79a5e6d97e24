// SPDX-License-Identifier: GPL-2.0
// The engine's speed ceiling (issue 18), in the guest under QEMU -icount:
// one axis' goto with a 10^6 steps/s^2 profile ramp, and the same move as
// a one-segment path, at each rate given (leader steps/s), on the test
// virtual port (tests/qemu/fixtures/x4vport). For each: the rising edges against
// the steps asked (none missed or merged), the shortest clock high and
// low time against their minimum (half the planned half period: the
// engine's guarantee, x4_engine.h), the step timer's lateness
// (X4STEP_GET_TIMING) next to a bare hrtimer at the same event rate in
// the same boot (tests/qemu/fixtures/x4hrbench), and the ratio of their p99.
// Rates above X4STEP_VEL_MAX must be refused. Figures for `make bench`;
// the checks are on counts and the API limit only.
//
//   speed_bench [-0] [RATE]...   (default 45000 60000 80000 100000 120000;
//                                -0: gotos without ramps)
#include <errno.h>
#include <fcntl.h>
#include <linux/x4step.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "bench.hpp"
#include "check.hpp"
#include "vport.hpp"

namespace {

using guest::Check;
using guest::F;
using guest::Percentile;
using guest::Put;
using guest::Slurp;
using guest::Spin;

using guest::kV;
uint32_t accel = 1000000;  // steps/s^2: 0.1 s ramps at 100 000 steps/s; 0: no ramps
int fd = -1;
uint64_t idle_loops;  // of Spin(kSpinNs) with no move running
constexpr uint64_t kSpinNs = 100000000;

int Ioctl(unsigned long cmd, void *arg = nullptr) { return ::ioctl(fd, cmd, arg) == 0 ? 0 : errno; }

struct Bare {
  unsigned long long events = 0, p50 = 0, p99 = 0, max = 0;
};

// A bare hrtimer firing `events` times at `rate` steps/s (2 events a step).
Bare BareTimer(uint32_t rate, uint64_t events) {
  Bare b;
  Put("/sys/kernel/debug/x4hrbench/run", F("%llu %llu\n", 500000000ull / rate, (unsigned long long)events));
  std::sscanf(Slurp("/sys/kernel/debug/x4hrbench/run").c_str(), "events %llu p50 %llu p99 %llu max %llu",
              &b.events, &b.p50, &b.p99, &b.max);
  return b;
}

bool PathIdle() {
  x4step_path_status s{};
  return Ioctl(X4STEP_GET_PATH, &s) == 0 && s.state == X4STEP_PATH_IDLE && !s.queued;
}

// Start `steps` steps of axis 1 at `rate`: a goto, or a one-segment path.
// Returns 0 or the errno of the refusal.
int Start(bool path, uint32_t rate, int32_t steps) {
  if (path) {
    x4step_segment s{};
    s.steps[0] = steps;
    s.length = steps;
    s.v_max = rate;
    s.accel = accel;
    return ::write(fd, &s, sizeof(s)) == (ssize_t)sizeof(s) ? 0 : errno;
  }
  x4step_profile p{};
  p.axis = 1;
  p.vm = rate;
  p.a0 = p.ae = accel;
  if (Ioctl(X4STEP_SET_PROFILE, &p)) return errno;
  x4step_goto g{};
  g.axes = 1;
  g.flags = X4STEP_GOTO_RELATIVE;
  g.target[0] = steps;
  return Ioctl(X4STEP_GOTO, &g);
}

bool WaitEnd(bool path) {
  if (path) {
    for (int i = 0; i < 3000; i++) {
      if (PathIdle()) return true;
      usleep(5000);
    }
    return false;
  }
  pollfd p{fd, POLLIN, 0};
  return poll(&p, 1, 30000) == 1 && (p.revents & POLLIN);
}

void Measure(bool path, uint32_t rate) {
  const char *kind = path ? "path" : "goto";
  // 0.2 s at the top speed, plus both ramps.
  const int32_t steps = int32_t(rate / 5 + (accel ? uint64_t(rate) * rate / accel : 0));
  if (path && !accel) return;  // a segment has a ramp
  x4step_timing t{};
  Ioctl(X4STEP_GET_TIMING, &t);  // reset
  Put(kV + "clear", "1\n");
  const int err = Start(path, rate, steps);
  if (rate > X4STEP_VEL_MAX) {
    std::printf("ceiling %s %6u steps/s: refused (%s), above X4STEP_VEL_MAX %u\n", kind, rate,
                err ? std::strerror(err) : "accepted", X4STEP_VEL_MAX);
    Check(err != 0, F("%s at %u steps/s, above the limit, refused", kind, rate));
    if (!err) {
      Ioctl(X4STEP_STOP);
      WaitEnd(path);
    }
    return;
  }
  if (err) {
    std::printf("ceiling %s %6u steps/s: refused (%s)\n", kind, rate, std::strerror(err));
    Check(false, F("%s at %u steps/s accepted", kind, rate));
    return;
  }
  // The CPU the step timer takes at the top speed: a spinner's loss over
  // 0.1 s of the 0.2 s cruise.
  usleep(accel ? uint32_t(uint64_t(rate) * 1000000 / accel) + 20000 : 20000);
  const double cpu = 100.0 * (1.0 - double(Spin(kSpinNs)) / double(idle_loops));
  const bool ended = WaitEnd(path);
  Ioctl(X4STEP_GET_TIMING, &t);
  const guest::Clock e = guest::Clocks()[0];
  const unsigned rises = unsigned(e.rises.size());
  const unsigned long long overruns = std::strtoull(Slurp(kV + "overruns").c_str(), nullptr, 10);
  const uint64_t half = 500000000ull / rate, min_ok = half / 2;
  const bool edges_ok =
      ended && !overruns && rises == unsigned(steps) && e.min_high >= min_ok && e.min_low >= min_ok;
  const uint64_t p50 = Percentile(t, 500), p99 = Percentile(t, 990);
  const Bare b = BareTimer(rate, t.events);
  std::printf(
      "ceiling %s %6u steps/s: %u/%d steps, min high %llu ns, min low %llu ns (planned %llu, minimum %llu): "
      "edges %s; timer CPU %.0f%%; lateness p50 %llu p99 %llu max %llu ns (%llu events, %llu capped, %llu "
      "shifts); "
      "bare hrtimer p50 %llu p99 %llu max %llu ns; p99 ratio %.2f\n",
      kind, rate, rises, steps, (unsigned long long)e.min_high, (unsigned long long)e.min_low,
      (unsigned long long)half, (unsigned long long)min_ok, edges_ok ? "ok" : "BAD", cpu,
      (unsigned long long)p50, (unsigned long long)p99, (unsigned long long)t.late_max_ns,
      (unsigned long long)t.events, (unsigned long long)t.capped, (unsigned long long)t.shifts, b.p50, b.p99,
      b.max, b.p99 ? double(p99) / double(b.p99) : 0.0);
  Check(edges_ok, F("%s at %u steps/s: every step, no pulse or space below %llu ns", kind, rate,
                    (unsigned long long)min_ok));
}

}  // namespace

int main(int argc, char **argv) {
  setvbuf(stdout, nullptr, _IOLBF, 0);
  std::vector<uint32_t> rates;
  int i = 1;
  if (argc > 1 && std::string(argv[1]) == "-0") {
    accel = 0;
    i++;
  }
  for (; i < argc; i++) rates.push_back(std::strtoul(argv[i], nullptr, 10));
  if (rates.empty()) rates = {45000, 60000, 80000, 100000, 120000};
  const int port = guest::VportNumber();
  if (port < 0) return guest::Finish("speed_bench");
  const std::string dev = "/dev/x4step" + std::to_string(port);
  fd = open(dev.c_str(), O_RDWR);
  Check(fd >= 0, "open " + dev);
  if (fd < 0) return guest::Finish("speed_bench");
  idle_loops = Spin(kSpinNs);
  std::printf("ceiling: X4STEP_VEL_MAX %u steps/s, ramps %u steps/s^2, 0.2 s at the top speed\n",
              X4STEP_VEL_MAX, accel);
  for (const uint32_t r : rates)
    for (const bool path : {false, true}) Measure(path, r);
  close(fd);
  return guest::Finish("speed_bench");
}
