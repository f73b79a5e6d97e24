// SPDX-License-Identifier: GPL-2.0
// Test support for the engine core: a double-precision reference of the
// X4Step profile, written from the definitions (not from the engine's
// integer formulas), and a recorder of the engine's event stream.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

extern "C" {
#include "x4_engine.h"
}

// One output event as the tests record them: the pin levels after
// x4_engine_fire(), at the time x4_engine_due() gave before it.
struct x4_event {
  uint64_t t_ns;  // since the engine epoch
  uint8_t data;   // data register after the event
  uint8_t ctl;    // control outputs after the event
};

namespace x4test {

// Ideal time in seconds of leader step n (n = 0 is the first step) of a
// move of `steps` leader steps (0: endless) at freq_hz with ramp_ms ramps.
double ref_step_time(uint64_t steps, int freq_hz, int ramp_ms, uint64_t n);

// Ideal speed in steps/s of the same move at position x (in steps from
// step 0): what a brake at step x starts from.
double ref_speed(uint64_t steps, int freq_hz, int ramp_ms, double x);

struct Edge {
  uint64_t t_ns;
  int bit;     // data bit 0..7 (clock of axis i = 2i + 1)
  bool level;  // new level
};

struct Recording {
  std::vector<x4_event> events;
  // Rising clock edges per axis, and the leader's falling edges.
  std::vector<uint64_t> rises[X4_AXES];
  std::vector<uint64_t> falls[X4_AXES];
  // Data changes of direction bits while the move ran.
  int dir_changes = 0;
};

// An interpolated move of the given paths at freq Hz with ramp ms ramps.
x4_move Move(int32_t s1, int32_t s2, int32_t s3, int32_t s4, int freq, int ramp);

// Fire the pending event at now_ns (0: when due); what it output.
x4_event fire(x4_engine &e, uint64_t now_ns = 0);

// Fire the engine until idle (or max_events), recording what it emits.
// `before_fire`, if set, runs before each event (e.g. to sense inputs).
void record(x4_engine &e, Recording &rec, size_t max_events = SIZE_MAX,
            const std::function<void()> &before_fire = nullptr);

}  // namespace x4test
