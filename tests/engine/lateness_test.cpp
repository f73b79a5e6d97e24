// SPDX-License-Identifier: GPL-2.0
// The engine under a late timer (issue 15): whatever the lateness, no clock
// pulse, space or phase step is shorter than its minimum, measured from the
// times the events really fire; no step is lost or merged; the rest of the
// schedule moves by what was lost and is counted. And the write budget: the
// moves of a port together never need more port writes per second than it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "engine_ref.h"

using namespace x4test;

namespace {

constexpr uint64_t kStart = 1000;

// The timer is stalled over [from, from + len): what is due then fires at its end.
struct Stall {
  uint64_t from, len;
};

// Fire the engine like the module's timer, but late: each event fires at
// its due time, or when the stall that covers it ends, plus up to
// `jitter_ns` of random lateness; never before the event fired before it.
// `before_fire` may start or halt moves at the engine time it is given.
// Each write reaches the port up to `write_ns` after the time fire() was
// given (x4_engine_written()); the events record when it did.
std::vector<x4_event> RunLate(x4_engine &e, const std::vector<Stall> &stalls, uint64_t jitter_ns = 0,
                              const std::function<void(uint64_t)> &before_fire = nullptr,
                              uint64_t write_ns = 0) {
  std::vector<x4_event> out;
  std::mt19937_64 rng(15);
  uint64_t clock = 0;
  while (x4_engine_busy(&e) && out.size() < 10'000'000) {
    uint64_t now = std::max(x4_engine_due(&e), clock);
    for (const Stall &s : stalls)
      if (now >= s.from && now < s.from + s.len) now = s.from + s.len;
    if (jitter_ns) now += rng() % (jitter_ns + 1);
    if (before_fire) before_fire(now);
    if (!x4_engine_busy(&e)) break;
    x4_engine_fire(&e, now);
    if (write_ns) {
      now += rng() % (write_ns + 1);
      x4_engine_written(&e, now);
    }
    out.push_back({now, e.data, e.ctl});
    clock = now;
  }
  return out;
}

// High and low times of axis' clock, from the times the events fired.
struct Pulses {
  std::vector<uint64_t> rises, highs, lows;
};

Pulses PulsesOf(const std::vector<x4_event> &ev, int axis) {
  Pulses p;
  bool high = false;
  uint64_t last = 0;
  for (const x4_event &e : ev) {
    const bool h = e.data & X4_CLK_BIT(axis);
    if (h == high) continue;
    if (h) {
      if (!p.rises.empty()) p.lows.push_back(e.t_ns - last);
      p.rises.push_back(e.t_ns);
    } else {
      p.highs.push_back(e.t_ns - last);
    }
    last = e.t_ns;
    high = h;
  }
  return p;
}

uint64_t Min(const std::vector<uint64_t> &v) {
  return v.empty() ? UINT64_MAX : *std::min_element(v.begin(), v.end());
}

// No high time below `high` and no low time below `low`.
void ExpectMinimums(const Pulses &p, uint64_t high, uint64_t low) {
  EXPECT_GE(Min(p.highs), high);
  EXPECT_GE(Min(p.lows), low);
}

// Stalls of 300 us every few ms from `from` on, as a busy CPU would give.
std::vector<Stall> Stalls(uint64_t from, int count, uint64_t every = 3'100'000, uint64_t len = 300'000) {
  std::vector<Stall> s;
  for (int i = 0; i < count; i++) s.push_back({from + i * every, len});
  return s;
}

x4_profile Prof(uint32_t v0, uint32_t ve, uint32_t vm, uint32_t a0, uint32_t ae) {
  return {v0, ve, vm, a0, ae};
}

struct Eng {
  x4_engine e;
  Eng() { x4_engine_init(&e); }
  void Timing(uint32_t pulse, uint32_t space) {
    const x4_timing t = {pulse, space, X4_DIR_SETUP_NS, 0};
    ASSERT_EQ(x4_engine_configure(&e, &t, X4_MODE_CLOCK_DIR), X4_OK);
  }
  void Start(const x4_move &m) {
    ASSERT_EQ(x4_engine_load(&e, &m), X4_OK);
    ASSERT_EQ(x4_engine_start(&e, kStart), X4_OK);
  }
  void Goto(int axis, int32_t steps, const x4_profile &p, uint64_t now = kStart) {
    int32_t target[X4_AXES] = {};
    target[axis] = steps;
    ASSERT_EQ(x4_engine_set_profile(&e, axis + 1, &p), X4_OK);
    ASSERT_EQ(x4_engine_goto(&e, uint8_t(1u << axis), target, true, now), X4_OK);
  }
};

// ---- a late timer ------------------------------------------------------------

// The example: a tick 300 us late at 20 kHz. Before the fix the
// overdue events fired back to back: pulses and spaces of 0 ns.
TEST(Lateness, A300usStallAt20kHzGivesNoShortPulse) {
  Eng eng;
  const x4_move m = Move(4000, 0, 0, 0, 20000, 50);
  eng.Start(m);
  const auto ev = RunLate(eng.e, Stalls(80'000'000, 20));
  const Pulses p = PulsesOf(ev, 0);
  EXPECT_EQ(p.rises.size(), 4000u);
  ExpectMinimums(p, X4_CLOCK_MIN_NS, X4_CLOCK_MIN_NS);
  EXPECT_GT(eng.e.shifts, 0u);
}

// What is lost is shifted, not caught up: after the last stall every step
// is exactly where the plan had it, moved by the total shift counted.
TEST(Lateness, TheRestOfTheScheduleMovesByTheCountedShift) {
  Eng eng;
  const x4_move m = Move(3000, 1000, 0, 0, 10000, 100);
  eng.Start(m);
  Recording ideal;
  {
    Eng ref;
    ASSERT_EQ(x4_engine_load(&ref.e, &m), X4_OK);
    ASSERT_EQ(x4_engine_start(&ref.e, kStart), X4_OK);
    record(ref.e, ideal);
  }
  const auto ev = RunLate(eng.e, Stalls(60'000'000, 10, 7'000'000, 450'000));
  const Pulses lead = PulsesOf(ev, 0), minor = PulsesOf(ev, 1);
  ASSERT_EQ(lead.rises.size(), 3000u);
  EXPECT_EQ(minor.rises.size(), 1000u);
  ExpectMinimums(lead, X4_CLOCK_MIN_NS, X4_CLOCK_MIN_NS);
  ASSERT_GT(eng.e.shifted_ns, 0u);
  // The last stall ends at 60 ms + 9 * 7 ms + 450 us; 200 steps later all is calm.
  for (size_t n = 2000; n < 3000; n++)
    ASSERT_EQ(lead.rises[n], ideal.rises[0][n] + eng.e.shifted_ns) << "step " << n;
}

// Jitter within the slack of a slow clock is absorbed: nothing shifts, and
// every edge stays within the jitter of its planned time.
TEST(Lateness, JitterWithinTheSlackDoesNotShift) {
  Eng eng;
  const x4_move m = Move(2000, 0, 0, 0, 5000, 100);
  eng.Start(m);
  const auto ev = RunLate(eng.e, {}, 5000);
  EXPECT_EQ(eng.e.shifts, 0u);
  EXPECT_EQ(PulsesOf(ev, 0).rises.size(), 2000u);
}

// At the clock's limit there is no slack: every late edge shifts.
TEST(Lateness, JitterAt20kHzShiftsAndKeeps25us) {
  Eng eng;
  ASSERT_EQ(x4_engine_endless(&eng.e, 2, true, 20000, 20, kStart), X4_OK);
  uint64_t stop_at = 200'000'000;
  const auto ev = RunLate(eng.e, {}, 800, [&](uint64_t now) {
    if (now >= stop_at) {
      x4_engine_brake(&eng.e);
      stop_at = UINT64_MAX;
    }
  });
  const Pulses p = PulsesOf(ev, 1);
  EXPECT_GT(p.rises.size(), 3000u);
  ExpectMinimums(p, X4_CLOCK_MIN_NS, X4_CLOCK_MIN_NS);
  EXPECT_GT(eng.e.shifts, 0u);
}

// The slack of the pending edge (x4_engine_slack()): how late it may fire
// before the rest of the schedule moves. At the X4Step API's top rate,
// 20 kHz with 25 us high and low, there is none; at 19 kHz a fall has
// half of the 2.6 us a step has over 50 us, a rise all of it. The module
// arms its timer early for an edge with less slack than its lateness.
TEST(Lateness, SlackOfThePendingEdge) {
  for (const int hz : {20000, 19000}) {
    Eng eng;
    eng.Start(Move(4000, 0, 0, 0, hz, 50));
    EXPECT_EQ(x4_engine_slack(&eng.e), X4_NO_STEP) << "SETUP moves nothing that follows";
    x4_engine_fire(&eng.e, x4_engine_due(&eng.e));
    EXPECT_EQ(x4_engine_slack(&eng.e), X4_NO_STEP) << "the first step has no step before it";
    while (eng.e.ch[0].n < 2000) x4_engine_fire(&eng.e, x4_engine_due(&eng.e));
    const uint64_t half = 500'000'000 / hz - 25000;  // of a cruise half period over 25 us
    ASSERT_EQ(eng.e.ch[0].phase, X4_RISE);
    EXPECT_NEAR(double(x4_engine_slack(&eng.e)), 2.0 * half, 2) << hz << " Hz, a rise";
    x4_engine_fire(&eng.e, x4_engine_due(&eng.e));
    ASSERT_EQ(eng.e.ch[0].phase, X4_FALL);
    EXPECT_NEAR(double(x4_engine_slack(&eng.e)), double(half), 2) << hz << " Hz, a fall";
    // A rise 400 ns late: at 20 kHz its fall comes 400 ns late, with no
    // slack left (never less than none); at 19 kHz its pulse absorbs it.
    x4_engine_fire(&eng.e, x4_engine_due(&eng.e));
    x4_engine_fire(&eng.e, x4_engine_due(&eng.e) + 400);
    EXPECT_NEAR(double(x4_engine_slack(&eng.e)), hz == 20000 ? 0.0 : double(half), 2)
        << hz << " Hz, late rise";
  }
}

// The module's on-time edges, as the engine sees them: the timer is 600 ns
// late, but an edge with less slack than that (and 300 ns to spare) is
// fired and written at its time (the glue armed early and waited). Then 20 kHz keeps its plan to
// the nanosecond with 25 us high and low; 19 kHz, with slack, is late by
// the 600 ns and never shifted either.
TEST(Lateness, EdgesWithoutSlackFiredOnTimeKeepThePlan) {
  for (const int hz : {20000, 19000}) {
    Eng eng;
    eng.Start(Move(3000, 0, 0, 0, hz, 50));
    std::vector<x4_event> ev;
    int on_time = 0;
    while (x4_engine_busy(&eng.e)) {
      const bool tight = x4_engine_slack(&eng.e) < 600 + 300;  // x4step_tight_locked()
      const uint64_t now = x4_engine_due(&eng.e) + (tight ? 0 : 600);
      on_time += tight;
      x4_engine_fire(&eng.e, now);
      x4_engine_written(&eng.e, now);
      ev.push_back({now, eng.e.data, eng.e.ctl});
    }
    const Pulses p = PulsesOf(ev, 0);
    ASSERT_EQ(p.rises.size(), 3000u);
    ExpectMinimums(p, X4_CLOCK_MIN_NS, X4_CLOCK_MIN_NS);
    EXPECT_EQ(eng.e.shifts, 0u) << hz << " Hz";
    const uint64_t period = 1'000'000'000 / hz;
    for (size_t n = 1000; n < 2000; n++)
      ASSERT_NEAR(double(p.rises[n + 1] - p.rises[n]), double(period), 1) << hz << " Hz, step " << n;
    if (hz == 20000)
      EXPECT_GT(on_time, 4000) << "the cruise's edges have no slack";
    else
      EXPECT_EQ(on_time, 0) << "19 kHz has slack at every edge";
  }
}

// The port write comes a little after the time the engine was given (the
// step's computation, the port's own delay): minimums count from the write.
TEST(Lateness, MinimumsCountFromTheWrite) {
  Eng eng;
  eng.Timing(5000, 5000);
  eng.Goto(1, 5000, Prof(0, 0, 45000, 400000, 400000));
  const auto ev = RunLate(eng.e, {}, 0, nullptr, 700);
  const Pulses p = PulsesOf(ev, 1);
  EXPECT_EQ(p.rises.size(), 5000u);
  ExpectMinimums(p, 5000u, 5000u);
}

// One stall moves the schedule once: the step after it, counted once even
// when its write, too, comes late.
TEST(Lateness, OneStallIsOneShift) {
  Eng eng;
  const x4_move m = Move(1000, 0, 0, 0, 10000, 0);
  eng.Start(m);
  const auto ev = RunLate(eng.e, {{30'000'000, 300'000}}, 0, nullptr, 700);
  EXPECT_EQ(PulsesOf(ev, 0).rises.size(), 1000u);
  EXPECT_EQ(eng.e.shifts, 1u);
  EXPECT_GE(eng.e.shifted_ns, 200'000u);
}

// Configured pulse and space are minimums from the real edges too.
TEST(Lateness, ConfiguredPulseAndSpaceAt45000StepsPerSecond) {
  Eng eng;
  eng.Timing(5000, 8000);
  eng.Goto(0, 20000, Prof(0, 0, 45000, 400000, 400000));
  const auto ev = RunLate(eng.e, Stalls(20'000'000, 40, 1'700'000, 120'000), 3000);
  const Pulses p = PulsesOf(ev, 0);
  EXPECT_EQ(p.rises.size(), 20000u);
  ExpectMinimums(p, 5000u, 8000u);
}

// Above 20 000 steps/s the symmetric clock's halves keep at least half of
// what the move plans: jitter does not shift them, a stall does.
TEST(Lateness, SymmetricClockAbove20kHzKeepsHalfItsPlannedHalves) {
  Eng eng;
  eng.Goto(2, -20000, Prof(0, 0, 45000, 400000, 400000));
  const auto ev = RunLate(eng.e, Stalls(20'000'000, 40, 1'700'000, 120'000), 2000);
  const Pulses p = PulsesOf(ev, 2);
  EXPECT_EQ(p.rises.size(), 20000u);
  // 45000 steps/s: 22222 ns per step, 11111 ns each half.
  ExpectMinimums(p, 11111u / 2, 11111u / 2);
  EXPECT_GT(eng.e.shifts, 0u);
}

// From 30000 to 45000 steps/s and back the slack is at least a quarter step.
TEST(Lateness, JitterAbove20kHzDoesNotShift) {
  Eng eng;
  eng.Goto(2, 20000, Prof(30000, 30000, 45000, 400000, 400000));
  const auto ev = RunLate(eng.e, {}, 3000);
  EXPECT_EQ(PulsesOf(ev, 2).rises.size(), 20000u);
  EXPECT_EQ(eng.e.shifts, 0u);
}

// Two independent channels, each stalled and shifted on its own.
TEST(Lateness, IndependentChannelsKeepTheirMinimums) {
  Eng eng;
  eng.Goto(0, 12000, Prof(100, 100, 30000, 200000, 200000));
  eng.Goto(3, -9000, Prof(0, 0, 18000, 100000, 50000), kStart + 3000);
  const auto ev = RunLate(eng.e, Stalls(5'000'000, 60, 1'300'000, 200'000), 1500);
  for (int axis : {0, 3}) {
    const Pulses p = PulsesOf(ev, axis);
    SCOPED_TRACE("axis " + std::to_string(axis));
    EXPECT_EQ(p.rises.size(), axis ? 9000u : 12000u);
    const uint64_t min = axis ? X4_CLOCK_MIN_NS : 1'000'000'000 / 30000 / 4;
    ExpectMinimums(p, min, min);
  }
}

// Phase mode: the patterns of one motor never follow each other faster
// than its planned step interval or 50 us, whichever is shorter.
TEST(Lateness, PhaseStepsKeepTheirInterval) {
  Eng eng;
  const x4_timing t = {0, 0, X4_DIR_SETUP_NS, 0};
  ASSERT_EQ(x4_engine_configure(&eng.e, &t, X4_MODE_SMC_PHASE), X4_OK);
  const x4_move m = Move(3000, 0, 0, 0, 10000, 50);
  eng.Start(m);
  const auto ev = RunLate(eng.e, Stalls(50'000'000, 30, 3'300'000, 400'000), 2000);
  std::vector<uint64_t> steps;  // writes of motor X's running patterns
  uint8_t last = 0xff;
  for (const x4_event &e : ev)
    if ((e.data & 0xc0) == 0 && e.data != 0x1b && e.data != last) {
      steps.push_back(e.t_ns);
      last = e.data;
    }
  ASSERT_EQ(steps.size(), 3001u);  // the first pattern, then one per step
  uint64_t shortest = UINT64_MAX;
  for (size_t i = 2; i < steps.size(); i++) shortest = std::min(shortest, steps[i] - steps[i - 1]);
  EXPECT_GE(shortest, 2 * X4_CLOCK_MIN_NS);
  EXPECT_GT(eng.e.shifts, 0u);
}

// The direction hold counts from the last fall as it really happened.
TEST(Lateness, DirectionHoldFromTheRealLastEdge) {
  Eng eng;
  const x4_timing t = {0, 0, X4_DIR_SETUP_NS, 40000};
  ASSERT_EQ(x4_engine_configure(&eng.e, &t, X4_MODE_CLOCK_DIR), X4_OK);
  const x4_move m = Move(-100, 0, 0, 0, 1000, 0);
  eng.Start(m);
  // Step 99 rises at 99 ms + 100 us and should fall 500 us later.
  const auto ev = RunLate(eng.e, {{99'400'000, 700'000}});
  ASSERT_GE(ev.size(), 2u);
  const x4_event &fall = ev[ev.size() - 2], &end = ev.back();
  EXPECT_FALSE(fall.data & X4_CLK_BIT(0));
  EXPECT_EQ(fall.t_ns, 100'100'000u);
  EXPECT_EQ(end.t_ns, fall.t_ns + 40000);
}

// ---- the write budget --------------------------------------------------------

TEST(Budget, TwoAxesAt45000FitAThirdMoveDoesNot) {
  Eng eng;
  eng.Goto(0, 100000, Prof(0, 0, 45000, 100000, 100000));
  eng.Goto(1, 100000, Prof(0, 0, 45000, 100000, 100000));
  const x4_engine before = eng.e;
  EXPECT_EQ(x4_engine_endless(&eng.e, 3, false, 10001, 0, kStart), X4_ERR_RATE_BUDGET);
  const x4_move m = Move(0, 0, 10, 10, 10001, 0);
  ASSERT_EQ(x4_engine_load(&eng.e, &m), X4_OK);
  const x4_engine loaded = eng.e;
  EXPECT_EQ(x4_engine_start(&eng.e, kStart), X4_ERR_RATE_BUDGET);
  EXPECT_EQ(std::memcmp(&loaded, &eng.e, sizeof loaded), 0);
  eng.e = before;
  // 2 * (45000 + 45000) + 2 * 10000 = 200000 writes/s: just fits.
  EXPECT_EQ(x4_engine_endless(&eng.e, 3, false, 10000, 0, kStart), X4_OK);
  int32_t target[X4_AXES] = {0, 0, 0, 5};
  EXPECT_EQ(x4_engine_goto(&eng.e, 0x08, target, true, kStart), X4_ERR_RATE_BUDGET);
}

TEST(Budget, AGotoOfFourFastAxesIsRefusedWhole) {
  Eng eng;
  const x4_profile fast = Prof(0, 0, 45000, 100000, 100000);
  for (int i = 1; i <= X4_AXES; i++) ASSERT_EQ(x4_engine_set_profile(&eng.e, i, &fast), X4_OK);
  const x4_engine before = eng.e;
  const int32_t target[X4_AXES] = {100, 100, 100, 100};
  EXPECT_EQ(x4_engine_goto(&eng.e, 0x0f, target, true, kStart), X4_ERR_RATE_BUDGET);
  EXPECT_EQ(std::memcmp(&before, &eng.e, sizeof before), 0);
  EXPECT_EQ(x4_engine_goto(&eng.e, 0x03, target, true, kStart), X4_OK);
}

TEST(Budget, HomingCountsItsFasterPhase) {
  Eng eng;
  x4_switches sw{};
  sw.ref[0] = 1;
  ASSERT_EQ(x4_switch_set(&eng.e, &sw), X4_OK);
  eng.Goto(1, 100000, Prof(0, 0, 45000, 100000, 100000));
  eng.Goto(2, 100000, Prof(0, 0, 45000, 100000, 100000));
  EXPECT_EQ(x4_switch_home(&eng.e, 1, X4_HOME_PHASE1 | X4_HOME_PHASE2, -100, 10001, 1000, kStart),
            X4_ERR_RATE_BUDGET);
  EXPECT_EQ(x4_switch_home(&eng.e, 1, X4_HOME_PHASE1 | X4_HOME_PHASE2, -10000, 100, 1000, kStart), X4_OK);
}

TEST(Budget, PhaseModeCountsOneWritePerMotor) {
  Eng eng;
  const x4_timing t = {0, 0, X4_DIR_SETUP_NS, 0};
  ASSERT_EQ(x4_engine_configure(&eng.e, &t, X4_MODE_SMC_PHASE), X4_OK);
  eng.e.budget = 3 * 20000 - 1;
  const x4_move m = Move(100, 100, 100, 0, 20000, 0);
  ASSERT_EQ(x4_engine_load(&eng.e, &m), X4_OK);
  EXPECT_EQ(x4_engine_start(&eng.e, kStart), X4_ERR_RATE_BUDGET);
  eng.e.budget = 3 * 20000;
  EXPECT_EQ(x4_engine_start(&eng.e, kStart), X4_OK);
}

// A reference run keeps the budget of its faster phase while it runs the
// slower one: phase 2 starts from the timer, where nothing can refuse it.
TEST(Budget, AReferenceRunHoldsItsFasterPhase) {
  Eng eng;
  x4_switches sw{};
  sw.ref[0] = 1;
  ASSERT_EQ(x4_switch_set(&eng.e, &sw), X4_OK);
  ASSERT_EQ(x4_switch_home(&eng.e, 1, X4_HOME_PHASE1 | X4_HOME_PHASE2, -100, 45000, 1000, kStart), X4_OK);
  eng.Goto(1, 100000, Prof(0, 0, 45000, 100000, 100000));
  EXPECT_EQ(x4_engine_endless(&eng.e, 3, false, 10001, 0, kStart), X4_ERR_RATE_BUDGET);
  EXPECT_EQ(x4_engine_endless(&eng.e, 3, false, 10000, 0, kStart), X4_OK);
}

// An axis of a goto that is at its target already needs nothing.
TEST(Budget, AxesAtTheirTargetsDoNotCount) {
  Eng eng;
  const x4_profile fast = Prof(0, 0, 45000, 100000, 100000);
  for (int i = 1; i <= X4_AXES; i++) ASSERT_EQ(x4_engine_set_profile(&eng.e, i, &fast), X4_OK);
  const int32_t target[X4_AXES] = {100, 100, 0, 0};
  EXPECT_EQ(x4_engine_goto(&eng.e, 0x0f, target, true, kStart), X4_OK);
}

TEST(Budget, ZeroMeansNoBudget) {
  Eng eng;
  eng.e.budget = 0;
  const x4_profile fast = Prof(0, 0, 45000, 100000, 100000);
  for (int i = 1; i <= X4_AXES; i++) ASSERT_EQ(x4_engine_set_profile(&eng.e, i, &fast), X4_OK);
  const int32_t target[X4_AXES] = {100, 100, 100, 100};
  EXPECT_EQ(x4_engine_goto(&eng.e, 0x0f, target, true, kStart), X4_OK);
}

}  // namespace
