// SPDX-License-Identifier: GPL-2.0
// Host tests of the simulated port: reading its recorded pin writes.
#ifndef X4STEP_TESTS_SIM_WRITES_HPP
#define X4STEP_TESTS_SIM_WRITES_HPP

#include <cstdint>
#include <vector>

#include "sim/port.hpp"

/// How many rising edges data bit `bit` makes over the writes w.
inline long rises(const std::vector<x4step::sim::pin_write> &w, int bit) {
  long n = 0;
  std::uint8_t last = 0;
  for (const auto &p : w) {
    n += (p.data & ~last) >> bit & 1;
    last = p.data;
  }
  return n;
}

#endif  // X4STEP_TESTS_SIM_WRITES_HPP
