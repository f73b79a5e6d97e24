// SPDX-License-Identifier: GPL-2.0
// Unit tests of the engine core (the same C file the module runs).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>

#include "engine_ref.h"

using namespace x4test;

namespace {

constexpr uint64_t kStart = 1000;  // engine time of X4Start in the tests
// Edge times against the double-precision reference. The engine computes
// every edge from the step index in integer ns (floors of square roots and
// divisions): it achieves <= 2 ns, printed by each test ("max error"). The
// bound is that plus a margin, so that an edge a few hundred ns off fails
// the physics, not only an interval test.
constexpr double kTolNs = 20;

// Prints a test's largest edge-time error, for the record, and checks it.
void ExpectEdgeError(double err_ns, const std::string &what) {
  std::printf("[ edges    ] %-60s max error %6.1f ns\n", what.c_str(), err_ns);
  EXPECT_LT(err_ns, kTolNs) << what;
}

struct Engine {
  x4_engine e;
  Engine() { x4_engine_init(&e); }
  int Load(const x4_move &m) { return x4_engine_load(&e, &m); }
  int Start() { return x4_engine_start(&e, kStart); }
  Recording Run(size_t max_events = SIZE_MAX) {
    Recording r;
    record(e, r, max_events);
    return r;
  }
};

Recording RunMove(const x4_move &m) {
  Engine eng;
  EXPECT_EQ(eng.Load(m), X4_OK);
  EXPECT_EQ(eng.Start(), X4_OK);
  return eng.Run();
}

int Leader(const x4_move &m) {
  int lead = 0;
  for (int i = 1; i < X4_AXES; i++)
    if (std::abs(m.steps[i]) > std::abs(m.steps[lead])) lead = i;
  return lead;
}

// Every leader rising edge against the double-precision reference.
double MaxErrorNs(const x4_move &m, const Recording &r) {
  const int lead = Leader(m);
  const uint64_t steps = std::abs(m.steps[lead]);
  const uint64_t origin = kStart + X4_DIR_SETUP_NS;
  double worst = 0;
  for (size_t n = 0; n < r.rises[lead].size(); n++) {
    const double ideal = ref_step_time(steps, m.freq_hz, m.ramp_ms, n) * 1e9;
    worst = std::max(worst, std::fabs(double(r.rises[lead][n] - origin) - ideal));
  }
  return worst;
}

}  // namespace

// ---- validation ------------------------------------------------------------

TEST(Validate, EveryErrorCode) {
  const struct {
    x4_move m;
    int err;
  } cases[] = {
      {Move(1000, 800, 600, 400, 1000, 50), X4_OK},
      {Move(1, 0, 0, 0, 20000, 1000), X4_OK},
      {Move(1, 0, 0, 0, 10, 10), X4_OK},
      {Move(0, 0, 0, 0, 1000, 50), X4_ERR_NO_STEPS},
      {Move(1, 0, 0, 0, 20001, 50), X4_ERR_FREQ_TOO_HIGH},
      {Move(1, 0, 0, 0, 9, 0), X4_ERR_FREQ_TOO_LOW},
      {Move(1, 0, 0, 0, -5, 0), X4_ERR_FREQ_TOO_LOW},
      {Move(1, 0, 0, 0, 2000, 1001), X4_ERR_RAMP_TOO_HIGH},
      {Move(1, 0, 0, 0, 10, 50), X4_ERR_RAMP_FREQ},
      {Move(1, 0, 0, 0, 100, 101), X4_ERR_RAMP_FREQ},
      {Move(1, 0, 0, 0, 100, -1), X4_ERR_PARAM_FAIL},
      {Move(16777216, -16777216, 0, 0, 1000, 50), X4_OK},
      {Move(16777217, 0, 0, 0, 1000, 50), X4_ERR_STEPS_TOO_HIGH},
      {Move(0, 0, 0, -16777217, 1000, 50), X4_ERR_STEPS_TOO_HIGH},
      // Documented order: frequency, then ramp, then paths.
      {Move(0, 0, 0, 0, 5, 2000), X4_ERR_FREQ_TOO_LOW},
      {Move(0, 0, 0, 0, 100, 2000), X4_ERR_RAMP_TOO_HIGH},
      {Move(16777217, 0, 0, 0, 100, 200), X4_ERR_RAMP_FREQ},
  };
  for (const auto &c : cases) {
    EXPECT_EQ(x4_move_check(&c.m), c.err) << c.m.steps[0] << " " << c.m.freq_hz << " " << c.m.ramp_ms;
  }
}

TEST(Validate, BadLoadChangesNothing) {
  Engine eng;
  const x4_engine before = eng.e;
  EXPECT_EQ(eng.Load(Move(0, 0, 0, 0, 1000, 50)), X4_ERR_NO_STEPS);
  EXPECT_EQ(std::memcmp(&before, &eng.e, sizeof before), 0);
  EXPECT_EQ(eng.Start(), X4_ERR_NOT_LOADED);
  EXPECT_EQ(x4_engine_brake(&eng.e), X4_ERR_NOT_ACTIVE);
  EXPECT_EQ(x4_engine_stop(&eng.e), X4_ERR_NOT_ACTIVE);
}

