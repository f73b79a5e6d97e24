// SPDX-License-Identifier: LGPL-2.1-or-later
// In-guest test of the C++ API against the module.
#include <cstdio>
#include <string>
#include <thread>
#include <utility>

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
  {
    x4step::controller c(1);
    Check(static_cast<bool>(c) && c.path() == "/dev/x4step0", "controller on LPT1");
    Check(Throws([] { x4step::controller second(1); }) == errc::lpt_not_found, "second controller refused");
    x4step::monitor mon(1);
    Check(mon.get_status().controlled, "monitor sees the controller");

    c.load({{300, -200, 100, 0}, 2000, 20ms});
    Check(Throws([&] { c.load({{1, 0, 0, 0}, 2000, 20ms}); }) == errc::is_loaded, "second load: is_loaded");
    Check(Throws([&] {
            c.load({{1, 0, 0, 0}, 30000, 20ms});
          }) == errc::freq_too_high,
          "bad load: freq_too_high");
    c.start();
    Check(!mon.wait(0ms), "monitor: move running");
    Check(c.wait(5s) && mon.wait(0ms), "wait for the end with poll");
    const x4step::status st = c.get_status();
    Check(st.steps[0] == 300 && st.steps[1] == -200 && st.steps[2] == 100 && !st.active,
          "steps after the move");
    std::printf("SEG 300 -200 100 0\n");
    Check(Throws([&] { c.brake(); }) == errc::not_active, "brake idle: not_active");
    Check(Throws([&] { c.start(); }) == errc::not_loaded, "start: not_loaded");

    c.set_output(x4step::signal::two, true);
    Check((c.get_status().outputs & 2) == 2, "signal 2 on");
    c.set_output(x4step::signal::two, false);

    x4step::controller moved = std::move(c);
    Check(!c && static_cast<bool>(moved), "controller moves");
    Check(Throws([&] { c.start(); }) == errc::init_not_done, "moved-from controller: init_not_done");
    moved.move_endless(4, x4step::direction::negative, 3000, 30ms);
    Check(moved.active(), "endless move runs");
    std::this_thread::sleep_for(300ms);
  }  // destructor brakes, waits, releases
  {
    x4step::controller again(1);
    Check(!again.active() && again.get_status().steps[3] < -10, "destructor braked the endless move");
  }
  std::printf("SEG 0 0 0 ? braked\n");
  return guest::Finish("cpp_test");
}
