// SPDX-License-Identifier: GPL-2.0
// What the guest benchmarks share (timing_bench.cpp, speed_bench.cpp):
// a spinner that measures the CPU left to user space, and
// percentiles of the step timer's lateness (X4STEP_GET_TIMING).
#pragma once

#include <linux/x4step.h>

#include <cstdint>

#include "check.hpp"

namespace guest {

// Loops of a user-space spinner in `ns` of guest time: what the CPU has
// left for everything but the step timer.
inline uint64_t Spin(uint64_t ns) {
  volatile uint64_t n = 0;
  const uint64_t end = NowNs() + ns;
  while (NowNs() < end) n = n + 1;
  return n;
}

// The lateness below which `permille` of the timer's events came, to the
// histogram's bucket (the largest lateness if the histogram ends first).
inline uint64_t Percentile(const x4step_timing &t, unsigned permille) {
  const uint64_t want = (t.events * permille + 999) / 1000;
  uint64_t seen = 0;
  for (int i = 0; i < X4STEP_TIMING_BUCKETS; i++) {
    seen += t.hist[i];
    if (seen >= want) return uint64_t(i + 1) * X4STEP_TIMING_BUCKET_NS;
  }
  return t.late_max_ns;
}

}  // namespace guest