TEST(Validate, StateErrors) {
  Engine eng;
  ASSERT_EQ(eng.Load(Move(100, 0, 0, 0, 1000, 0)), X4_OK);
  EXPECT_EQ(eng.Load(Move(100, 0, 0, 0, 1000, 0)), X4_ERR_IS_LOADED);
  EXPECT_EQ(x4_engine_endless(&eng.e, 1, false, 1000, 0, 0), X4_ERR_IS_LOADED);
  ASSERT_EQ(eng.Start(), X4_OK);
  EXPECT_EQ(eng.Start(), X4_ERR_NOT_LOADED);
  EXPECT_EQ(x4_engine_endless(&eng.e, 1, false, 1000, 0, 0), X4_ERR_IS_ACTIVE);
  ASSERT_EQ(eng.Load(Move(5, 0, 0, 0, 1000, 0)), X4_OK);  // preload
  EXPECT_EQ(eng.Start(), X4_ERR_IS_ACTIVE);
}

TEST(Validate, EndlessArguments) {
  Engine eng;
  EXPECT_EQ(x4_engine_endless(&eng.e, 0, false, 1000, 50, 0), X4_ERR_PARAM_FAIL);
  EXPECT_EQ(x4_engine_endless(&eng.e, 5, false, 1000, 50, 0), X4_ERR_PARAM_FAIL);
  EXPECT_EQ(x4_engine_endless(&eng.e, 1, false, 30000, 50, 0), X4_ERR_FREQ_TOO_HIGH);
  EXPECT_EQ(x4_engine_endless(&eng.e, 1, false, 1000, 1500, 0), X4_ERR_RAMP_TOO_HIGH);
  EXPECT_EQ(x4_engine_endless(&eng.e, 1, true, 20, 50, 0), X4_ERR_RAMP_FREQ);
  EXPECT_FALSE(x4_engine_busy(&eng.e));
}

// ---- profile ---------------------------------------------------------------

TEST(Profile, IsqrtIsExactFloor) {
  std::mt19937_64 rng(1);
  for (int i = 0; i < 200000; i++) {
    const uint64_t x = rng() >> (rng() % 64);
    const uint64_t r = x4_isqrt(x);
    ASSERT_LE((unsigned __int128)r * r, x);
    ASSERT_GT((unsigned __int128)(r + 1) * (r + 1), x);
  }
}

TEST(Profile, ManualExampleMatchesReference) {
  const x4_move m = Move(1000, 800, 600, 400, 1000, 50);
  const Recording r = RunMove(m);
  for (int a = 0; a < 4; a++) EXPECT_EQ(r.rises[a].size(), size_t(std::abs(m.steps[a])));
  ExpectEdgeError(MaxErrorNs(m, r), "the manual's example");
}

TEST(Profile, EdgeTimesMatchTheReferenceAcrossTheRange) {
  const int freqs[] = {10, 11, 99, 1000, 4999, 13331, 20000};
  const int ramps[] = {0, 1, 7, 50, 333, 1000};
  const int32_t lengths[] = {1, 2, 3, 5, 6, 7, 10, 100, 1001, 25000};
  double worst = 0;
  std::string where;
  for (int f : freqs)
    for (int rp : ramps) {
      if (rp > f) continue;
      for (int32_t len : lengths) {
        const x4_move m = Move(len, len / 3, -len / 2, 0, f, rp);
        const Recording r = RunMove(m);
        ASSERT_EQ(r.rises[0].size(), size_t(len));
        const double err = MaxErrorNs(m, r);
        if (err >= worst) {
          worst = err;
          where = std::to_string(len) + " steps, " + std::to_string(f) + " Hz, " + std::to_string(rp) + " ms";
        }
        EXPECT_LT(err, kTolNs) << f << " Hz " << rp << " ms " << len;
      }
    }
  ExpectEdgeError(worst, "across the range, worst at " + where);
}

TEST(Profile, LongestMoveSampledDirectly) {
  // 16,777,216 steps: the closed form at sampled n, and the last edges of
  // a full run below.
  for (int f : {10, 1000, 20000})
    for (int rp : {0, 10, 1000}) {
      if (rp > f) continue;
      Engine eng;
      ASSERT_EQ(eng.Load(Move(X4_STEPS_MAX, 0, 0, 0, f, rp)), X4_OK);
      std::mt19937_64 rng(f + rp);
      double worst = 0;
      for (int i = 0; i < 20000; i++) {
        const uint64_t n = i < 100 ? i : (i < 200 ? X4_STEPS_MAX - 1 - (i - 100) : rng() % X4_STEPS_MAX);
        const double ideal = ref_step_time(X4_STEPS_MAX, f, rp, n) * 1e9;
        const double err = std::fabs(double(x4_plan_time(&eng.e.next, n)) - ideal);
        worst = std::max(worst, err);
        ASSERT_LT(err, kTolNs) << f << " " << rp << " n=" << n;
      }
      ExpectEdgeError(worst,
                      "16777216 steps sampled, " + std::to_string(f) + " Hz, " + std::to_string(rp) + " ms");
    }
}

