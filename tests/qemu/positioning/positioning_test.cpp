// SPDX-License-Identifier: LGPL-2.1-or-later
// In-guest test of positioning (issue 8) through the C++ API, on the
// test-only virtual port tests/qemu/fixtures/x4vport, which is a machine: it counts
// each axis' step/direction edges into a position and drives inputs from
// switches placed at positions. What the module reports (coordinates,
// errors, sync) is compared with what that machine did; the edge times of
// its trace (guest time, run under --icount) measure the profiles.
//
// With --no-timing (a debug kernel) the edge-timing checks print SKIP.
//
// At the end a few moves on QEMU's emulated parport (/dev/x4step0) print
// `SEG` lines and a `COORD` line: tests/qemu/positioning/check-positioning.sh checks
// them against QEMU's own port trace (an observer outside the guest).
//
// Prints PASS/FAIL per check and figures as `info:` lines.
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "check.hpp"
#include "vport.hpp"
#include "x4step.hpp"

using namespace std::chrono_literals;

namespace {

using guest::Check;
using guest::CheckTiming;
using guest::F;
using guest::Throws;
using x4step::errc;
namespace axerr = x4step::axis_error;

using guest::kV;

using guest::Put;
using guest::Slurp;

// ---- the machine (x4vport) -------------------------------------------------

using Pos4 = std::array<long long, 4>;

Pos4 Machine() {
  Pos4 p{};
  std::istringstream in(Slurp(kV + "positions"));
  for (auto &v : p) in >> v;
  return p;
}

std::string Str(const Pos4 &p) { return F("%lld %lld %lld %lld", p[0], p[1], p[2], p[3]); }

// Replace the machine's switches: "clear" then `cmds` (';'-separated adds).
bool Switches(const std::string &cmds) {
  const bool ok = Put(kV + "switches", "clear" + (cmds.empty() ? "" : ";" + cmds) + "\n");
  Check(ok, "x4vport switches: " + (cmds.empty() ? std::string("none") : cmds));
  return ok;
}

void ClearTrace() { Put(kV + "clear", "1\n"); }

struct Edge {
  uint64_t t;  // ns, guest CLOCK_MONOTONIC
  int sign;    // +1: direction pin high
};

// Rising clock edges of each axis in the trace since the last ClearTrace().
std::array<std::vector<Edge>, 4> Edges() {
  std::array<std::vector<Edge>, 4> e;
  std::istringstream in(Slurp(kV + "trace"));
  unsigned long long t;
  char reg;
  std::string val;
  unsigned prev = 0;  // clocks are low at rest
  while (in >> t >> reg >> val) {
    if (reg != 'd') continue;
    const unsigned v = std::strtoul(val.c_str(), nullptr, 16);
    for (int a = 0; a < 4; a++) {
      const unsigned clk = 2u << (2 * a), dir = 1u << (2 * a);
      if ((v & clk) && !(prev & clk)) e[a].push_back({t, (v & dir) ? 1 : -1});
    }
    prev = v;
  }
  return e;
}

long long Signed(const std::vector<Edge> &e) {
  long long s = 0;
  for (const Edge &x : e) s += x.sign;
  return s;
}

std::vector<double> Intervals(const std::vector<Edge> &e) {  // in us
  std::vector<double> iv;
  for (size_t i = 1; i < e.size(); i++) iv.push_back(double(e[i].t - e[i - 1].t) / 1000.0);
  return iv;
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// ---- the controller -------------------------------------------------------

x4step::controller *ctl;
Pos4 off{};  // machine position - module coordinate, per axis

x4step::axes_status A() { return ctl->get_axes(); }

std::string Mod(const x4step::axes_status &s) {
  return F("%ld %ld %ld %ld", s.axis[0].position, s.axis[1].position, s.axis[2].position, s.axis[3].position);
}

std::string Flags(const x4step::axis_status &a) {
  return F("pos %ld err 0x%x%s%s", a.position, a.error, a.running ? " running" : "",
           a.synced ? " synced" : " unsynced");
}

// Wait for the axes; a move still running after `timeout` is a failure
// (and is stopped, so that the next checks start from rest).
bool Wait(unsigned mask, const std::string &what, std::chrono::milliseconds timeout = 15s) {
  const bool ended = ctl->wait_axes(x4step::axis_set{mask}, timeout);
  if (!ended) {
    Check(false, what + ": the move ends within " + std::to_string(timeout.count()) + " ms");
    Throws([&] { ctl->halt(x4step::axis_set{0x0fu}, x4step::halt_mode::stop); });
    ctl->wait_axes(x4step::axis_set{0x0fu}, 2s);
  }
  return ended;
}

// The module's coordinates plus the known offsets are the machine's positions.
bool Coords(const std::string &what) {
  const x4step::axes_status s = A();
  const Pos4 m = Machine();
  bool ok = true;
  for (int i = 0; i < 4; i++) ok &= m[i] - s.axis[i].position == off[i];
  std::string o = off == Pos4{} ? "" : " (machine - module offsets " + Str(off) + ")";
  Check(ok, what + ": module coordinates " + Mod(s) + " match the machine " + Str(m) + o);
  return ok;
}

// Move an axis (own profile) so that the machine is at `target`.
void MachineTo(int axis, long long target) {
  ctl->move_to(x4step::axis{axis}, long(target - off[axis - 1]));
  Wait(1u << (axis - 1), F("axis %d to machine %lld", axis, target));
}

// Make the module's coordinates equal the machine's (stop and set).
void Align() {
  const Pos4 m = Machine();
  for (int a = 1; a <= 4; a++) ctl->set_position(x4step::axis{a}, long(m[a - 1]));
  off = Pos4{};
}

bool Near(double got, double want, double rel) { return std::fabs(got - want) <= rel * std::fabs(want); }

const x4step::profile kFast = x4step::profile{}.top_speed(3000).accel(30000).decel(30000);

// ---- 1. coordinates --------------------------------------------------------

void TestCoordinates() {
  std::printf("== coordinates\n");
  const x4step::axes_status s0 = A();
  const Pos4 m0 = Machine();
  Check(Mod(s0) == "0 0 0 0" && m0 == Pos4{}, "start: module " + Mod(s0) + ", machine " + Str(m0));
  Check(!s0.axis[0].synced && !s0.axis[3].synced, "start: no axis synchronized");

  const x4step::profile pa = x4step::profile{}.top_speed(4000).accel(40000).decel(40000);
  const x4step::profile pb =
      x4step::profile{}.start_speed(500).end_speed(300).top_speed(2500).accel(10000).decel(20000);
  ctl->set_profile(x4step::axis{1}, pa);
  ctl->set_profile(x4step::axis{2}, pb);
  const x4step::profile gb = ctl->get_profile(x4step::axis{2});
  Check(gb.start_speed() == 500 && gb.end_speed() == 300 && gb.top_speed() == 2500 && gb.accel() == 10000 &&
            gb.decel() == 20000,
        F("profile of axis 2 reads back (%u %u %u %u %u)", gb.start_speed(), gb.end_speed(), gb.top_speed(),
          gb.accel(), gb.decel()));
  Check(Throws([] {
          ctl->set_profile(x4step::axis{1},
                           x4step::profile{}.top_speed(x4step::vel_max + 1).accel(1000).decel(1000));
        }) == errc::param_fail,
        "profile vm vel_max + 1 refused (param_fail)");
  Check(Throws([] {
          ctl->set_profile(x4step::axis{1},
                           x4step::profile{}.start_speed(2000).top_speed(1000).accel(1000).decel(1000));
        }) == errc::param_fail,
        "profile v0 > vm refused (param_fail)");

  ctl->move_to(x4step::axis{1}, 1500);
  Wait(0x1, "goto 1500");
  x4step::axis_status a = ctl->get_axis(x4step::axis{1});
  Check(a.position == 1500 && Machine()[0] == 1500 && !a.running && a.error == 0,
        F("goto absolute 1500: module %ld, machine %lld, err 0x%x", a.position, Machine()[0], a.error));
  ctl->move_by(x4step::axis{1}, -2300);
  Wait(0x1, "move_by -2300");
  a = ctl->get_axis(x4step::axis{1});
  Check(a.position == -800 && Machine()[0] == -800,
        F("goto relative -2300 from 1500: module %ld, machine %lld (want -800)", a.position, Machine()[0]));
  ClearTrace();
  ctl->move_to(x4step::axis{1}, -800);
  std::this_thread::sleep_for(20ms);
  a = ctl->get_axis(x4step::axis{1});
  Check(!a.running && a.position == -800 && Edges()[0].empty(),
        F("goto to the current coordinate makes no step (module %ld, %zu edges)", a.position,
          Edges()[0].size()));

  // Two axes at once, each with its own profile.
  ClearTrace();
  ctl->move_to(x4step::axis_set{0x3u}, {1000, -1200, 0, 0});
  x4step::axes_status s = A();
  Check(s.axis[0].running && s.axis[1].running, "goto of axes 1+2: both run right after the call");
  Wait(0x3, "goto axes 1+2");
  s = A();
  Check(s.axis[0].position == 1000 && s.axis[1].position == -1200,
        F("goto axes 1+2 to (1000, -1200): module %ld %ld", s.axis[0].position, s.axis[1].position));
  Coords("after the two-axis goto");
  auto e = Edges();
  Check(Signed(e[0]) == 1800 && Signed(e[1]) == -1200 && e[0].size() == 1800 && e[1].size() == 1200,
        F("machine saw 1800 (+%lld) and 1200 (%lld) steps", Signed(e[0]), Signed(e[1])));
  if (!e[0].empty() && !e[1].empty()) {
    const double dt = std::fabs(double(e[0][0].t) - double(e[1][0].t)) / 1000.0;
    CheckTiming(dt < 20, F("both axes' first steps at once (%.1f us apart)", dt));
    const auto i0 = Intervals(e[0]), i1 = Intervals(e[1]);
    // The middle third of each move is at cruise speed.
    const double c0 = Median(std::vector<double>(i0.begin() + i0.size() / 3, i0.begin() + 2 * i0.size() / 3));
    const double c1 = Median(std::vector<double>(i1.begin() + i1.size() / 3, i1.begin() + 2 * i1.size() / 3));
    CheckTiming(Near(c0, 1e6 / pa.top_speed(), 0.01) && Near(c1, 1e6 / pb.top_speed(), 0.01),
                F("own profiles: cruise interval axis 1 %.1f us (1/vm %.1f), axis 2 %.1f us (1/vm %.1f)", c0,
                  1e6 / pa.top_speed(), c1, 1e6 / pb.top_speed()));
    const double f0 = i0.empty() ? 0 : i0.front(), f1 = i1.empty() ? 0 : i1.front();
    const double w0 = 1e6 * std::sqrt(2.0 / pa.accel());
    const double w1 =
        1e6 * (std::sqrt(double(pb.start_speed()) * pb.start_speed() + 2.0 * pb.accel()) - pb.start_speed()) /
        pb.accel();
    CheckTiming(Near(f0, w0, 0.03) && Near(f1, w1, 0.03),
                F("own profiles: first interval axis 1 %.1f us (v0 0: %.1f), axis 2 %.1f us (v0 500: %.1f)",
                  f0, w0, f1, w1));
  }

  // A second independent move while the first runs.
  ctl->set_profile(x4step::axis{1}, kFast);
  ctl->set_profile(x4step::axis{3}, x4step::profile{}.top_speed(2000).accel(20000).decel(20000));
  ClearTrace();
  ctl->move_by(x4step::axis{1}, 3000);  // about 1.1 s
  std::this_thread::sleep_for(300ms);
  Check(ctl->get_axis(x4step::axis{1}).running, "axis 1 runs its 3000-step goto");
  Check(Throws([] { ctl->move_by(x4step::axis{1}, 10); }) == errc::is_active,
        "another goto of the running axis 1: is_active");
  const errc third = Throws([] { ctl->move_by(x4step::axis{3}, 800); });
  Check(third == errc::ok, F("goto of axis 3 while axis 1 runs is accepted (errc %d)", int(third)));
  s = A();
  Check(s.axis[0].running && s.axis[2].running, "axes 1 and 3 run at the same time");
  const errc interp = Throws([] {
    ctl->load({{0, 0, 0, 300}, 2000, 0ms});
    ctl->start();
  });
  Check(interp == errc::ok, F("interpolated move of idle axis 4 while axis 1 runs (errc %d)", int(interp)));
  const errc busy = Throws([] {
    ctl->load({{10, 0, 0, 0}, 1000, 0ms});
    ctl->start();
  });
  Check(busy == errc::is_active,
        F("interpolated move with the running axis 1: is_active (errc %d)", int(busy)));
  Wait(0xf, "axes 1, 3, 4");
  s = A();
  Check(s.axis[0].position == 4000,
        F("axis 1 at 1000 + 3000 after the overlapping moves (module %ld)", s.axis[0].position));
  Check(s.axis[2].position == 800 && s.axis[3].position == 300,
        F("axis 3 at 800, axis 4 at 300 (module %ld, %ld)", s.axis[2].position, s.axis[3].position));
  Coords("after overlapping independent moves");
  e = Edges();
  if (e[0].size() > 400 && !e[2].empty()) {
    // Axis 1's cruise (after its 150-step ramp) while axis 3 started and ran.
    const auto iv = Intervals(e[0]);
    double worst = 0, sum = 0;
    int n = 0;
    for (size_t i = 200; i + 200 < iv.size(); i++) {
      worst = std::max(worst, std::fabs(iv[i] - 1e6 / kFast.top_speed()));
      sum += iv[i];
      n++;
    }
    CheckTiming(
        worst < 25 && Near(sum / n, 1e6 / kFast.top_speed(), 0.002),
        F("axis 1's cruise undisturbed by axes 3, 4: mean %.2f us, worst deviation %.2f us (1/vm %.2f)",
          sum / n, worst, 1e6 / kFast.top_speed()));
  }
  // The refused interpolated move stays loaded: run it now.
  const errc late = Throws([] { ctl->start(); });
  Wait(0x1, "the loaded 10-step move");
  Check(late == errc::ok && ctl->get_axis(x4step::axis{1}).position == 4010,
        F("the loaded move runs once axis 1 is idle: module %ld (want 4010)",
          ctl->get_axis(x4step::axis{1}).position));

  // X4Step moves update the coordinates too.
  const x4step::axes_status before = A();
  ctl->load({{400, -300, 200, -100}, 2000, 50ms});
  ctl->start();
  Wait(0xf, "interpolated move");
  s = A();
  bool ok = true;
  const long d[4] = {400, -300, 200, -100};
  for (int i = 0; i < 4; i++) ok &= s.axis[i].position == before.axis[i].position + d[i];
  Check(ok, "interpolated move (400, -300, 200, -100): module " + Mod(before) + " -> " + Mod(s));
  Coords("after the interpolated move");
  ctl->move_endless(x4step::axis{2}, x4step::direction::negative, 2000, 20ms);
  std::this_thread::sleep_for(200ms);
  ctl->brake();
  Wait(0xf, "endless move");
  Coords("after an endless move braked");
}

// ---- 2. asymmetric profile, measured ----------------------------------------

void TestProfile() {
  std::printf("== asymmetric profile\n");
  const x4step::profile p =
      x4step::profile{}.start_speed(200).end_speed(500).top_speed(3000).accel(2000).decel(8000);
  const double v0 = p.start_speed(), ve = p.end_speed(), vm = p.top_speed(), a0 = p.accel(), ae = p.decel();
  const long steps = 4000;
  ctl->set_profile(x4step::axis{1}, p);
  ClearTrace();
  ctl->move_by(x4step::axis{1}, steps);
  // The state bits and the velocity while it runs, sampled.
  std::string phases;
  unsigned vcruise_min = ~0u, vcruise_max = 0, samples = 0, zero_v = 0;
  while (true) {
    const x4step::axis_status a = ctl->get_axis(x4step::axis{1});
    if (!a.running) break;
    const char ph = a.accelerating ? 'A' : a.cruising ? 'C' : a.decelerating ? 'D' : '?';
    if (phases.empty() || phases.back() != ph) phases += ph;
    if (ph != '?') {
      samples++;
      zero_v += a.velocity == 0;
    }
    if (a.cruising) {
      vcruise_min = std::min(vcruise_min, a.velocity);
      vcruise_max = std::max(vcruise_max, a.velocity);
    }
    std::this_thread::sleep_for(10ms);
  }
  Wait(0x1, "asymmetric profile move");
  // Right after the call the axis may still be in its direction setup
  // (100 us before the first step): running, no ramp phase yet.
  if (!phases.empty() && phases[0] == '?') {
    std::printf("info: first sample in the direction setup: running, no ramp phase\n");
    phases.erase(0, 1);
  }
  Check(phases == "ACD", "state bits seen in order accelerating, cruising, decelerating: \"" + phases + "\"");
  Check(zero_v == 0,
        F("velocity reported while stepping is never 0: %u of %u samples read 0", zero_v, samples));
  Check(vcruise_min >= 2970 && vcruise_max <= 3030,
        F("velocity while cruising %u..%u steps/s (vm 3000 +-1%%)", vcruise_min, vcruise_max));
  Coords("after the asymmetric move");

  const auto e = Edges()[0];
  Check(e.size() == size_t(steps) && Signed(e) == steps, F("%zu steps seen (want %ld)", e.size(), steps));
  if (e.size() < 100) return;
  const auto iv = Intervals(e);  // us
  const double t1 = 1e6 * (std::sqrt(v0 * v0 + 2 * a0) - v0) / a0;
  const double tl = 1e6 * (std::sqrt(ve * ve + 2 * ae) - ve) / ae;
  std::printf("info: first interval %.2f us (v0 start: %.2f), last %.2f us (ve stop: %.2f)\n", iv.front(), t1,
              iv.back(), tl);
  CheckTiming(Near(iv.front(), t1, 0.01),
              F("first interval %.2f us = (sqrt(v0^2+2a0)-v0)/a0 = %.2f us +-1%%", iv.front(), t1));
  CheckTiming(Near(iv.back(), tl, 0.01),
              F("last interval %.2f us = (sqrt(ve^2+2ae)-ve)/ae = %.2f us +-1%%", iv.back(), tl));
  // Cruise: between the ramps' planned lengths.
  const size_t sa = size_t(std::ceil((vm * vm - v0 * v0) / (2 * a0)));
  const size_t sd = size_t(std::ceil((vm * vm - ve * ve) / (2 * ae)));
  std::vector<double> dev;
  double sum = 0;
  for (size_t i = sa + 2; i + sd + 2 < iv.size(); i++) {
    dev.push_back(std::fabs(iv[i] - 1e6 / vm));
    sum += iv[i];
  }
  if (!dev.empty()) {
    std::sort(dev.begin(), dev.end());
    const double mean = sum / dev.size(), p99 = dev[dev.size() * 99 / 100], worst = dev.back();
    std::printf("info: cruise %zu intervals, mean %.3f us (1/vm %.3f), |dev| p99 %.2f us, max %.2f us\n",
                dev.size(), mean, 1e6 / vm, p99, worst);
    CheckTiming(
        Near(mean, 1e6 / vm, 0.001) && p99 <= 5 && worst <= 25,
        F("cruise intervals = 1/vm: mean %.3f us (want %.3f +-0.1%%), p99 |dev| %.2f us (<= 5), max %.2f "
          "(<= 25)",
          mean, 1e6 / vm, p99, worst));
  }
  // The ramps' durations: from the first edge to where the speed first
  // comes within 1 % of vm, and from where it last was to the last edge.
  const double thr = 1.01e6 / vm;
  size_t i_up = 0, i_down = iv.size();
  while (i_up < iv.size() && iv[i_up] > thr) i_up++;
  while (i_down > 0 && iv[i_down - 1] > thr) i_down--;
  const double t_acc = double(e[i_up + 1 < e.size() ? i_up + 1 : 0].t - e[0].t) / 1e9;
  const double t_dec = double(e.back().t - e[i_down].t) / 1e9;
  const double w_acc = (vm / 1.01 - v0) / a0, w_dec = (vm / 1.01 - ve) / ae;
  const double full_ratio = ((vm - v0) / a0) / ((vm - ve) / ae);
  std::printf(
      "info: accelerating %.4f s over %zu steps (v0->0.99vm at a0: %.4f s), decelerating %.4f s over %zu "
      "steps "
      "(0.99vm->ve at ae: %.4f s)\n",
      t_acc, i_up + 1, w_acc, t_dec, iv.size() - i_down, w_dec);
  std::printf("info: ratio accel/decel time %.3f (planned %.3f; ae/a0 = %.1f, (vm-v0)/(vm-ve) = %.2f)\n",
              t_acc / t_dec, w_acc / w_dec, ae / a0, (vm - v0) / (vm - ve));
  CheckTiming(Near(t_acc, w_acc, 0.02),
              F("acceleration phase %.4f s = (0.99vm - v0)/a0 = %.4f s +-2%%", t_acc, w_acc));
  CheckTiming(Near(t_dec, w_dec, 0.02),
              F("deceleration phase %.4f s = (0.99vm - ve)/ae = %.4f s +-2%%", t_dec, w_dec));
  CheckTiming(
      t_acc > t_dec && Near(t_acc / t_dec, w_acc / w_dec, 0.03),
      F("accel/decel time ratio %.3f = %.3f +-3%% (ae/a0 %.0f times (vm-v0)/(vm-ve); full ramps: %.3f)",
        t_acc / t_dec, w_acc / w_dec, ae / a0, full_ratio));
  const double total = double(e.back().t - e.front().t) / 1e9;
  const double w_total =
      (steps - 1) / vm + (vm - v0) * (vm - v0) / (2 * a0 * vm) + (vm - ve) * (vm - ve) / (2 * ae * vm);
  CheckTiming(Near(total, w_total, 0.002),
              F("first to last step %.5f s (profile: %.5f s +-0.2%%)", total, w_total));
  ctl->set_profile(x4step::axis{1}, kFast);
}

// ---- 3. limit switches -----------------------------------------------------

void ExpectLimit(int axis, const std::string &what, long long at, unsigned err, bool allow_next = true) {
  const x4step::axis_status a = ctl->get_axis(x4step::axis{axis});
  const long long m = Machine()[axis - 1];
  const long long step = (err & axerr::limit_pos) ? 1 : -1;
  const bool at_switch = m == at || (allow_next && m == at + step);
  Check(!a.running && a.error == err && at_switch && m - a.position == off[axis - 1] && !a.synced,
        F("%s: axis %d stopped at machine %lld (switch at %lld), module %ld, err 0x%x (want 0x%x), %s",
          what.c_str(), axis, m, at, a.position, a.error, err, a.synced ? "still synced" : "sync cleared"));
}

// Off the limits without them (after a failed back-off), then rearm.
void Recover(const x4step::switches &sw) {
  ctl->set_switches(x4step::switches{});
  MachineTo(1, 0);
  MachineTo(2, 0);
  ctl->set_switches(sw);
  std::printf("info: recovered: limits off, axes 1 and 2 to 0, limits on again\n");
}

void TestLimits() {
  std::printf("== limit switches\n");
  for (int a = 1; a <= 4; a++) ctl->set_profile(x4step::axis{a}, kFast);
  MachineTo(1, 0);
  MachineTo(2, 0);
  Align();
  Check(ctl->get_axis(x4step::axis{1}).synced && ctl->get_axis(x4step::axis{1}).position == 0,
        "set_position: coordinate set, axis synchronized");

  // Normally open, E+ above 1000 and E- below -1000, hysteresis 20.
  Switches("add 1 0 above 1000 20 no;add 1 1 below -1000 20 no");
  x4step::switches sw;
  sw.plus[0] = 1;
  sw.minus[0] = 2;
  ctl->set_switches(sw);
  const x4step::switches rb = ctl->get_switches();
  Check(rb.plus[0] == 1 && rb.minus[0] == 2 && rb.nc == 0, "switches read back");
  Check((A().switches_active & 3) == 0,
        F("NO: E+ and E- (inputs 1, 2) inactive at 0 (active 0x%x)", A().switches_active));
  ctl->move_to(x4step::axis{1}, 3000);
  Wait(0x1, "goto 3000 into E+");
  ExpectLimit(1, "NO: goto 3000 beyond E+", 1000, axerr::limit_pos);
  Check(A().switches_active & 1, F("E+ (input 1) active (0x%x)", A().switches_active));
  const long long stopped = Machine()[0];
  ctl->move_to(x4step::axis{1}, 2000);
  Wait(0x1, "goto toward the active E+");
  ExpectLimit(1, "NO: goto toward the active E+ makes no step", stopped, axerr::limit_pos, false);
  ctl->move_to(x4step::axis{1}, 0);
  Wait(0x1, "back off E+");
  x4step::axis_status a = ctl->get_axis(x4step::axis{1});
  Check(a.position == 0 && Machine()[0] == 0 && a.error == 0 && (A().switches_active & 1) == 0,
        "NO: backing off E+ to 0: " + Flags(a));
  ctl->move_to(x4step::axis{1}, -3000);
  Wait(0x1, "goto -3000 into E-");
  ExpectLimit(1, "NO: goto -3000 beyond E-", -1000, axerr::limit_neg);
  ctl->move_to(x4step::axis{1}, 0);
  Wait(0x1, "back off E-");
  a = ctl->get_axis(x4step::axis{1});
  Check(a.position == 0 && Machine()[0] == 0 && a.error == 0, "NO: backing off E- to 0: " + Flags(a));

  // Normally closed, the same places.
  Switches("add 1 0 above 1000 20 nc;add 1 1 below -1000 20 nc");
  sw.nc = 0x3;
  ctl->set_switches(sw);
  x4step::axes_status s = A();
  Check((s.inputs & 3) == 3 && (s.switches_active & 3) == 0,
        F("NC: pins 1, 2 high at rest, E+ and E- inactive (inputs 0x%x, active 0x%x)", s.inputs,
          s.switches_active));
  ctl->move_to(x4step::axis{1}, 3000);
  Wait(0x1, "NC goto 3000");
  ExpectLimit(1, "NC: goto 3000 beyond E+", 1000, axerr::limit_pos);
  s = A();
  Check((s.inputs & 1) == 0 && (s.switches_active & 1),
        F("NC: E+ pin low, active (inputs 0x%x, active 0x%x)", s.inputs, s.switches_active));
  ctl->move_to(x4step::axis{1}, -3000);
  Wait(0x1, "NC goto -3000");
  ExpectLimit(1, "NC: from E+ back past 0 to E-", -1000, axerr::limit_neg);
  MachineTo(1, 0);
  // NC switches taken for NO: both read active at rest, nothing moves.
  sw.nc = 0;
  ctl->set_switches(sw);
  ctl->move_to(x4step::axis{1}, 500);
  Wait(0x1, "NC switches wired as NO");
  ExpectLimit(1, "NC switches configured as NO: E+ reads active at rest, goto +500", 0, axerr::limit_pos,
              false);
  sw.nc = 0x3;
  ctl->set_switches(sw);

  // An interpolated move of axes 1+2 toward axis 1's E+: both stop there.
  Switches("add 1 0 above 1000 20 no;add 1 1 below -1000 20 no");
  sw.nc = 0;
  ctl->set_switches(sw);
  ctl->zero(x4step::axis{2});
  ctl->load({{3000, 1500, 0, 0}, 3000, 20ms});
  ctl->start();
  Wait(0x3, "interpolated move into E+");
  s = A();
  const Pos4 m = Machine();
  ExpectLimit(1, "interpolated 1+2 (3000, 1500) into axis 1's E+", 1000, axerr::limit_pos);
  Check(!s.axis[1].running && std::llabs(m[1] - m[0] / 2) <= 1 && m[1] == s.axis[1].position &&
            s.axis[1].error == 0 && !s.axis[1].synced,
        F("its partner axis 2 stopped with it at machine %lld (on the line: %lld), module %ld, err 0x%x, %s",
          m[1], m[0] / 2, s.axis[1].position, s.axis[1].error, s.axis[1].synced ? "synced" : "sync cleared"));
  Check(!ctl->active(), "no move runs after the limit");
  MachineTo(1, 0);
  MachineTo(2, 0);

  // SMC1500: every limit of axes 1 and 2 in parallel on input 3.
  Switches(
      "add 1 2 above 1000 20 no;add 1 2 below -1000 20 no;add 2 2 above 1000 20 no;add 2 2 below -1000 20 "
      "no");
  x4step::switches shared;
  shared.plus = {3, 3, 0, 0};
  shared.minus = {3, 3, 0, 0};
  ctl->set_switches(shared);
  ctl->move_to(x4step::axis{1}, 3000);
  Wait(0x1, "shared: axis 1 +");
  ExpectLimit(1, "shared input: axis 1 alone into its E+, hit attributed to it", 1000, axerr::limit_pos);
  Check(ctl->get_axis(x4step::axis{2}).error == 0,
        F("shared input: idle axis 2 not blamed (err 0x%x)", ctl->get_axis(x4step::axis{2}).error));
  ctl->move_to(x4step::axis{1}, 0);
  Wait(0x1, "shared: axis 1 backs off");
  a = ctl->get_axis(x4step::axis{1});
  Check(a.position == 0 && Machine()[0] == 0 && a.error == 0,
        "shared input: goto backs axis 1 off E+ although its E- is the same active input: " + Flags(a));
  if (Machine()[0] != 0) {
    // Still on the switch (and its error now says E-): an X4 move further
    // into E+ must still be refused.
    ClearTrace();
    ctl->load({{200, 0, 0, 0}, 2000, 0ms});
    ctl->start();
    Wait(0x1, "X4 move further into E+");
    a = ctl->get_axis(x4step::axis{1});
    Check(
        Machine()[0] == 1000 && Edges()[0].empty(),
        F("after the refused back-off: an X4 move of +200 further into the active E+ makes no step (machine "
          "%lld, %zu steps, %s)",
          Machine()[0], Edges()[0].size(), Flags(a).c_str()));
    Recover(shared);
  }
  // Backing off with an X4 move.
  ctl->move_to(x4step::axis{1}, 3000);
  Wait(0x1, "shared: axis 1 + again");
  ExpectLimit(1, "shared input: axis 1 into its E+ again", 1000, axerr::limit_pos);
  ctl->load({{-1000, 0, 0, 0}, 3000, 20ms});
  ctl->start();
  Wait(0x1, "shared: X4 back-off");
  a = ctl->get_axis(x4step::axis{1});
  Check(Machine()[0] == 0 && a.position == 0 && a.error == 0,
        "shared input: an X4 move (-1000) backs axis 1 off E+: machine " + std::to_string(Machine()[0]) +
            ", " + Flags(a));
  if (Machine()[0] != 0) Recover(shared);
  ctl->move_to(x4step::axis{2}, -3000);
  Wait(0x2, "shared: axis 2 -");
  ExpectLimit(2, "shared input: axis 2 alone into its E-", -1000, axerr::limit_neg);
  Check(ctl->get_axis(x4step::axis{1}).error == 0,
        F("shared input: idle axis 1 not blamed (err 0x%x)", ctl->get_axis(x4step::axis{1}).error));
  ctl->move_to(x4step::axis{2}, 0);
  Wait(0x2, "shared: axis 2 backs off");
  a = ctl->get_axis(x4step::axis{2});
  Check(a.position == 0 && Machine()[1] == 0 && a.error == 0,
        "shared input: goto backs axis 2 off E- although its E+ is the same active input: " + Flags(a));
  if (Machine()[1] != 0) Recover(shared);
  // Both moving toward the shared input: axis 1 (faster) reaches its E+ first.
  ctl->set_profile(x4step::axis{2}, x4step::profile{}.top_speed(1500).accel(30000).decel(30000));
  ctl->move_to(x4step::axis_set{0x3u}, {3000, -3000, 0, 0});
  Wait(0x3, "shared: axes 1 and 2");
  s = A();
  const Pos4 m2 = Machine();
  ExpectLimit(1, "shared input, axes 1 (+) and 2 (-) moving", 1000, axerr::limit_pos | axerr::ambiguous);
  Check(!s.axis[1].running && s.axis[1].error == (axerr::limit_neg | axerr::ambiguous) && m2[1] > -1000 &&
            m2[1] < 0 && m2[1] == s.axis[1].position,
        F("shared input: axis 2 stopped too at machine %lld (its E- at -1000 not reached), module %ld, err "
          "0x%x "
          "(want E- | ambiguous 0x%x)",
          m2[1], s.axis[1].position, s.axis[1].error, axerr::limit_neg | axerr::ambiguous));
  ctl->set_profile(x4step::axis{2}, kFast);
  ctl->move_to(x4step::axis_set{0x3u}, {0, 0, 0, 0});
  Wait(0x3, "shared: both back");
  s = A();
  Check(s.axis[0].position == 0 && s.axis[1].position == 0 && s.axis[0].error == 0 && s.axis[1].error == 0,
        "shared input: goto backs both off to 0: " + Flags(s.axis[0]) + "; " + Flags(s.axis[1]));
  if (s.axis[0].position != 0 || s.axis[1].position != 0) Recover(shared);
  Coords("after the limit tests");
  ctl->set_switches(x4step::switches{});
  Switches("");
}

// ---- 4. homing -------------------------------------------------------------

struct HomeRun {
  bool ref1 = false, ref2 = false;
  x4step::axis_status end;
  long long machine = 0;
};

// A reference run of axis 3; if `halt_after` > 0, halt it then with `how`.
HomeRun Home(const x4step::homing &h, std::chrono::milliseconds halt_after = 0ms,
             x4step::halt_mode how = x4step::halt_mode::stop) {
  HomeRun r;
  const errc err = Throws([&] { ctl->home(x4step::axis{3}, h); });
  if (err != errc::ok) {
    Check(false, F("home(3) accepted (errc %d)", int(err)));
    return r;
  }
  const auto t0 = std::chrono::steady_clock::now();
  bool halted = false;
  for (;;) {
    const x4step::axis_status a = ctl->get_axis(x4step::axis{3});
    r.ref1 |= a.ref1;
    r.ref2 |= a.ref2;
    if (!a.running) break;
    if (halt_after > 0ms && !halted && std::chrono::steady_clock::now() - t0 >= halt_after) {
      ctl->halt(x4step::axis_set{0x4u}, how);
      halted = true;
    }
    if (std::chrono::steady_clock::now() - t0 > 20s) break;
    std::this_thread::sleep_for(2ms);
  }
  Wait(0x4, "reference run");
  r.end = ctl->get_axis(x4step::axis{3});
  r.machine = Machine()[2];
  return r;
}

void TestHoming() {
  std::printf("== homing\n");
  ctl->set_profile(x4step::axis{3}, kFast);
  Align();
  x4step::switches sw;
  sw.ref[2] = 4;  // input 4, X4GetIn bit 3
  ctl->set_switches(sw);
  Check(Throws([] { ctl->home(x4step::axis{4}, x4step::homing{}); }) == errc::param_fail,
        "home of an axis without REF refused");

  // vref1 negative, vref2 positive: REF below -700, hysteresis 25.
  Switches("add 3 3 below -700 25 no");
  MachineTo(3, 0);
  HomeRun r = Home(x4step::homing{}.phase1_speed(-2000).phase2_speed(500).max_travel(5000));
  Check(r.ref1 && r.ref2, F("auto (-2000, +500): state showed phase 1 %d and phase 2 %d", r.ref1, r.ref2));
  Check(
      r.end.position == 0 && r.end.synced && r.end.error == 0 && !r.end.running && r.machine == -674,
      F("auto (-2000, +500): coordinate 0 at the REF release point: machine %lld (want -674: REF at <= -700, "
        "released past -700 + 25), %s",
        r.machine, Flags(r.end).c_str()));
  off[2] = r.machine - r.end.position;
  ctl->move_to(x4step::axis{3}, 100);
  Wait(0x4, "after homing");
  Coords("after homing, goto 100");

  // The opposite direction: REF above 700.
  Switches("add 3 3 above 700 25 no");
  r = Home(x4step::homing{}.phase1_speed(2000).phase2_speed(-500).max_travel(5000));
  Check(r.end.position == 0 && r.end.synced && r.end.error == 0 && r.machine == 674 && r.ref1 && r.ref2,
        F("auto (+2000, -500): coordinate 0 at machine %lld (want 674: REF at >= 700, released below 700 - "
          "25), %s",
          r.machine, Flags(r.end).c_str()));
  off[2] = r.machine - r.end.position;

  // Phase 2 in phase 1's direction, through a REF cam between -800 and
  // -600: two NC switches in parallel, read as NO, are active only between.
  Switches("add 3 3 below -800 0 nc;add 3 3 above -600 0 nc");
  Check((A().switches_active & 8) == 0, "REF cam inactive at machine 674");
  r = Home(x4step::homing{}.phase1_speed(-2000).phase2_speed(-500).max_travel(5000));
  Check(
      r.end.position == 0 && r.end.synced && r.end.error == 0 && r.machine == -800 && r.ref1 && r.ref2,
      F("auto (-2000, -500) through a cam: coordinate 0 at machine %lld (want -800, the cam's far edge), %s",
        r.machine, Flags(r.end).c_str()));
  off[2] = r.machine - r.end.position;

  // Phase 1 alone, then phase 2 alone.
  Switches("add 3 3 below -700 25 no");
  MachineTo(3, 0);
  r = Home(x4step::homing{}.phase1_speed(-2000).phase2_speed(500).max_travel(5000).phase2(false));
  Check(r.ref1 && !r.ref2 && !r.end.synced && r.end.error == 0 && r.machine == -700 &&
            r.machine - r.end.position == off[2],
        F("phase 1 alone: stops where REF becomes active, machine %lld (want -700), coordinate kept (module "
          "%ld), %s",
          r.machine, r.end.position, Flags(r.end).c_str()));
  r = Home(x4step::homing{}.phase1_speed(-2000).phase2_speed(500).max_travel(5000).phase1(false));
  Check(r.ref2 && !r.ref1 && r.end.synced && r.end.position == 0 && r.machine == -674,
        F("phase 2 alone: coordinate 0 at machine %lld (want -674), %s", r.machine, Flags(r.end).c_str()));
  off[2] = r.machine - r.end.position;
  // With the brake: on past REF along the profile's ae, the step at which
  // it sees REF and ceil(2000^2 / 2 ae) more.
  const long long brake = 1 + (2000LL * 2000 + 2LL * kFast.decel() - 1) / (2LL * kFast.decel());
  MachineTo(3, 0);
  r = Home(x4step::homing{}.phase1_speed(-2000).phase2_speed(500).max_travel(5000).phase2(false).brake(true));
  Check(r.ref1 && !r.end.synced && r.end.error == 0 && r.machine == -700 - brake,
        F("phase 1 alone, --brake: machine %lld (want %lld), %s", r.machine, -700 - brake,
          Flags(r.end).c_str()));
  r = Home(x4step::homing{}.phase1_speed(-2000).phase2_speed(500).max_travel(5000).phase1(
      false));  // synchronized again
  Check(r.end.synced && r.machine == -674, F("phase 2 after the brake: machine %lld (want -674)", r.machine));
  off[2] = r.machine - r.end.position;

  // Halted during a reference run: not synchronized.
  MachineTo(3, 0);
  Check(ctl->get_axis(x4step::axis{3}).synced, "axis 3 synced before the halted runs");
  r = Home(x4step::homing{}.phase1_speed(-1000).phase2_speed(500).max_travel(5000), 200ms,
           x4step::halt_mode::stop);
  Check(!r.end.synced && !r.end.running && r.machine < 0 && r.machine > -700 &&
            r.machine - r.end.position == off[2],
        F("reference run stopped (halt stop) in phase 1: machine %lld, %s, coordinate kept", r.machine,
          Flags(r.end).c_str()));
  ctl->zero(x4step::axis{3});
  off[2] = Machine()[2];
  r = Home(x4step::homing{}.phase1_speed(-1000).phase2_speed(500).max_travel(5000), 200ms,
           x4step::halt_mode::brake);
  Check(!r.end.synced && !r.end.running && r.machine - r.end.position == off[2],
        F("reference run braked (halt brake) in phase 1: machine %lld, %s", r.machine, Flags(r.end).c_str()));

  // sref exceeded.
  MachineTo(3, 0);
  ctl->zero(x4step::axis{3});
  off[2] = Machine()[2];
  r = Home(x4step::homing{}.phase1_speed(-2000).phase2_speed(500).max_travel(300));
  Check(r.end.error == axerr::ref_travel && !r.end.synced && r.machine == -300 && r.end.position == -300,
        F("sref 300 exceeded in phase 1: machine %lld (want -300), %s (want err ref_travel 0x%x)", r.machine,
          Flags(r.end).c_str(), axerr::ref_travel));
  MachineTo(3, -1500);
  r = Home(x4step::homing{}.phase1_speed(-2000).phase2_speed(1000).max_travel(300).phase1(false));
  Check(r.end.error == axerr::ref_travel && !r.end.synced && r.machine == -1200,
        F("sref 300 exceeded in phase 2 (REF still active): machine %lld (want -1200), %s", r.machine,
          Flags(r.end).c_str()));
  Coords("after the reference runs");
  ctl->set_switches(x4step::switches{});
  Switches("");
}

// ---- 5. synchronization ------------------------------------------------------

void TestSync() {
  std::printf("== synchronization\n");
  ctl->set_profile(x4step::axis{4}, kFast);
  ctl->set_profile(x4step::axis{3}, kFast);
  auto zero = [](int axis) {
    ctl->zero(x4step::axis{axis});
    off[axis - 1] = Machine()[axis - 1];
  };
  auto run = [&](const std::string &what, const std::function<void()> &halt, bool want_sync) {
    zero(3);
    zero(4);
    ctl->move_by(x4step::axis{4}, 3000);
    std::this_thread::sleep_for(300ms);
    const bool ran = ctl->get_axis(x4step::axis{4}).running;
    halt();
    Wait(0x8, what);
    const x4step::axis_status a = ctl->get_axis(x4step::axis{4});
    const long long m = Machine()[3] - off[3];
    Check(
        ran && !a.running && a.synced == want_sync && a.position == m && a.position > 0 && a.position < 3000,
        F("%s during a goto: %s (want %s), stopped at %ld of 3000, machine agrees (%lld)", what.c_str(),
          a.synced ? "synced" : "not synced", want_sync ? "synced" : "not synced", a.position, m));
    Check(ctl->get_axis(x4step::axis{3}).synced, what + ": idle axis 3 keeps its sync");
  };
  zero(4);
  x4step::axis_status a = ctl->get_axis(x4step::axis{4});
  Check(a.synced && a.position == 0, "zero(): coordinate 0, synced: " + Flags(a));
  run(
      "controller::stop() (X4Stop)", [] { ctl->stop(); }, false);
  run(
      "controller::brake() (X4Brake)", [] { ctl->brake(); }, true);
  run(
      "halt(stop)", [] { ctl->halt(x4step::axis_set{0x8u}, x4step::halt_mode::stop); }, false);
  run(
      "halt(brake)", [] { ctl->halt(x4step::axis_set{0x8u}, x4step::halt_mode::brake); }, true);
  // X4Stop of an interpolated move.
  zero(4);
  ctl->load({{0, 0, 0, 3000}, 3000, 20ms});
  ctl->start();
  std::this_thread::sleep_for(300ms);
  ctl->stop();
  Wait(0x8, "interpolated move stopped");
  a = ctl->get_axis(x4step::axis{4});
  Check(!a.synced, "X4Stop of an interpolated move clears its axis' sync: " + Flags(a));
  Coords("after the sync tests");
}

// ---- outside observer: QEMU's parport --------------------------------------

void TestOutside() {
  std::printf("== coordinates against QEMU's port trace\n");
  x4step::controller c0("/dev/x4step0");
  for (int a = 1; a <= 4; a++) c0.set_profile(x4step::axis{a}, kFast);
  long last[4] = {};
  auto seg = [&](const std::string &what) {
    const x4step::axes_status s = c0.get_axes();
    long d[4];
    for (int i = 0; i < 4; i++) {
      d[i] = s.axis[i].position - last[i];
      last[i] = s.axis[i].position;
    }
    std::printf("SEG %ld %ld %ld %ld\n", d[0], d[1], d[2], d[3]);
    std::printf("info: %s: coordinates %s\n", what.c_str(), Mod(s).c_str());
  };
  const x4step::axes_status s0 = c0.get_axes();
  for (int i = 0; i < 4; i++) last[i] = s0.axis[i].position;
  std::printf("COORD0 %s\n", Mod(s0).c_str());
  c0.move_to(x4step::axis{1}, 1200);
  c0.wait_axes(x4step::axis_set{0xfu}, 10s);
  seg("goto 1 1200");
  c0.move_to(x4step::axis{2}, -700);
  c0.wait_axes(x4step::axis_set{0xfu}, 10s);
  seg("goto 2 -700");
  c0.move_by(x4step::axis{1}, -2000);
  c0.wait_axes(x4step::axis_set{0xfu}, 10s);
  seg("goto 1 by -2000");
  c0.load({{300, -200, 100, 50}, 2000, 20ms});
  c0.start();
  c0.wait_axes(x4step::axis_set{0xfu}, 10s);
  seg("interpolated (300, -200, 100, 50)");
  const x4step::axes_status s = c0.get_axes();
  Check(s.axis[0].position == s0.axis[0].position - 500 && s.axis[1].position == s0.axis[1].position - 900 &&
            s.axis[2].position == s0.axis[2].position + 100 && s.axis[3].position == s0.axis[3].position + 50,
        "parport0: coordinates moved by (-500, -900, 100, 50): " + Mod(s0) + " -> " + Mod(s));
  std::printf("COORD %s\n", Mod(s).c_str());
}

}  // namespace

int main(int argc, char **argv) {
  setvbuf(stdout, nullptr, _IOLBF, 0);
  if (!guest::TimingArgs(argc, argv, "positioning_test")) return 2;
  const int port = guest::VportNumber();
  if (port < 0) return guest::Finish("positioning_test");
  const std::string dev = "/dev/x4step" + std::to_string(port);
  try {
    x4step::controller c(dev);
    ctl = &c;
    TestCoordinates();
    TestProfile();
    TestLimits();
    TestHoming();
    TestSync();
  } catch (const std::exception &e) {
    Check(false, std::string("unexpected exception: ") + e.what());
  }
  try {
    TestOutside();
  } catch (const std::exception &e) {
    Check(false, std::string("unexpected exception (parport0): ") + e.what());
  }
  return guest::Finish("positioning_test");
}
