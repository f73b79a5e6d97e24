// SPDX-License-Identifier: LGPL-2.1-or-later
// In-guest test of the SMC1500 phase drive and the step timing settings
// through the C++ API. The host (check-phase.sh) compares the data bytes
// QEMU saw with the PHASE line printed here.
#include <cstdio>
#include <string>

#include "check.hpp"
#include "x4step.hpp"

using namespace std::chrono_literals;

namespace {

using guest::Check;
using guest::Throws;

}  // namespace

int main() {
  setvbuf(stdout, nullptr, _IOLBF, 0);
  using x4step::errc;
  x4step::controller c(1);

  // Step timing: set, read back, refuse what cannot fit or is out of range.
  x4step::step_timing t;
  t.pulse(5us);
  t.space(3us);
  t.dir_setup(20us);
  t.dir_hold(40us);
  c.set_step_timing(t);
  const x4step::step_timing back = c.get_step_timing();
  Check(back.pulse() == 5us && back.space() == 3us && back.dir_setup() == 20us && back.dir_hold() == 40us,
        "step timing reads back");
  x4step::step_timing slow;
  slow.pulse(60us);
  slow.space(50us);
  c.set_step_timing(slow);
  Check(Throws([&] {
          c.load({{10, 0, 0, 0}, 10000, 0ms});
        }) == errc::freq_too_high,
        "10 kHz refused with 60 us pulses and 50 us space");
  x4step::step_timing bad;
  bad.pulse(999ns);
  Check(Throws([&] { c.set_step_timing(bad); }) == errc::param_fail, "pulse under 1 us refused");
  bad.pulse(2ms);
  Check(Throws([&] { c.set_step_timing(bad); }) == errc::param_fail, "pulse over 1 ms refused");
  c.set_step_timing(x4step::step_timing{});

  // Phase drive: X +3, Y -2 interpolated, motors off at rest.
  x4step::config cfg = c.get_config();
  cfg.mode(x4step::output_mode::smc_phase);
  c.set_config(cfg);
  Check(c.get_config().mode() == x4step::output_mode::smc_phase, "phase mode reads back");
  Check(Throws([&] { c.load({{1, 0, 0, 1}, 1000, 0ms}); }) == errc::param_fail, "no fourth motor");
  c.load({{3, -2, 0, 0}, 1000, 0ms});
  c.start();
  Check(c.wait(5s), "phase move ends");
  // Rest after the mode change, energize, steps, rest again.
  std::printf("PHASE 1b 5b 9b 03 43 09 4d 38 29 5c 1b 5b 9b\n");
  cfg.mode(x4step::output_mode::clock_dir);
  c.set_config(cfg);
  return guest::Finish("phase_test");
}