TEST(Profile, LongestMoveFullRun) {
  // Streamed: every edge is checked as the engine produces it, in constant
  // memory (a recording of the 67 million events took 1.6 GB and most of
  // this test's time).
  const x4_move m = Move(X4_STEPS_MAX, X4_STEPS_MAX / 3, 7, -X4_STEPS_MAX, 20000, 1000);
  Engine eng;
  ASSERT_EQ(eng.Load(m), X4_OK);
  ASSERT_EQ(eng.Start(), X4_OK);
  const int lead = Leader(m);
  const uint64_t origin = kStart + X4_DIR_SETUP_NS;
  uint64_t rises[X4_AXES] = {};
  uint8_t data = eng.e.data;
  double worst = 0;
  while (x4_engine_busy(&eng.e)) {
    const x4_event ev = fire(eng.e);
    const uint8_t rose = ev.data & ~data & X4_CLK_MASK;
    data = ev.data;
    for (int a = 0; a < X4_AXES; a++) rises[a] += (rose & X4_CLK_BIT(a)) != 0;
    if (!(rose & X4_CLK_BIT(lead))) continue;
    const uint64_t n = rises[lead] - 1;
    const double err =
        std::fabs(double(ev.t_ns - origin) - ref_step_time(X4_STEPS_MAX, 20000, 1000, n) * 1e9);
    worst = std::max(worst, err);
    ASSERT_LT(err, kTolNs) << "leader step " << n;
  }
  for (int a = 0; a < 4; a++) ASSERT_EQ(rises[a], uint64_t(std::abs(m.steps[a])));
  ExpectEdgeError(worst, "16777216 steps run, 20 kHz, 1000 ms");
}

namespace {

// The leader's intervals of a short move at 20 kHz with 1 s ramps (10,000
// steps per ramp: none of these reaches 20 kHz), and the plateau: the run
// of intervals within 2 ns of the shortest.
struct Plateau {
  std::vector<int64_t> iv;
  size_t first = 0, count = 0;
};

Plateau PlateauOf(int32_t len) {
  const Recording r = RunMove(Move(len, 0, 0, 0, 20000, 1000));
  Plateau p;
  EXPECT_EQ(r.rises[0].size(), size_t(len));
  for (size_t i = 1; i < r.rises[0].size(); i++) p.iv.push_back(r.rises[0][i] - r.rises[0][i - 1]);
  const int64_t top = *std::min_element(p.iv.begin(), p.iv.end());
  while (p.iv[p.first] > top + 2) p.first++;
  while (p.first + p.count < p.iv.size() && p.iv[p.first + p.count] <= top + 2) p.count++;
  return p;
}

// Ramps up to the plateau and down from it, each interval shorter (longer)
// than the one before, mirrored: interval i as long as interval D - 1 - i.
void ExpectMirroredRamps(const Plateau &p, int32_t len) {
  const size_t n = p.iv.size();
  for (size_t i = 0; i + 1 < n; i++) {
    if (i + 1 <= p.first) {
      EXPECT_GT(p.iv[i], p.iv[i + 1] + 2) << len << " steps: accelerating, interval " << i;
    }
    if (i + 1 >= p.first + p.count) {
      EXPECT_LT(p.iv[i] + 2, p.iv[i + 1]) << len << " steps: braking, interval " << i;
    }
    EXPECT_LE(std::llabs(p.iv[i] - p.iv[n - 1 - i]), 2) << len << " steps: interval " << i << " not mirrored";
  }
}

}  // namespace

TEST(Profile, ShortMoveKeepsPlateau) {
  // Moves too short to reach their frequency run X4_PLATEAU_STEPS steps at
  // constant speed between mirrored ramps (docs/motion.md, "Interpolated moves and ramps"): 101
  // steps are 48 up, 4 at constant speed, 48 down; 21 steps 8, 4, 8.
  for (int32_t len : {101, 21}) {
    const Plateau p = PlateauOf(len);
    EXPECT_EQ(p.count, size_t(X4_PLATEAU_STEPS)) << len << " steps: intervals at the top speed";
    EXPECT_EQ(p.first, size_t(len - 1 - X4_PLATEAU_STEPS) / 2) << len << " steps: ramp steps";
    ExpectMirroredRamps(p, len);
  }
}

TEST(Profile, ShortMoveKeepsPlateauOddDistance) {
  // The same with an odd number of intervals D (102 and 20 steps). Mirrored
  // ramps leave an odd number of equal intervals in the middle, so the
  // documented 4 steps at constant speed are at least 4 here (5); an engine
  // ramping over (D - 4) / 2 = 48.5 (7.5) steps left 3.
  for (int32_t len : {102, 20}) {
    const Plateau p = PlateauOf(len);
    EXPECT_GE(p.count, size_t(X4_PLATEAU_STEPS)) << len << " steps: intervals at the top speed";
    ExpectMirroredRamps(p, len);
  }
}

