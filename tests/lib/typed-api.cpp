// SPDX-License-Identifier: LGPL-2.1-or-later
// What the C++ API must refuse to compile, for compile-fail.sh: as it is,
// this file compiles; each line marked "bad:" is also compiled with the
// code after the mark in its place, which must not. An integer is never
// an axis or a set of axes, a setting of several numbers is never made by
// position, and each marked line shows the spelling the API wants instead.
#include <x4step.hpp>

using namespace std::chrono_literals;
using x4step::axis;
using x4step::axis_set;

// Each mark must stay on its line.
// clang-format off
void calls(x4step::controller &c, const x4step::monitor &m) {
  const std::array<long, x4step::axes> t{};
  const x4step::profile p;
  const x4step::homing h;
  c.move_to(axis{3}, 100);                    // bad: c.move_to(3u, 100);
  c.move_to(axis::z, 100);                    // bad: c.move_to(3, 100);
  c.move_to(axis::x | axis::y, t);            // bad: c.move_to(0x3u, t);
  c.move_to(axis_set{0x3u}, t, true);         // bad: c.move_to(3, t, true);
  c.move_by(axis::z, 5);                      // bad: c.move_by(3, 5);
  c.halt(axis::x | axis::y, x4step::halt_mode::brake);  // bad: c.halt(0x3u, x4step::halt_mode::brake);
  c.wait_axes(axis::x);                       // bad: c.wait_axes(1);
  m.wait_axes(axis::x, 10ms);                 // bad: m.wait_axes(0x1u, 10ms);
  c.set_profile(axis::x, p);                  // bad: c.set_profile(1, p);
  c.get_profile(axis::x);                     // bad: c.get_profile(1);
  c.home(axis::x, h);                         // bad: c.home(1, h);
  c.set_position(axis::x, 0);                 // bad: c.set_position(1, 0);
  c.zero(axis::x);                            // bad: c.zero(1);
  c.get_axis(axis::x);                        // bad: c.get_axis(1);
  c.steps(axis::x);                           // bad: c.steps(1);
  c.move_endless(axis::x, x4step::direction::positive, 1000, 0ms);  // bad: c.move_endless(1, x4step::direction::positive, 1000, 0ms);
  const x4step::axes_status s = c.get_axes();
  (void)s[axis::x];                           // bad: (void)s[1];
}

void values() {
  const axis a = axis::z;                                // bad: const axis a = 3;
  const axis_set one = axis::x;                          // bad: const axis_set one = 0x1u;
  const axis_set two = a | axis::y;                      // bad: const axis_set two = a | 2u;
  x4step::event e;
  e.axes = two;                                          // bad: e.axes = 0x6u;
  (void)one;
  const auto p = x4step::profile{}.top_speed(5000).accel(20000);  // bad: const x4step::profile p{0, 0, 5000, 20000, 20000};
  const auto h = x4step::homing{}.phase1_speed(-1000);            // bad: const x4step::homing h{-1000, 100};
  const auto t = x4step::step_timing{}.pulse(5us).space(5us);     // bad: const x4step::step_timing t{5us, 5us};
  auto cfg = x4step::config{}.clock_invert(axis::x);              // bad: x4step::config cfg{axis::x, axis::y};
  cfg.dir_invert(axis::y);                                        // bad: cfg.dir_invert(2u);
  (void)p, (void)h, (void)t;
}
// clang-format on
