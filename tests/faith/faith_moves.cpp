// SPDX-License-Identifier: LGPL-2.1-or-later
// The moves of the faithfulness test (tests/faith/README.md): one compact
// run of every feature, through the C++ API, on LPT N (argv[1]). In the
// guest it drives the module on the virtual port x4vport; on the host
// (X4STEP_SIM=1) the simulated port. Both record every pin change; the
// host check compares them edge for edge. It waits for each move to end,
// so the moves' own timing, not the program's, decides the edges.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "x4step.hpp"

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

void run(x4step::controller &c) {
  // A 4-axis interpolated move with ramps, and an output between moves.
  c.load({{1200, -900, 600, 300}, 8000, 50ms});
  c.start();
  c.wait();
  report(c, "interpolated");
  c.set_output(x4step::signal::one, true);
  // An endless move, braked on its way.
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