TEST(Profile, RampZeroIsFullFrequencyFromTheStart) {
  const Recording r = RunMove(Move(10, 0, 0, 0, 5000, 0));
  for (size_t i = 1; i < r.rises[0].size(); i++) EXPECT_EQ(r.rises[0][i] - r.rises[0][i - 1], 200000u);
}

TEST(Profile, CruiseAtFreqAndSymmetricRamps) {
  const Recording r = RunMove(Move(5000, 0, 0, 0, 10000, 100));
  const auto &t = r.rises[0];
  EXPECT_EQ(t[2500] - t[2499], 100000u);  // 10 kHz in the middle
  for (size_t i = 1; i < 600; i++) {
    const int64_t up = t[i] - t[i - 1], down = t[t.size() - i] - t[t.size() - i - 1];
    EXPECT_LE(std::llabs(up - down), 2) << i;
  }
}

// ---- interpolation -----------------------------------------------------------

TEST(Interpolation, RandomMovesStayWithinHalfAStep) {
  std::mt19937 rng(42);
  std::uniform_int_distribution<int32_t> len(-30000, 30000);
  for (int trial = 0; trial < 200; trial++) {
    x4_move m = Move(len(rng), len(rng), len(rng), len(rng), 20000, 0);
    if (!m.steps[0]) m.steps[0] = 1;
    Engine eng;
    ASSERT_EQ(eng.Load(m), X4_OK);
    ASSERT_EQ(eng.Start(), X4_OK);
    const int lead = Leader(m);
    const uint64_t total = std::abs(m.steps[lead]);
    uint64_t k = 0;
    while (x4_engine_busy(&eng.e)) {
      const x4_event ev = fire(eng.e);
      if (!(ev.data & X4_CLK_BIT(lead))) continue;
      if (eng.e.ch[0].phase != X4_FALL || eng.e.ch[0].n + 1 == k) continue;
      k = eng.e.ch[0].n + 1;  // leader steps made (axis 1 moves: channel 0)
      for (int a = 0; a < X4_AXES; a++) {
        // |pos - k * path / total| <= 1/2, in integers.
        const int64_t off = 2 * int64_t(total) * eng.e.steps[a] - 2 * int64_t(k) * m.steps[a];
        ASSERT_LE(std::llabs(off), int64_t(total)) << "axis " << a << " at " << k;
      }
    }
    for (int a = 0; a < X4_AXES; a++) EXPECT_EQ(eng.e.steps[a], m.steps[a]);
  }
}

TEST(Interpolation, MinorStepsCoincideWithLeaderSteps) {
  const Recording r = RunMove(Move(1000, 800, 600, 400, 1000, 50));
  for (int a = 1; a < 4; a++) {
    for (uint64_t t : r.rises[a]) EXPECT_TRUE(std::binary_search(r.rises[0].begin(), r.rises[0].end(), t));
    for (uint64_t t : r.falls[a]) EXPECT_TRUE(std::binary_search(r.falls[0].begin(), r.falls[0].end(), t));
  }
  EXPECT_EQ(r.rises[0].back(), std::max({r.rises[1].back(), r.rises[2].back(), r.rises[3].back()}));
}

// ---- signals -----------------------------------------------------------------

TEST(Signals, DirectionSetupAndHold) {
  Engine eng;
  ASSERT_EQ(eng.Load(Move(-50, 20, 0, -3, 2000, 10)), X4_OK);
  eng.e.data = 0xff & ~X4_CLK_MASK;  // axis 3 keeps its level
  ASSERT_EQ(eng.Start(), X4_OK);
  const Recording r = eng.Run();
  const x4_event &start = r.events.front();
  EXPECT_EQ(start.t_ns, kStart);
  EXPECT_EQ(start.data & 0x55, X4_DIR_BIT(1) | X4_DIR_BIT(2));
  EXPECT_EQ(r.rises[0].front() - start.t_ns, X4_DIR_SETUP_NS);
  EXPECT_EQ(r.dir_changes, 0);
  EXPECT_EQ(eng.e.steps[0], -50);
  EXPECT_EQ(eng.e.steps[3], -3);
}

TEST(Signals, SymmetricClockAndPulseWidths) {
  const Recording r = RunMove(Move(3000, 1000, 0, 0, 20000, 20));
  const auto &up = r.rises[0], &down = r.falls[0];
  ASSERT_EQ(up.size(), down.size());
  for (size_t i = 0; i + 1 < up.size(); i++) {
    const int64_t high = down[i] - up[i], low = up[i + 1] - down[i];
    ASSERT_LE(std::llabs(high - low), 1) << i;
    ASSERT_GE(high, 25000) << i;
  }
  for (size_t i = 0; i < r.rises[1].size(); i++) {
    const size_t j = std::lower_bound(up.begin(), up.end(), r.rises[1][i]) - up.begin();
    EXPECT_EQ(r.falls[1][i] - r.rises[1][i], down[j] - up[j]);
  }
}

