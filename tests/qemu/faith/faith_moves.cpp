// SPDX-License-Identifier: LGPL-2.1-or-later
// The moves of the faithfulness test (tests/qemu/faith/README.md): one compact
// run of every feature, through the C++ API, on LPT N (argv[1]). In the
// guest it drives the module on the virtual port x4vport; on the host
// (X4STEP_SIM=1) the simulated port. Both record every pin change; the
// host check compares them edge for edge. It waits for each move to end,
// so the moves' own timing, not the program's, decides the edges.
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <stdexcept>
#include <utility>
#include <vector>

#include "x4step.hpp"
#include "x4step_path.hpp"

using namespace std::chrono_literals;
using x4step::axis;

namespace {

// What the module says after a stage: the check compares these lines too.
void report(const x4step::controller &c, const char *stage) {
  const x4step::axes_status a = c.get_axes();
  std::printf("FAITH %s:", stage);
  for (const x4step::axis_status &s : a.axis) std::printf(" %ld/%u/%d", s.position, s.error, s.synced);
  std::printf(" steps %lld %lld %lld %lld\n", c.steps(axis(1)), c.steps(axis(2)), c.steps(axis(3)),
              c.steps(axis(4)));
}

// The path: 2 to 4 axes a segment, each axis leading somewhere, corners
// at their junction speeds and one reversal (an exact stop). The two slow
// segments are where the program changes the override and holds: it
// polls until the one before them is done, well within their first step
// interval (3 ms), so both cut the path at the same step on the module
// and on the simulator; their own timing then is the path's.
constexpr std::uint32_t feed = 16000, accel = 400000, slow = 300;  // path units: steps
constexpr double deviation = 10;                      // steps: small enough that corners set speeds
constexpr std::size_t override_at = 4, hold_at = 11;  // indices of the slow segments
const std::array<std::array<long, x4step::axes>, 16> shape = {{
    {120, 40, 0, 0},
    {100, 80, 20, 0},
    {30, 110, 45, 0},
    {-20, 90, 75, 30},
    {3, 2, 6, 0},  // slow: the override changes here
    {15, 30, 120, 60},
    {-60, 10, 100, 110},
    {-100, -30, 40, 80},
    {-120, -70, 0, 20},
    {-45, -115, -30, 0},
    {0, -80, -90, -35},
    {0, -2, -6, -3},  // slow: the path holds here
    {20, -40, -110, -75},
    {80, 0, -60, -100},
    {110, 45, 0, -70},
    {60, 100, 30, -20},
}};

// Segments along `steps`, each entered at its corner's junction speed.
class path_builder {
 public:
  void add(const std::array<long, x4step::axes> &steps, std::uint32_t speed) {
    std::array<double, x4step::axes> dir{};
    double len2 = 0;
    x4step::segment s;
    for (int i = 0; i < x4step::axes; i++) {
      s.steps(axis(i + 1), steps[i]);
      dir[i] = static_cast<double>(steps[i]);
      len2 += dir[i] * dir[i];
    }
    s.length(static_cast<std::uint32_t>(std::lround(std::sqrt(len2)))).top_speed(speed).accel(accel);
    if (any_) s.entry_speed(x4step::junction_speed(last_, dir, accel, deviation));
    last_ = dir;
    any_ = true;
    segs_.push_back(s.tag(++tags_));
  }
  // The segments added since the last take().
  std::vector<x4step::segment> take() { return std::exchange(segs_, {}); }

