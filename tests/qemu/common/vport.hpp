// SPDX-License-Identifier: GPL-2.0
// The guest programs' view of the test virtual port tests/qemu/fixtures/x4vport:
// its debugfs files, its trace of clock edges and the x4step device on it.
// Its trace stamps each write with ktime_get_ns(), the clock of NowNs()
// (check.hpp): under -icount, guest time.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "check.hpp"

namespace guest {

inline const std::string kV = "/sys/kernel/debug/x4vport/";

// The clock of each axis in the trace since the last clear: its rising
// and falling edges, and its shortest high and low times.
struct Clock {
  std::vector<uint64_t> rises, falls;
  uint64_t min_high = UINT64_MAX, min_low = UINT64_MAX;
};

inline std::array<Clock, 4> Clocks() {
  std::array<Clock, 4> c;
  std::array<uint64_t, 4> last{};
  std::istringstream in(Slurp(kV + "trace"));
  unsigned long long t;
  char reg;
  std::string val;
  unsigned prev = 0;
  while (in >> t >> reg >> val) {
    if (reg != 'd') continue;
    const unsigned v = std::strtoul(val.c_str(), nullptr, 16);
    for (int a = 0; a < 4; a++) {
      const unsigned clk = 2u << (2 * a);
      if ((v ^ prev) & clk) {
        if (v & clk) {
          if (!c[a].rises.empty()) c[a].min_low = std::min<uint64_t>(c[a].min_low, t - last[a]);
          c[a].rises.push_back(t);
        } else {
          c[a].min_high = std::min<uint64_t>(c[a].min_high, t - last[a]);
          c[a].falls.push_back(t);
        }
        last[a] = t;
      }
    }
    prev = v;
  }
  return c;
}

// x4vport's parportN: N, or -1 (after a FAIL line) if it is not loaded.
inline int VportNumber() {
  const std::string port = Slurp(kV + "port");
  if (port.empty()) {
    Check(false, "x4vport loaded (" + kV + "port)");
    return -1;
  }
  return std::atoi(port.c_str());
}

}  // namespace guest