TEST(Signals, BoostWhileRampingAktivWhileRunning) {
  Engine eng;
  ASSERT_EQ(eng.Load(Move(2000, 0, 0, 0, 10000, 50)), X4_OK);  // 250-step ramps
  ASSERT_EQ(eng.Start(), X4_OK);
  const Recording r = eng.Run();
  int step = -1;
  for (size_t i = 0; i < r.events.size(); i++) {
    const x4_event &ev = r.events[i];
    if (i + 1 < r.events.size()) {
      EXPECT_TRUE(ev.ctl & X4_CTL_AKTIV);
    }
    if (ev.data & X4_CLK_BIT(0)) step++;
    if (!(ev.data & X4_CLK_BIT(0)) || step < 0) continue;
    const bool boost = ev.ctl & X4_CTL_BOOST;
    if (step < 240 || step > 1760) {
      EXPECT_TRUE(boost) << step;
    }
    if (step > 260 && step < 1740) {
      EXPECT_FALSE(boost) << step;
    }
  }
  EXPECT_EQ(r.events.back().ctl & (X4_CTL_AKTIV | X4_CTL_BOOST), 0);
  EXPECT_EQ(r.events.back().data & X4_CLK_MASK, 0);
}

TEST(Signals, NoBoostWithoutRamp) {
  const Recording r = RunMove(Move(100, 0, 0, 0, 1000, 0));
  for (const auto &ev : r.events) EXPECT_FALSE(ev.ctl & X4_CTL_BOOST);
}

TEST(Signals, OutputsSurviveMoves) {
  Engine eng;
  x4_engine_set_signal(&eng.e, X4_CTL_SIGNAL2, true);
  ASSERT_EQ(eng.Load(Move(10, 0, 0, 0, 1000, 0)), X4_OK);
  ASSERT_EQ(eng.Start(), X4_OK);
  const Recording r = eng.Run();
  for (const auto &ev : r.events) EXPECT_EQ(ev.ctl & 3, X4_CTL_SIGNAL2);
}

// ---- brake, stop, endless, preload -------------------------------------------

namespace {

// Brake after `events` events and check the stop follows the ramp.
void BrakeAfter(const x4_move &m, size_t events, int64_t expect_steps) {
  Engine eng;
  ASSERT_EQ(eng.Load(m), X4_OK);
  ASSERT_EQ(eng.Start(), X4_OK);
  Recording r = eng.Run(events);
  ASSERT_EQ(x4_engine_brake(&eng.e), x4_engine_busy(&eng.e) ? X4_OK : X4_ERR_NOT_ACTIVE);
  record(eng.e, r);
  EXPECT_EQ(eng.e.steps[0], int32_t(r.rises[0].size()));
  if (expect_steps >= 0) {
    EXPECT_EQ(int64_t(r.rises[0].size()), expect_steps) << "after " << events;
  }
  EXPECT_EQ(r.events.back().ctl & X4_CTL_AKTIV, 0);
  EXPECT_EQ(r.events.back().data & X4_CLK_MASK, 0);
}

}  // namespace

TEST(Brake, WhileAcceleratingMirrorsTheRamp) {
  // 1000 Hz, 1000 ms: 500 steps of ramp. Braking when step 100 is due
  // (1 + 2*100 events) decelerates over 100 more: steps 0..200.
  const x4_move m = Move(10000, 5000, 0, 0, 1000, 1000);
  BrakeAfter(m, 1 + 2 * 100, 201);
  Engine eng;
  ASSERT_EQ(eng.Load(m), X4_OK);
  ASSERT_EQ(eng.Start(), X4_OK);
  Recording r = eng.Run(1 + 2 * 100);
  ASSERT_EQ(x4_engine_brake(&eng.e), X4_OK);
  record(eng.e, r);
  const auto &t = r.rises[0];
  for (size_t i = 1; i < 100; i++) {
    const int64_t up = t[i] - t[i - 1], down = t[200 - i + 1] - t[200 - i];
    EXPECT_LE(std::llabs(up - down), 2) << i;
  }
  EXPECT_EQ(eng.e.steps[1], (eng.e.steps[0] * 5000 + 5000) / 10000);  // interpolation holds
}

TEST(Brake, WhileCruisingUsesTheRampLength) {
  // 10 kHz, 50 ms: 250-step ramps. Brake when step 1000 is due.
  BrakeAfter(Move(100000, 0, 0, 0, 10000, 50), 1 + 2 * 1000, 1000 + 250 + 1);
  // While the falling edge of step 999 is pending: same outcome.
  BrakeAfter(Move(100000, 0, 0, 0, 10000, 50), 2 * 1000, 1000 + 250 + 1);
}

TEST(Brake, WhileDeceleratingChangesNothing) {
  const x4_move m = Move(1000, 0, 0, 0, 10000, 50);
  BrakeAfter(m, 2 * 900, 1000);
}

TEST(Brake, AtEveryEventOfAShortMove) {
  for (size_t ev = 0; ev < 56; ev++) BrakeAfter(Move(25, 12, 0, -25, 5000, 100), ev, -1);
}