 private:
  std::vector<x4step::segment> segs_;
  std::array<double, x4step::axes> last_{};
  bool any_ = false;
  std::uint64_t tags_ = 0;
};

// Until the path has completed `n` segments (polled: a wait would wake
// it later on the module than on the simulator).
void poll_done(const x4step::path &p, std::uint64_t n) {
  for (x4step::path_status s = p.status(); s.done < n; s = p.status())
    if (s.state == x4step::path_state::idle)
      throw std::runtime_error("the path stood before its slow segment");
}

void report_path(const x4step::path &p, const char *stage) {
  const x4step::path_status s = p.status();
  std::printf("FAITH %s: done %llu starved %llu override %u\n", stage,
              static_cast<unsigned long long>(s.done), static_cast<unsigned long long>(s.starved),
              s.override_percent);
}

// A path streamed in two writes: the first half runs, changes its override
// in the slow segment and holds in the next; the second half (the first
// retraced) goes in while it is held, at a new override, and it resumes.
// Short direction times: where they hold a path's next step back, the
// module counts the rest of the path from its (late) direction write, a
// lateness the simulator, never late, cannot have (README.md).
void run_path(x4step::controller &c) {
  c.set_step_timing(x4step::step_timing{}.dir_setup(2us).dir_hold(2us));
  x4step::path p(c);
  path_builder b;
  for (std::size_t i = 0; i < shape.size(); i++)
    b.add(shape[i], i == override_at || i == hold_at ? slow : feed);
  const std::uint64_t done0 = p.status().done;
  p.append(b.take());
  poll_done(p, done0 + override_at);
  p.set_override(125);
  poll_done(p, done0 + hold_at);
  p.hold();
  p.wait();
  report(c, "path-held");
  report_path(p, "path-held");
  for (std::size_t i = shape.size(); i-- > 0;)
    if (i != override_at && i != hold_at) {
      std::array<long, x4step::axes> back{};
      for (int a = 0; a < x4step::axes; a++) back[a] = -shape[i][a];
      b.add(back, feed);
    }
  p.append(b.take());
  p.set_override(80);
  p.resume();
  p.wait();
  report(c, "path");
  report_path(p, "path");
  c.set_step_timing(x4step::step_timing{});
}

void run(x4step::controller &c) {
  // A 4-axis interpolated move with ramps, and an output between moves.
  c.load({{1200, -900, 600, 300}, 8000, 50ms});
  c.start();
  c.wait();
  report(c, "interpolated");
  c.set_output(x4step::signal::one, true);
  // An endless move, braked on its way after 60 ms: just after its 120th
  // step (40 ms of ramp to 3000 Hz, then 20 ms at 333 us a step). The
  // simulator brakes there; the module when the program wakes up, later
  // by its wake-up latency, which must stay below the 333 us to the next
  // step. (Polling the step count instead made the guest's ioctls delay
  // the module's timer by up to 2.6 us.)
  c.move_endless(axis(3), x4step::direction::negative, 3000, 40ms);
  c.wait(60ms);
  c.brake();
  c.wait();
  report(c, "endless");
  // Step timing: a set pulse, space and direction setup and hold.
  c.set_step_timing(x4step::step_timing{}.pulse(8us).space(12us).dir_setup(30us).dir_hold(20us));
  c.load({{-400, 250, 0, 0}, 15000, 15ms});
  c.start();
  c.wait();
  report(c, "step-timing");
  c.set_step_timing(x4step::step_timing{});
  // Positioning against the machine's switches (faith.machine).
  x4step::switches sw;
  sw.ref[0] = 4;   // pin 10
  sw.plus[0] = 5;  // pin 11, NC
  sw.minus[0] = 5;
  sw.plus[1] = 3;  // pin 12
  sw.nc = 1u << 4;
  c.set_switches(sw);
  c.home(axis(1), x4step::homing{}.phase1_speed(-3000).phase2_speed(400).max_travel(2000));
  c.wait();
  report(c, "homed");
  c.set_profile(axis(1), x4step::profile{}.start_speed(200).top_speed(6000).accel(60000).decel(40000));
  c.set_profile(axis(2), x4step::profile{}.top_speed(3000).accel(30000).decel(30000));
  c.move_to(axis(1), 700);
  c.wait();
  report(c, "goto");
  c.move_to(axis(1) | axis(2), {2000, 1000, 0, 0});  // both run onto E+
  c.wait();
  report(c, "limits");
  c.move_by(axis(2), -50);
  c.wait();
  report(c, "off-limit");
  c.set_switches(x4step::switches{});
  // The SMC phase drive, then back to step and direction.
  c.set_config(x4step::config{}.mode(x4step::output_mode::smc_phase));
  c.load({{160, 0, 0, 0}, 1000, 20ms});  // one motor: one write per step
  c.start();
  c.wait();
  report(c, "smc-phase");
  c.set_config(x4step::config{});
  c.set_output(x4step::signal::one, false);
  run_path(c);
}

}  // namespace

int main(int argc, char **argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: faith_moves LPT   (1..4; X4STEP_SIM=1: the simulated port)\n");
    return 2;
  }
  try {
    x4step::controller c(std::atoi(argv[1]));
    run(c);
  } catch (const std::exception &e) {
    std::fprintf(stderr, "faith_moves: %s\n", e.what());
    return 1;
  }
  return 0;
}