namespace {

// Brake while leader step nb is next (its rise pending, or the fall of step
// nb - 1) and check the stop against the physics. From the reference's
// speed v at step nb, the ramp's deceleration a = freq / ramp needs
// v^2 / 2a more steps to stop: the engine must take the next whole number
// of them, as fewer would need more deceleration than a. The edges say the
// same: from step nb to the last interval the speed falls by no more than
// a per second (on a ramp, an interval's speed is the ramp's speed at its
// middle, exactly).
void ExpectStopWithinTheRamp(const x4_move &m, uint64_t nb, bool fall_pending) {
  SCOPED_TRACE(std::to_string(m.steps[0]) + " steps, " + std::to_string(m.freq_hz) + " Hz, " +
               std::to_string(m.ramp_ms) + " ms, braked at step " + std::to_string(nb) +
               (fall_pending ? " (fall pending)" : " (rise pending)"));
  Engine eng;
  ASSERT_EQ(eng.Load(m), X4_OK);
  ASSERT_EQ(eng.Start(), X4_OK);
  Recording r = eng.Run(fall_pending ? 2 * nb : 1 + 2 * nb);
  ASSERT_EQ(r.rises[0].size(), nb);
  ASSERT_EQ(x4_engine_brake(&eng.e), X4_OK);
  record(eng.e, r);
  const auto &t = r.rises[0];
  ASSERT_GE(t.size(), nb + 2) << "a stop from speed takes steps";
  const double a = m.freq_hz * 1000.0 / m.ramp_ms;
  const double v = ref_speed(uint64_t(m.steps[0]), m.freq_hz, m.ramp_ms, double(nb));
  const double dist = v * v / (2 * a);
  const uint64_t more = t.size() - 1 - nb;
  EXPECT_EQ(more, uint64_t(std::ceil(dist - 1e-9))) << "v^2 / 2a = " << dist << " steps";
  EXPECT_LE(v * v / (2.0 * more), a * (1 + 1e-9)) << "the deceleration the stop needs";
  const double last_iv = double(t.back() - t[t.size() - 2]);
  const double mid = (double(t.back()) + double(t[t.size() - 2])) / 2;
  EXPECT_LE((v - 1e9 / last_iv) / ((mid - double(t[nb])) * 1e-9), a * (1 + 1e-6)) << "measured on the edges";
}

}  // namespace

TEST(Brake, StopDistanceRoundsUp) {
  // The brake tests above stop after whole numbers of ramp steps (v^2 / 2a
  // = 100, 250, 500); here v^2 / 2a has a fraction: 10.5, 46.66, 124.975,
  // 9999.5 and 1.0005 steps in the cruise.
  const struct { int freq, ramp; } ramps[] = {{1000, 21}, {13331, 7}, {4999, 50}, {19999, 1000}, {2001, 1}};
  for (const auto &rp : ramps) {
    const uint64_t na = uint64_t(rp.freq) * rp.ramp / 2000;  // whole steps of one ramp
    const x4_move m = Move(30000, 7001, 0, -12345, rp.freq, rp.ramp);
    for (bool fall : {false, true}) {
      for (uint64_t nb : {std::max<uint64_t>(na / 2, 1), na, na + 1, na + 7, uint64_t(15000)})
        ExpectStopWithinTheRamp(m, nb, fall);
    }
  }
  // Short moves: ramps of floor((d - 4) / 2) steps around the plateau of 4
  // or 5 intervals; braked on the plateau.
  for (int32_t len : {101, 102, 20, 21})
    for (uint64_t nb : {uint64_t(len / 2 - 1), uint64_t(len / 2)})
      ExpectStopWithinTheRamp(Move(len, 0, 0, 0, 20000, 1000), nb, false);
}

TEST(Brake, WithoutRampEndsAfterTheCurrentPulse) {
  BrakeAfter(Move(1000, 0, 0, 0, 1000, 0), 1 + 2 * 10, 10);  // rise 10 pending
  BrakeAfter(Move(1000, 0, 0, 0, 1000, 0), 2 * 10, 10);      // fall 9 pending
  BrakeAfter(Move(1000, 0, 0, 0, 1000, 0), 0, 0);            // before the start
}

TEST(Brake, EndlessMove) {
  Engine eng;
  ASSERT_EQ(x4_engine_endless(&eng.e, 2, true, 2000, 100, kStart), X4_OK);  // 100-step ramp
  Recording r = eng.Run(1 + 2 * 5000);
  ASSERT_TRUE(x4_engine_busy(&eng.e));
  EXPECT_EQ(r.rises[1].size(), 5000u);
  EXPECT_EQ(r.rises[1][4000] - r.rises[1][3999], 500000u);  // 2 kHz
  ASSERT_EQ(x4_engine_brake(&eng.e), X4_OK);
  record(eng.e, r);
  EXPECT_EQ(r.rises[1].size(), 5000u + 100 + 1);
  EXPECT_EQ(eng.e.steps[1], -5101);
  EXPECT_EQ(r.events.front().data & X4_DIR_BIT(1), 0);
}

TEST(Brake, EndlessMatchesReference) {
  Engine eng;
  ASSERT_EQ(x4_engine_endless(&eng.e, 1, false, 20000, 1000, kStart), X4_OK);
  const Recording r = eng.Run(1 + 2 * 300000);
  const uint64_t origin = kStart + X4_DIR_SETUP_NS;
  double worst = 0;
  for (size_t n = 0; n < r.rises[0].size(); n++) {
    const double err = std::fabs(double(r.rises[0][n] - origin) - ref_step_time(0, 20000, 1000, n) * 1e9);
    worst = std::max(worst, err);
    ASSERT_LT(err, kTolNs) << n;
  }
  ExpectEdgeError(worst, "endless, 20 kHz, 1000 ms, 300000 steps");
}

TEST(Stop, NoFurtherEdge) {
  Engine eng;
  ASSERT_EQ(eng.Load(Move(1000, 0, 0, 0, 1000, 50)), X4_OK);
  ASSERT_EQ(eng.Start(), X4_OK);
  Recording r = eng.Run(2 + 2 * 10);  // clock of step 10 is high
  ASSERT_TRUE(eng.e.data & X4_CLK_BIT(0));
  ASSERT_EQ(x4_engine_stop(&eng.e), X4_OK);
  EXPECT_FALSE(x4_engine_busy(&eng.e));
  EXPECT_EQ(eng.e.data & X4_CLK_MASK, 0);
  EXPECT_EQ(eng.e.ctl & (X4_CTL_AKTIV | X4_CTL_BOOST), 0);
  EXPECT_EQ(eng.e.steps[0], 11);
  EXPECT_EQ(x4_engine_stop(&eng.e), X4_ERR_NOT_ACTIVE);
}

TEST(Preload, SecondMoveStartsAfterTheFirst) {
  Engine eng;
  ASSERT_EQ(eng.Load(Move(1000, 800, 600, 400, 1000, 50)), X4_OK);
  ASSERT_EQ(eng.Start(), X4_OK);
  ASSERT_EQ(eng.Load(Move(-1000, -800, -600, -400, 1000, 50)), X4_OK);
  const x4_plan planned = eng.e.next;
  Recording r = eng.Run();
  EXPECT_EQ(eng.e.steps[0], 1000);
  ASSERT_EQ(x4_engine_start(&eng.e, r.events.back().t_ns), X4_OK);
  EXPECT_EQ(std::memcmp(&planned, &eng.e.ch[0].run, sizeof planned), 0) << "started as planned";
  Recording back = eng.Run();
  EXPECT_EQ(eng.e.steps[0], -1000);
  EXPECT_EQ(eng.e.steps[3], -400);
  EXPECT_EQ(back.rises[2].size(), 600u);
  EXPECT_EQ(eng.Start(), X4_ERR_NOT_LOADED);
}

TEST(Signals, DirectionSetupCountsFromALateStart) {
  Engine eng;
  ASSERT_EQ(eng.Load(Move(5, 0, 0, 0, 1000, 0)), X4_OK);
  ASSERT_EQ(eng.Start(), X4_OK);
  fire(eng.e, kStart + 7000);  // the timer fired 7 us late
  EXPECT_EQ(x4_engine_due(&eng.e), kStart + 7000 + X4_DIR_SETUP_NS);
}

// ---- step timing settings -----------------------------------------------------

TEST(Timing, ConfiguredTimesAreMetExactly) {
  Engine eng;
  const x4_timing t{5000, 2000, 20000, 50000};
  ASSERT_EQ(x4_engine_configure(&eng.e, &t, X4_MODE_CLOCK_DIR), X4_OK);
  ASSERT_EQ(eng.Load(Move(200, -50, 0, 0, 10000, 10)), X4_OK);
  ASSERT_EQ(eng.Start(), X4_OK);
  const Recording r = eng.Run();
  ASSERT_EQ(r.rises[0].size(), 200u);
  EXPECT_EQ(r.rises[0][0] - kStart, 20000u) << "direction setup";
  for (size_t i = 0; i < 200; i++) EXPECT_EQ(r.falls[0][i] - r.rises[0][i], 5000u) << "pulse " << i;
  for (size_t i = 0; i < r.rises[1].size(); i++) EXPECT_EQ(r.falls[1][i] - r.rises[1][i], 5000u);
  const x4_event &last = r.events.back();
  EXPECT_EQ(last.t_ns - r.falls[0].back(), 50000u) << "direction hold";
  EXPECT_EQ(last.ctl & X4_CTL_AKTIV, 0);
  EXPECT_EQ(r.dir_changes, 0);
}

TEST(Timing, MovesThatCannotFitAreRefused) {
  Engine eng;
  const x4_timing fixed{60000, 50000, 100000, 0};  // 110 us per step: < 9090 Hz
  ASSERT_EQ(x4_engine_configure(&eng.e, &fixed, X4_MODE_CLOCK_DIR), X4_OK);
  EXPECT_EQ(eng.Load(Move(10, 0, 0, 0, 10000, 0)), X4_ERR_FREQ_TOO_HIGH);
  EXPECT_EQ(x4_engine_endless(&eng.e, 1, false, 10000, 0, 0), X4_ERR_FREQ_TOO_HIGH);
  EXPECT_EQ(eng.Load(Move(10, 0, 0, 0, 9090, 0)), X4_OK);
  Engine sym;
  const x4_timing space{0, 30000, 100000, 0};  // symmetric: low 25 us at 20 kHz
  ASSERT_EQ(x4_engine_configure(&sym.e, &space, X4_MODE_CLOCK_DIR), X4_OK);
  EXPECT_EQ(sym.Load(Move(10, 0, 0, 0, 20000, 0)), X4_ERR_FREQ_TOO_HIGH);
  EXPECT_EQ(sym.Load(Move(10, 0, 0, 0, 16666, 0)), X4_OK);
}

TEST(Timing, BadSettingsAreRefusedAndChangeNothing) {
  Engine eng;
  const x4_engine before = eng.e;
  const x4_timing bad[] = {
      {999, 0, 0, 0}, {1000001, 0, 0, 0}, {0, 1000001, 0, 0}, {0, 0, 1000001, 0}, {0, 0, 0, 1000001}};
  for (const auto &t : bad) EXPECT_EQ(x4_engine_configure(&eng.e, &t, X4_MODE_CLOCK_DIR), X4_ERR_PARAM_FAIL);
  const x4_timing ok{1000, 0, 0, 0};
  EXPECT_EQ(x4_engine_configure(&eng.e, &ok, 3), X4_ERR_PARAM_FAIL);
  EXPECT_EQ(std::memcmp(&before, &eng.e, sizeof before), 0);
  ASSERT_EQ(eng.Load(Move(10, 0, 0, 0, 1000, 0)), X4_OK);
  ASSERT_EQ(eng.Start(), X4_OK);
  EXPECT_EQ(x4_engine_configure(&eng.e, &ok, X4_MODE_CLOCK_DIR), X4_ERR_IS_ACTIVE);
}

// ---- SMC1500 phase drive --------------------------------------------------------

namespace {

std::vector<uint8_t> PhaseBytes(uint8_t mode, const x4_move &m) {
  Engine eng;
  const x4_timing t{0, 0, X4_DIR_SETUP_NS, 0};
  EXPECT_EQ(x4_engine_configure(&eng.e, &t, mode), X4_OK);
  EXPECT_EQ(eng.Load(m), X4_OK);
  EXPECT_EQ(eng.Start(), X4_OK);
  std::vector<uint8_t> bytes;
  for (const x4_event &ev : eng.Run().events) bytes.push_back(ev.data);
  return bytes;
}

}  // namespace

TEST(PhaseDrive, ExactByteSequenceOfAKnownMove) {
  // X +3, Y -2 interpolated: Y steps with X's steps 1 and 3.
  const std::vector<uint8_t> want = {0x03, 0x43,         // energize X, Y at phase 0
                                     0x09, 0x4d,         // X -> 1, Y -> 7
                                     0x38,               // X -> 2
                                     0x29, 0x5c,         // X -> 3, Y -> 6
                                     0x1b, 0x5b, 0x9b};  // all off at rest
  EXPECT_EQ(PhaseBytes(X4_MODE_SMC_PHASE, Move(3, -2, 0, 0, 1000, 0)), want);
}

TEST(PhaseDrive, ReducedHoldingCurrentAtRest) {
  const std::vector<uint8_t> got = PhaseBytes(X4_MODE_SMC_PHASE_HOLD, Move(3, -2, 0, 0, 1000, 0));
  ASSERT_EQ(got.size(), 10u);
  // X at phase 3 (0x29: 20 %/20 % stays), Y at 6 (0x1c: 100 % -> 20 %), Z at 0 (0x03: 100 % -> 20 %).
  EXPECT_EQ(std::vector<uint8_t>(got.end() - 3, got.end()), (std::vector<uint8_t>{0x29, 0x5d, 0x8b}));
}

TEST(PhaseDrive, WalksTheTableBothWaysAndKeepsThePhase) {
  Engine eng;
  const x4_timing t{0, 0, 0, 0};
  ASSERT_EQ(x4_engine_configure(&eng.e, &t, X4_MODE_SMC_PHASE), X4_OK);
  ASSERT_EQ(eng.Load(Move(0, 0, 11, 0, 2000, 5)), X4_OK);  // Z forward 11 (ramps run as usual)
  ASSERT_EQ(eng.Start(), X4_OK);
  Recording r = eng.Run();
  EXPECT_EQ(eng.e.smc_phase[2], 11 % 8);
  EXPECT_EQ(r.events[r.events.size() - 4].data, 0x29 | 0x80);  // last step: entry 3, Z selected
  ASSERT_EQ(eng.Load(Move(0, 0, -11, 0, 2000, 5)), X4_OK);
  ASSERT_EQ(x4_engine_start(&eng.e, r.events.back().t_ns), X4_OK);
  eng.Run();
  EXPECT_EQ(eng.e.smc_phase[2], 0);
  EXPECT_EQ(eng.Load(Move(0, 0, 0, 5, 1000, 0)), X4_ERR_PARAM_FAIL) << "no fourth motor";
  EXPECT_EQ(x4_engine_endless(&eng.e, 4, false, 1000, 0, 0), X4_ERR_PARAM_FAIL);
}
