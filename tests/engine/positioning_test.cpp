// SPDX-License-Identifier: GPL-2.0
// Unit tests of the engine's positioning (issue 8, the ProStep4 model):
// asymmetric profiles, absolute coordinates, independent axes, limit
// switches and reference runs. The profile reference is written from the
// physics in double precision, not from the engine's integer formulas; the
// switches come from a small simulated machine that counts the step and
// direction edges the engine emits.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <random>
#include <string>

#include "engine_ref.h"

using namespace x4test;

namespace {

constexpr uint64_t kStart = 1000;                       // engine time of the first command
constexpr uint64_t kOrigin = kStart + X4_DIR_SETUP_NS;  // its step 0
// Edge times against the double-precision physics. The engine computes
// every time from the step index in integer ns (floors of sqrt and
// divisions): it achieves <= 2 ns on the moves run here and <= 12 ns on
// the sampled ramps of up to an hour (each test prints its "max error").
// The bounds are that plus a margin: an edge a few hundred ns off fails
// the physics, not only an interval test.
constexpr double kTolNs = 20;
constexpr double kLongTolNs = 32;  // ramps of minutes to an hour, sampled

using Targets = std::array<int32_t, X4_AXES>;

x4_profile Prof(uint32_t v0, uint32_t ve, uint32_t vm, uint32_t a0, uint32_t ae) {
  return {v0, ve, vm, a0, ae};
}

std::string Str(const x4_profile &p) {
  char s[96];
  std::snprintf(s, sizeof s, "v0=%u ve=%u vm=%u a0=%u ae=%u", p.v0, p.ve, p.vm, p.a0, p.ae);
  return s;
}

// ---- the physics of a profile move -----------------------------------------

// A move of `steps` steps (d = steps - 1 intervals): s(t) = v0 t + a0 t^2 / 2
// from the start, cruise at vm, the end mirrored: ve with ae. The shapes of
// plan_prof's comment: trapezoid; triangle (turn where the ramps meet);
// too short to brake from v0 to ve (start at the speed from which the ramp
// just reaches ve, brake all the way); too short to accelerate to ve
// (accelerate all the way). A side with a = 0 has no ramp: it runs at vm.
class ProfileRef {
 public:
  enum Shape { kTrapezoid, kTriangle, kBrakeOnly, kAccelOnly };

  ProfileRef(const x4_profile &p, uint64_t steps) {
    vm_ = p.vm;
    a0_ = p.a0;
    ae_ = p.ae;
    v0_ = a0_ ? p.v0 : vm_;
    ve_ = ae_ ? p.ve : vm_;
    d_ = double(steps - 1);
    sa_ = a0_ ? (vm_ * vm_ - v0_ * v0_) / (2 * a0_) : 0;
    sd_ = ae_ ? (vm_ * vm_ - ve_ * ve_) / (2 * ae_) : 0;
    vp_ = vm_;
    shape_ = kTrapezoid;
    if (d_ < sa_ + sd_) {
      const double vp2 = a0_ && ae_ ? (ae_ * (v0_ * v0_ + 2 * a0_ * d_) + a0_ * ve_ * ve_) / (a0_ + ae_) : 0;
      if (!a0_ || (ae_ && vp2 < v0_ * v0_)) {
        shape_ = kBrakeOnly;
        v0_ = vp_ = std::sqrt(ve_ * ve_ + 2 * ae_ * d_);
        sa_ = 0;
        sd_ = d_;
      } else if (!ae_ || vp2 < ve_ * ve_) {
        shape_ = kAccelOnly;
        ve_ = vp_ = std::sqrt(v0_ * v0_ + 2 * a0_ * d_);
        sa_ = d_;
        sd_ = 0;
      } else {
        shape_ = kTriangle;
        vp_ = std::sqrt(vp2);
        sa_ = (vp2 - v0_ * v0_) / (2 * a0_);
        sd_ = d_ - sa_;
      }
    }
    ta_ = HasAcc() ? (vp_ - v0_) / a0_ : 0;
    const double td = HasDec() ? (vp_ - ve_) / ae_ : 0;
    t_end_ = ta_ + (d_ - sa_ - sd_) / vm_ + td;
  }

  Shape shape() const { return shape_; }
  double d() const { return d_; }

  // Ideal time of step n in seconds, step 0 at 0.
  double Time(uint64_t n) const {
    const double x = double(n);
    if (HasAcc() && x <= sa_) return (std::sqrt(v0_ * v0_ + 2 * a0_ * x) - v0_) / a0_;
    if (HasDec() && d_ - x <= sd_) return t_end_ - (std::sqrt(ve_ * ve_ + 2 * ae_ * (d_ - x)) - ve_) / ae_;
    return ta_ + (x - sa_) / vm_;
  }

  // The speed at position x (in steps from step 0), steps/s.
  double Speed(double x) const {
    if (HasAcc() && x <= sa_) return std::sqrt(v0_ * v0_ + 2 * a0_ * x);
    if (HasDec() && d_ - x <= sd_) return std::sqrt(ve_ * ve_ + 2 * ae_ * (d_ - x));
    return vm_;
  }

  // The speed of the interval from step n to n + 1, steps/s.
  double IntervalSpeed(uint64_t n) const { return 1 / (Time(n + 1) - Time(n)); }

  // The X4_AX_ACCEL/CRUISE/DECEL bits step n may show (both at a boundary;
  // any for a single step).
  uint32_t Bits(uint64_t n) const {
    const double x = double(n);
    uint32_t b = d_ == 0 ? X4_AX_ACCEL | X4_AX_CRUISE | X4_AX_DECEL : 0;
    if (HasAcc() && x <= sa_) b |= X4_AX_ACCEL;
    if (HasDec() && d_ - x <= sd_) b |= X4_AX_DECEL;
    if (shape_ == kTrapezoid && x >= sa_ && d_ - x >= sd_) b |= X4_AX_CRUISE;
    return b;
  }

 private:
  bool HasAcc() const { return a0_ > 0 && sa_ > 0; }
  bool HasDec() const { return ae_ > 0 && sd_ > 0; }

  double v0_, ve_, vm_, a0_, ae_, d_, sa_, sd_, vp_, ta_, t_end_;
  Shape shape_;
};

// Prints a test's largest edge-time error, for the record, and checks it.
void ExpectEdgeError(double err_ns, const std::string &what, double tol_ns = kTolNs) {
  std::printf("[ edges    ] %-90s max error %6.1f ns\n", what.c_str(), err_ns);
  EXPECT_LT(err_ns, tol_ns) << what;
}

// The largest |edge - ideal| of rising edges `rises` of a move whose step 0
// is due at `origin`.
double MaxErrorNs(const ProfileRef &ref, const std::vector<uint64_t> &rises, uint64_t origin) {
  double worst = 0;
  for (size_t n = 0; n < rises.size(); n++)
    worst = std::max(worst, std::fabs(double(rises[n] - origin) - ref.Time(n) * 1e9));
  return worst;
}

// ---- a machine behind the port -------------------------------------------------

// A switch of the simulated machine: active while lo <= axis position <= hi.
struct Switch {
  int axis;   // 0-based
  int input;  // 1..5
  int64_t lo, hi;
};

// The engine with a machine attached: the machine counts each axis' rising
// clock edges with the direction level into its own position, and drives
// the inputs from its switches (NO: HIGH while active, NC: LOW). The
// inputs are sensed before every event, as the glue does on every tick.
class Rig {
 public:
  x4_engine e;
  int64_t machine[X4_AXES] = {};  // physical positions, from the edges
  std::vector<Switch> switches;
  uint8_t nc_wiring = 0;  // bit k: input k + 1 is wired normally closed
  uint64_t now = kStart;  // time of the last event: when commands are given
  // Ticks at which the active inputs changed (the first tick seeing it).
  std::vector<std::pair<uint64_t, uint8_t>> seen;

  Rig() {
    x4_engine_init(&e);
    data_ = e.data;
  }

  uint8_t Active() const {
    uint8_t bits = 0;
    for (const Switch &s : switches)
      if (machine[s.axis] >= s.lo && machine[s.axis] <= s.hi) bits |= uint8_t(1u << (s.input - 1));
    return bits;
  }

  void Sense() {
    const uint8_t active = Active();
    if (seen.empty() || seen.back().second != active)
      seen.push_back({x4_engine_busy(&e) ? e.due : now, active});
    x4_switch_sense(&e, active ^ nc_wiring);
  }

  // The first tick from which input (1..5) was seen active, 0: never.
  uint64_t FirstActive(int input) const {
    for (const auto &s : seen)
      if (s.second & (1u << (input - 1))) return s.first;
    return 0;
  }

  int SetSwitches(x4_switches sw) {
    sw.nc = nc_wiring;
    return x4_switch_set(&e, &sw);
  }
  int SetProfile(int axis, const x4_profile &p) { return x4_engine_set_profile(&e, axis + 1, &p); }
  int SetPosition(uint8_t axes, const Targets &pos) { return x4_engine_set_position(&e, axes, pos.data()); }
  int Goto(uint8_t axes, const Targets &target, bool relative = false) {
    Sense();
    return x4_engine_goto(&e, axes, target.data(), relative, now);
  }
  int GotoAxis(int axis, int32_t target, bool relative = false) {
    Targets t{};
    t[axis] = target;
    return Goto(uint8_t(1u << axis), t, relative);
  }
  int Home(int axis, uint8_t phases, int32_t vref1, int32_t vref2, uint32_t sref) {
    Sense();
    return x4_switch_home(&e, axis + 1, phases, vref1, vref2, sref, now);
  }
  int Start(const x4_move &m) {
    Sense();
    const int ret = x4_engine_load(&e, &m);
    return ret ? ret : x4_engine_start(&e, now);
  }

  x4_axis_state Axis(int axis) const {
    x4_axis_state st;
    x4_status_axis(&e, axis, &st);
    return st;
  }

  // Fire until idle (or max_events); `after_event` runs after each event.
  Recording Run(size_t max_events = SIZE_MAX, const std::function<void()> &after_event = nullptr) {
    Recording r;
    bool first = true;
    const auto settle = [&] {
      Track();
      if (!first && after_event) after_event();
      first = false;
    };
    record(e, r, max_events, [&] {
      settle();
      Sense();
    });
    settle();
    if (!r.events.empty()) now = r.events.back().t_ns;
    return r;
  }

 private:
  void Track() {
    const uint8_t rose = e.data & ~data_ & X4_CLK_MASK;
    for (int i = 0; i < X4_AXES; i++)
      if (rose & X4_CLK_BIT(i)) machine[i] += (e.data & X4_DIR_BIT(i)) ? 1 : -1;
    data_ = e.data;
  }

  uint8_t data_;
};

x4_switches NoSwitches() {
  x4_switches sw;
  std::memset(&sw, 0, sizeof sw);
  return sw;
}

// Intervals between consecutive edges.
std::vector<int64_t> Intervals(const std::vector<uint64_t> &t, size_t from = 0, size_t to = SIZE_MAX) {
  std::vector<int64_t> iv;
  for (size_t i = std::max<size_t>(from, 1); i < std::min(to, t.size()); i++)
    iv.push_back(int64_t(t[i] - t[i - 1]));
  return iv;
}

}  // namespace

// ---- 1. asymmetric profile timing ---------------------------------------------

namespace {

struct ProfileCase {
  const char *name;
  x4_profile p;
  uint32_t steps;
  ProfileRef::Shape shape;
};

const ProfileCase kProfileCases[] = {
    {"trapezoid", Prof(500, 200, 5000, 20000, 8000), 10000, ProfileRef::kTrapezoid},
    {"trapezoid from/to rest", Prof(0, 0, 2000, 4000, 4000), 3000, ProfileRef::kTrapezoid},
    {"triangle", Prof(100, 300, 20000, 10000, 30000), 2000, ProfileRef::kTriangle},
    {"tiny triangle", Prof(0, 0, 1000, 1000, 3000), 5, ProfileRef::kTriangle},
    // sa + sd = 260.87 + 231.88 = 492.75 > d = 492, where rounding either
    // ramp down would make room for vm.
    {"triangle a step short of vm", Prof(0, 0, 2043, 8000, 9000), 493, ProfileRef::kTriangle},
    {"too short to brake from v0", Prof(5000, 100, 10000, 5000, 2000), 3000, ProfileRef::kBrakeOnly},
    {"too short to reach ve", Prof(100, 5000, 10000, 2000, 5000), 3000, ProfileRef::kAccelOnly},
    {"a0 = 0", Prof(700, 0, 3000, 0, 6000), 2000, ProfileRef::kTrapezoid},
    {"ae = 0", Prof(0, 900, 3000, 6000, 0), 2000, ProfileRef::kTrapezoid},
    {"a0 = ae = 0", Prof(0, 0, 7000, 0, 0), 500, ProfileRef::kTrapezoid},
    {"a0 = 0, too short to brake", Prof(0, 100, 3000, 0, 6000), 300, ProfileRef::kBrakeOnly},
    {"ae = 0, too short, v0 = 0", Prof(0, 0, 3000, 6000, 0), 300, ProfileRef::kAccelOnly},
    {"single step", Prof(300, 100, 1000, 1000, 1000), 1, ProfileRef::kBrakeOnly},
    {"long ramps (10 s, sh > 0)", Prof(0, 0, 1000, 100, 100), 12000, ProfileRef::kTrapezoid},
    {"long ramps, v0 and ve", Prof(150, 40, 1000, 90, 110), 11000, ProfileRef::kTrapezoid},
    {"45000 steps/s", Prof(1000, 2000, 45000, 400000, 300000), 20000, ProfileRef::kTrapezoid},
    {"45000 steps/s, no ramps", Prof(0, 0, 45000, 0, 0), 5000, ProfileRef::kTrapezoid},
    {"45000 steps/s triangle, 1e6 steps/s^2", Prof(0, 0, 45000, 1000000, 1000000), 1500,
     ProfileRef::kTriangle},
    {"brake only, ramp of 3461 s (sh = 11)", Prof(0, 0, 45000, 0, 13), 20000, ProfileRef::kBrakeOnly},
    {"accelerate only from v0, 3461 s ramp", Prof(700, 45000, 45000, 13, 13), 20000, ProfileRef::kAccelOnly},
    // X4_VEL_MAX (issue 18)
    {"100000 steps/s", Prof(1000, 2000, 100000, 1000000, 800000), 40000, ProfileRef::kTrapezoid},
    {"100000 steps/s triangle, 1e6 steps/s^2", Prof(0, 0, 100000, 1000000, 1000000), 6000,
     ProfileRef::kTriangle},
    {"brake only from 100000, ramp of 3571 s", Prof(0, 0, 100000, 0, 28), 20000, ProfileRef::kBrakeOnly},
};

struct ProfileRun {
  Recording rec;
  std::vector<x4_axis_state> after_rise;    // the axis' state after each rising edge
  std::vector<x4_axis_state> after_fall;    // ... and after each falling edge
  std::vector<x4_axis_state> before_first;  // after each event before the first step, in a ramp phase
};

// A goto of `steps` steps on `axis` with profile p, from coordinate 0.
ProfileRun RunProfile(const x4_profile &p, uint32_t steps, int axis = 0) {
  Rig rig;
  ProfileRun out;
  EXPECT_EQ(rig.SetProfile(axis, p), X4_OK) << Str(p);
  EXPECT_EQ(rig.GotoAxis(axis, int32_t(steps)), X4_OK) << Str(p);
  uint8_t prev = rig.e.data;
  out.rec = rig.Run(SIZE_MAX, [&] {
    const uint8_t clk = rig.e.data & X4_CLK_BIT(axis);
    if (clk != (prev & X4_CLK_BIT(axis))) (clk ? out.after_rise : out.after_fall).push_back(rig.Axis(axis));
    const x4_axis_state st = rig.Axis(axis);
    if (out.after_rise.empty() && (st.state & (X4_AX_ACCEL | X4_AX_CRUISE | X4_AX_DECEL)))
      out.before_first.push_back(st);
    prev = rig.e.data;
  });
  EXPECT_EQ(rig.Axis(axis).position, int32_t(steps));
  return out;
}

}  // namespace

namespace {

constexpr int kOverlap = -1;  // a plan whose ramps overlap: no shape

// The shape the engine planned for a goto of `steps` steps, from its plan:
// leader step n accelerates while n < n_cruise, brakes from n_decel on and
// cruises in between (x4_engine.h, struct x4_plan).
int PlannedShape(const x4_profile &p, uint32_t steps) {
  x4_engine e;
  x4_engine_init(&e);
  EXPECT_EQ(x4_engine_set_profile(&e, 1, &p), X4_OK);
  const int32_t target[X4_AXES] = {int32_t(steps)};
  x4_goto g;
  EXPECT_EQ(x4_engine_plan_goto(&e, 0x1, target, true, &g), X4_OK);
  const x4_plan &plan = g.plan[0];
  EXPECT_EQ(plan.last, steps - 1u);
  if (plan.n_decel == 0) return ProfileRef::kBrakeOnly;
  if (plan.n_cruise > plan.last && plan.n_decel > plan.last) return ProfileRef::kAccelOnly;
  if (plan.n_cruise == plan.n_decel) return ProfileRef::kTriangle;
  return plan.n_cruise < plan.n_decel ? ProfileRef::kTrapezoid : kOverlap;
}

}  // namespace

TEST(ProfileTiming, ReferenceShapesAreTheIntendedOnes) {
  // Each case of the table exercises the shape its name says, in the
  // physics and in the engine's plan.
  for (const auto &c : kProfileCases) {
    EXPECT_EQ(ProfileRef(c.p, c.steps).shape(), c.shape) << c.name << ": the reference";
    EXPECT_EQ(PlannedShape(c.p, c.steps), c.shape) << c.name << ": the engine's plan";
  }
}

TEST(ProfileTiming, EveryRisingEdgeMatchesThePhysics) {
  for (const auto &c : kProfileCases) {
    const ProfileRun run = RunProfile(c.p, c.steps);
    const auto &rises = run.rec.rises[0];
    ASSERT_EQ(rises.size(), c.steps) << c.name;
    const double err = MaxErrorNs(ProfileRef(c.p, c.steps), rises, kOrigin);
    ExpectEdgeError(err, std::string(c.name) + ", " + Str(c.p) + ", " + std::to_string(c.steps) + " steps");
  }
}

TEST(ProfileTiming, FirstIntervalFollowsV0AndA0) {
  // T(1) = (sqrt(v0^2 + 2 a0) - v0) / a0: v0 is the speed at step 0, not
  // the first interval's average (which would be 1 / v0).
  const struct {
    x4_profile p;
    uint32_t steps;
  } cases[] = {{Prof(500, 0, 5000, 20000, 8000), 3000},
               {Prof(0, 0, 2000, 4000, 4000), 2000},
               {Prof(3000, 0, 6000, 1000, 1000), 32000},
               {Prof(40, 0, 1000, 10, 10), 100000}};
  for (const auto &c : cases) {
    ASSERT_EQ(ProfileRef(c.p, c.steps).shape(), ProfileRef::kTrapezoid) << Str(c.p);
    const ProfileRun run = RunProfile(c.p, c.steps);
    const double ideal = (std::sqrt(double(c.p.v0) * c.p.v0 + 2.0 * c.p.a0) - c.p.v0) / c.p.a0 * 1e9;
    ExpectEdgeError(std::fabs(double(run.rec.rises[0][1] - run.rec.rises[0][0]) - ideal),
                    "first interval, " + Str(c.p));
  }
  // a0 = 0: at vm from the first step, whatever v0 says.
  const ProfileRun flat = RunProfile(Prof(100, 0, 4000, 0, 4000), 3000);
  EXPECT_NEAR(double(flat.rec.rises[0][1] - flat.rec.rises[0][0]), 250000, 1);
}

TEST(ProfileTiming, LastIntervalEndsAtVe) {
  const struct {
    x4_profile p;
    uint32_t steps;
  } cases[] = {{Prof(0, 2000, 5000, 20000, 8000), 3000},
               {Prof(0, 800, 2000, 4000, 500), 5000},
               {Prof(0, 0, 2000, 4000, 4000), 3000},
               {Prof(0, 9000, 10000, 10000, 10000), 7000}};
  for (const auto &c : cases) {
    const x4_profile &p = c.p;
    ASSERT_EQ(ProfileRef(p, c.steps).shape(), ProfileRef::kTrapezoid) << Str(p);
    const ProfileRun run = RunProfile(p, c.steps);
    const auto &t = run.rec.rises[0];
    const double last = double(t.back() - t[t.size() - 2]);
    const double ideal = (std::sqrt(double(p.ve) * p.ve + 2.0 * p.ae) - p.ve) / p.ae * 1e9;
    ExpectEdgeError(std::fabs(last - ideal), "last interval, " + Str(p));
    if (p.ve * p.ve > 100 * p.ae) {
      EXPECT_NEAR(1e9 / last, p.ve, p.ve * 0.01) << "the last interval runs at about ve";
    }
  }
}

TEST(ProfileTiming, CruiseRunsAtVm) {
  const ProfileRun run = RunProfile(Prof(0, 0, 8000, 40000, 40000), 6000);  // ramps of 800 steps
  for (int64_t iv : Intervals(run.rec.rises[0], 1000, 5000)) ASSERT_NEAR(iv, 125000, 1);
}

TEST(ProfileTiming, LongRampsSampledAtTheLimits) {
  // Ramps up to X4_RAMP_TIME_MAX_S (3600 s): too long to run here, so the
  // planned times are sampled directly (ramp ends, cruise, random steps).
  // With v0 or ve > 0 these need the ramp's rest offset s = v / a to well
  // under a microsecond, though plan_ramp keeps it in units of 2^sh ns.
  const struct {
    x4_profile p;
    uint32_t steps;
  } cases[] = {
      {Prof(0, 0, 45000, 13, 13), 200000000},        // 3461 s ramps, trapezoid
      {Prof(1000, 500, 45000, 13, 20), 160000000},   // v0, ve on 3461 s and 2250 s ramps
      {Prof(0, 0, 3600, 1, 1), 20000000},            // a = 1, ramp 3600 s
      {Prof(2000, 1000, 40000, 12, 12), 150000000},  // 3333 s ramps (sh = 11), v0 and ve
      {Prof(0, 7, 45000, 15, 13), 4000000000u},      // 4e9 steps, absolute goto range
      {Prof(0, 0, 100000, 28, 28), 400000000},       // X4_VEL_MAX on 3571 s ramps
      {Prof(1000, 500, 100000, 28, 50), 300000000},  // ... v0, ve, 2000 s down
      {Prof(0, 7, 100000, 30, 28), 4000000000u},     // ... 4e9 steps
  };
  for (const auto &c : cases) {
    Rig rig;
    ASSERT_EQ(rig.SetProfile(0, c.p), X4_OK) << Str(c.p);
    ASSERT_EQ(rig.SetPosition(1, {int32_t(-2000000000)}), X4_OK);
    ASSERT_EQ(rig.GotoAxis(0, int32_t(-2000000000 + int64_t(c.steps))), X4_OK) << Str(c.p);
    const x4_plan &plan = rig.e.ch[0].run;
    ASSERT_EQ(plan.abs_steps[0], c.steps);
    const ProfileRef ref(c.p, c.steps);
    std::mt19937_64 rng(c.steps);
    double worst = 0;
    for (int i = 0; i < 30000; i++) {
      const uint64_t n = i < 1000 ? i : i < 2000 ? c.steps - 1 - (i - 1000) : rng() % c.steps;
      worst = std::max(worst, std::fabs(double(x4_plan_time(&plan, n)) - ref.Time(n) * 1e9));
    }
    ExpectEdgeError(worst, "sampled, " + Str(c.p) + ", " + std::to_string(c.steps) + " steps", kLongTolNs);
    x4_engine_stop(&rig.e);
  }
}

TEST(ProfileTiming, StateBitsAtTheRightSteps) {
  for (const auto &c : kProfileCases) {
    if (c.steps > 20000) continue;
    const ProfileRef ref(c.p, c.steps);
    const ProfileRun run = RunProfile(c.p, c.steps);
    ASSERT_EQ(run.after_rise.size(), c.steps) << c.name;
    for (uint64_t n = 0; n < c.steps; n++) {
      const x4_axis_state &st = run.after_rise[n];
      const uint32_t bits = st.state & (X4_AX_ACCEL | X4_AX_CRUISE | X4_AX_DECEL);
      ASSERT_TRUE(st.state & X4_AX_RUN) << c.name << " step " << n;
      ASSERT_EQ(__builtin_popcount(bits), 1) << c.name << " step " << n << " state " << st.state;
      ASSERT_TRUE(bits & ref.Bits(n))
          << c.name << " step " << n << " state 0x" << std::hex << st.state << " allowed 0x" << ref.Bits(n);
    }
  }
}

TEST(ProfileTiming, VelocityWhileTheClockIsHigh) {
  // After step n rose, the axis runs the interval n .. n + 1 (the last
  // step: the interval before it). The reported speed lies between the
  // speeds of the neighbouring intervals (1 % for the integer division).
  for (const auto &c : kProfileCases) {
    if (c.steps < 3 || c.steps > 20000) continue;
    const ProfileRef ref(c.p, c.steps);
    const ProfileRun run = RunProfile(c.p, c.steps);
    for (uint64_t n = 0; n < c.steps; n++) {
      const double lo_n = n ? n - 1 : 0, hi_n = std::min<double>(n + 1, c.steps - 2);
      double lo = 1e18, hi = 0;
      for (double j = lo_n; j <= hi_n; j++) {
        lo = std::min(lo, ref.IntervalSpeed(uint64_t(j)));
        hi = std::max(hi, ref.IntervalSpeed(uint64_t(j)));
      }
      const double v = run.after_rise[n].velocity;
      ASSERT_TRUE(v >= lo * 0.99 - 1 && v <= hi * 1.01 + 1)
          << c.name << " step " << n << ": " << v << " not in [" << lo << ", " << hi << "]";
    }
  }
}

TEST(ProfileTiming, VelocityWhileTheClockIsLow) {
  // Between the clock's fall after step n and step n + 1 the axis still
  // runs at the speed of that interval: the status must not read 0 half
  // of the time.
  const x4_profile p = Prof(500, 200, 5000, 20000, 8000);
  const ProfileRef ref(p, 4000);
  const ProfileRun run = RunProfile(p, 4000);
  ASSERT_EQ(run.after_fall.size(), 4000u);
  int zero = 0, wrong = 0;
  for (uint64_t n = 0; n + 1 < 4000; n++) {
    const double v = run.after_fall[n].velocity;
    const double lo = std::min(ref.IntervalSpeed(n ? n - 1 : 0), ref.IntervalSpeed(n));
    const double hi =
        std::max(ref.IntervalSpeed(n ? n - 1 : 0), ref.IntervalSpeed(std::min<uint64_t>(n + 1, 3998)));
    zero += v == 0;
    if (!(v >= lo * 0.99 - 1 && v <= hi * 1.01 + 1) && wrong++ < 3) {
      ADD_FAILURE() << "after the fall of step " << n << ": " << v << " not in [" << lo << ", " << hi << "]";
    }
  }
  EXPECT_EQ(zero, 0) << "of 3999 falls, after which the running axis reported velocity 0";
  EXPECT_EQ(wrong, 0);
}

TEST(ProfileTiming, VelocityBeforeTheFirstStep) {
  // From the end of the direction setup to the first step the axis is in
  // its first interval already: the speed it starts with, not 0.
  for (const auto &c : kProfileCases) {
    if (c.steps < 2 || c.steps > 20000) continue;
    const ProfileRef ref(c.p, c.steps);
    const ProfileRun run = RunProfile(c.p, c.steps);
    ASSERT_FALSE(run.before_first.empty()) << c.name << ": no event between the setup and the first step";
    const double want = ref.IntervalSpeed(0);
    for (const x4_axis_state &st : run.before_first) {
      ASSERT_TRUE(st.velocity >= want * 0.99 - 1 && st.velocity <= want * 1.01 + 1)
          << c.name << ": " << st.velocity << " before the first step, want " << want;
    }
  }
}

TEST(ProfileTiming, NoDecelerationRampShortMoveFromV0) {
  // ae = 0 (stop at full speed) and too short to reach vm: accelerate all
  // the way from v0 and stop. With v0 > 0 as with v0 = 0.
  for (const x4_profile &p : {Prof(200, 0, 3000, 6000, 0), Prof(0, 0, 3000, 6000, 0)}) {
    const ProfileRef ref(p, 300);
    ASSERT_EQ(ref.shape(), ProfileRef::kAccelOnly);
    // A rig that ran a braking move before, as a machine would have.
    Rig rig;
    ASSERT_EQ(rig.SetProfile(0, Prof(0, 0, 1000, 1000, 1000)), X4_OK);
    ASSERT_EQ(rig.GotoAxis(0, -2000), X4_OK);
    rig.Run();
    ASSERT_EQ(rig.SetProfile(0, p), X4_OK);
    const uint64_t origin = rig.now + X4_DIR_SETUP_NS;
    ASSERT_EQ(rig.GotoAxis(0, 300, true), X4_OK);
    std::vector<uint32_t> bits;
    uint8_t prev = rig.e.data;
    const Recording r = rig.Run(SIZE_MAX, [&] {
      if ((rig.e.data & ~prev) & X4_CLK_BIT(0)) bits.push_back(rig.Axis(0).state);
      prev = rig.e.data;
    });
    ASSERT_EQ(r.rises[0].size(), 300u) << Str(p);
    ExpectEdgeError(MaxErrorNs(ref, r.rises[0], origin), "accelerate only, " + Str(p));
    EXPECT_EQ(bits[0] & (X4_AX_ACCEL | X4_AX_CRUISE | X4_AX_DECEL), uint32_t(X4_AX_ACCEL)) << Str(p);
    EXPECT_EQ(bits[299] & (X4_AX_ACCEL | X4_AX_CRUISE | X4_AX_DECEL), uint32_t(X4_AX_ACCEL)) << Str(p);
  }
}

TEST(ProfileTiming, TrianglesOfSlowRamps) {
  // Where the ramps meet, vp^2 = (ae (v0^2 + 2 a0 d) + a0 ve^2) / (a0 + ae),
  // and the time to get there, (vp - v0) / a0, are needed to well under a
  // microsecond also for small accelerations.
  const ProfileRef slow(Prof(0, 0, 45000, 50, 70), 30000);
  ASSERT_EQ(slow.shape(), ProfileRef::kTriangle);
  const ProfileRun run = RunProfile(Prof(0, 0, 45000, 50, 70), 30000);
  ASSERT_EQ(run.rec.rises[0].size(), 30000u);
  ExpectEdgeError(MaxErrorNs(slow, run.rec.rises[0], kOrigin),
                  "slow triangle, " + Str(Prof(0, 0, 45000, 50, 70)));
  // a = 1 and 2 (sampled: the move takes an hour).
  const x4_profile p = Prof(100, 0, 3600, 1, 2);
  const ProfileRef ref(p, 2000000);
  ASSERT_EQ(ref.shape(), ProfileRef::kTriangle);
  Rig rig;
  ASSERT_EQ(rig.SetProfile(0, p), X4_OK);
  ASSERT_EQ(rig.GotoAxis(0, 2000000), X4_OK);
  double worst = 0;
  for (uint64_t n = 0; n < 2000000; n += 997)
    worst = std::max(worst, std::fabs(double(x4_plan_time(&rig.e.ch[0].run, n)) - ref.Time(n) * 1e9));
  ExpectEdgeError(worst, "sampled triangle, " + Str(p) + ", 2000000 steps", kLongTolNs);
}

TEST(ProfileTiming, BrakeFollowsTheDecelerationRamp) {
  // Braking from step k: the speed there (on the ramp or vm) comes down to
  // ve with ae over ceil((v^2 - ve^2) / 2 ae) more steps.
  const x4_profile p = Prof(300, 100, 4000, 10000, 5000);
  for (size_t events : {size_t(1 + 2 * 200), size_t(1 + 2 * 3000), size_t(2 * 3000)}) {
    Rig rig;
    ASSERT_EQ(rig.SetProfile(0, p), X4_OK);
    ASSERT_EQ(rig.SetPosition(1, {0}), X4_OK);
    ASSERT_EQ(rig.GotoAxis(0, 100000), X4_OK);
    Recording r = rig.Run(events);
    const uint64_t k = r.rises[0].size();  // the next step is k: braking starts there
    const double sa = (4000.0 * 4000 - 300 * 300) / 20000;
    const double v2 = k <= sa ? 300.0 * 300 + 2.0 * 10000 * k : 4000.0 * 4000;
    ASSERT_EQ(x4_engine_halt(&rig.e, 1, false), X4_OK);
    const Recording rest = rig.Run();
    const uint64_t more = uint64_t(std::ceil((v2 - 100.0 * 100) / (2 * 5000)));
    EXPECT_EQ(rest.rises[0].size(), more + 1) << "braked at step " << k;
    // The last interval runs at about ve: sqrt(ve^2 + 2 ae) - ve over ae.
    const auto &t = rest.rises[0];
    ExpectEdgeError(std::fabs(double(t.back() - t[t.size() - 2]) -
                              (std::sqrt(100.0 * 100 + 2 * 5000) - 100) / 5000 * 1e9),
                    "braked at step " + std::to_string(k) + ": last interval");
    EXPECT_TRUE(rig.Axis(0).state & X4_AX_SYNC) << "brake keeps the synchronization";
    EXPECT_EQ(rig.Axis(0).position, int32_t(k + more + 1));
  }
}

TEST(ProfileTiming, BrakeStopDistanceRoundsUp) {
  // As above, where (v^2 - ve^2) / 2 ae has a fraction (the test above
  // divides exactly): the stop takes the next whole number of steps, as
  // fewer would need more deceleration than ae. The edges say the same:
  // from the brake step to the last interval the speed falls by no more
  // than ae per second (on a ramp, an interval's speed is the ramp's speed
  // at its middle, exactly).
  const x4_profile profiles[] = {
      Prof(300, 100, 4000, 10000, 7000),   // ramps of 795.5 and 1142.14 steps
      Prof(0, 0, 3001, 7001, 6997),        // 643.19 and 643.56
      Prof(2500, 0, 9000, 40000, 33333),   // 934.38 and 1215.01
      Prof(0, 1000, 45000, 333333, 99999)  // 3037.5 and 10120.1
  };
  const uint32_t steps = 100000;
  for (const x4_profile &p : profiles) {
    const ProfileRef ref(p, steps);
    ASSERT_EQ(ref.shape(), ProfileRef::kTrapezoid);
    const uint64_t sa = (uint64_t(p.vm) * p.vm - uint64_t(p.v0) * p.v0) / (2ull * p.a0);  // whole ramp steps
    for (uint64_t k : {uint64_t(7), uint64_t(200), sa, sa + 1, uint64_t(30000)})
      for (bool fall : {false, true}) {
        SCOPED_TRACE(Str(p) + ": braked at step " + std::to_string(k) + (fall ? " (fall pending)" : ""));
        Rig rig;
        ASSERT_EQ(rig.SetProfile(0, p), X4_OK);
        ASSERT_EQ(rig.GotoAxis(0, int32_t(steps)), X4_OK);
        const Recording r = rig.Run(fall ? 2 * k : 1 + 2 * k);
        ASSERT_EQ(r.rises[0].size(), k);
        ASSERT_EQ(x4_engine_halt(&rig.e, 1, false), X4_OK);
        const Recording rest = rig.Run();
        const auto &t = rest.rises[0];  // step k, then the stop
        ASSERT_GE(t.size(), 2u);
        const uint64_t more = t.size() - 1;
        const double v = ref.Speed(double(k)), ve = p.ve;
        const double dist = (v * v - ve * ve) / (2.0 * p.ae);
        EXPECT_EQ(more, uint64_t(std::ceil(dist - 1e-9))) << "(v^2 - ve^2) / 2 ae = " << dist << " steps";
        EXPECT_LE((v * v - ve * ve) / (2.0 * more), p.ae * (1 + 1e-9)) << "the deceleration the stop needs";
        const double last_iv = double(t.back() - t[t.size() - 2]);
        const double mid = (double(t.back()) + double(t[t.size() - 2])) / 2;
        EXPECT_LE((v - 1e9 / last_iv) / ((mid - double(t[0])) * 1e-9), p.ae * (1 + 1e-6))
            << "measured on the edges";
        EXPECT_EQ(rig.Axis(0).position, int32_t(k + more + 1));
      }
  }
}

TEST(ProfileTiming, LengthsAroundTheTrapezoidLimit) {
  // A move needs sa = (vm^2 - v0^2) / 2 a0 steps to reach vm and sd =
  // (vm^2 - ve^2) / 2 ae to come down: shorter than sa + sd it turns below
  // vm. With fractions in sa and sd, the lengths around that limit against
  // the physics: every edge, and no interval faster than vm.
  const x4_profile profiles[] = {
      Prof(300, 100, 4000, 10000, 7000),   // sa + sd = 795.5 + 1142.14
      Prof(0, 0, 3001, 7001, 6997),        // 643.19 + 643.56
      Prof(2500, 0, 9000, 40000, 33333),   // 934.38 + 1215.01
      Prof(0, 0, 2043, 8000, 9000),        // 260.87 + 231.88: either rounded down fits in 492
      Prof(500, 300, 6000, 20000, 30000),  // 893.75 + 598.5
  };
  for (const x4_profile &p : profiles) {
    const double sa = (double(p.vm) * p.vm - double(p.v0) * p.v0) / (2.0 * p.a0);
    const double sd = (double(p.vm) * p.vm - double(p.ve) * p.ve) / (2.0 * p.ae);
    for (uint64_t d = uint64_t(sa) + uint64_t(sd) - 2; d <= uint64_t(sa) + uint64_t(sd) + 3; d++) {
      const uint32_t steps = uint32_t(d + 1);
      const ProfileRun run = RunProfile(p, steps);
      const auto &rises = run.rec.rises[0];
      ASSERT_EQ(rises.size(), steps) << Str(p);
      const ProfileRef ref(p, steps);
      EXPECT_LT(MaxErrorNs(ref, rises, kOrigin), kTolNs)
          << Str(p) << ", " << steps << " steps ("
          << (ref.shape() == ProfileRef::kTrapezoid ? "trapezoid" : "triangle") << ")";
      const std::vector<int64_t> iv = Intervals(rises);
      EXPECT_GE(*std::min_element(iv.begin(), iv.end()), int64_t(1e9 / p.vm) - 2)
          << Str(p) << ", " << steps << " steps";
    }
  }
}

// A plan that decided "too short for vm" with sa and sd rounded up turned,
// between sa + sd and ceil(sa) + ceil(sd) steps, where the ramps would meet,
// above vm: 2 steps of Prof(0, 0, 300, 1e6, 1e6) took 2 ms, not 3.3 ms.
TEST(ProfileTiming, ShortRampsNeverExceedVm) {
  // Ramps of a fraction of a step or a few steps (a large a for vm): a move
  // as long as sa + sd or longer has room for vm and must not pass it.
  const x4_profile profiles[] = {
      Prof(0, 0, 300, 1000000, 1000000),       // sa = sd = 0.045 steps
      Prof(0, 0, 1000, 1000000, 700000),       // 0.5 and 0.71
      Prof(200, 100, 1500, 1000000, 1000000),  // 1.1 and 1.12
      Prof(0, 0, 4500, 1000000, 1000000),      // 10.1 and 10.1
  };
  for (const x4_profile &p : profiles) {
    for (uint32_t steps = 2; steps <= 40; steps++) {
      const ProfileRun run = RunProfile(p, steps);
      const auto &rises = run.rec.rises[0];
      ASSERT_EQ(rises.size(), steps) << Str(p);
      const ProfileRef ref(p, steps);
      const std::vector<int64_t> iv = Intervals(rises);
      EXPECT_GE(*std::min_element(iv.begin(), iv.end()), int64_t(1e9 / p.vm) - 2)
          << Str(p) << ", " << steps << " steps: an interval faster than vm";
      EXPECT_LT(MaxErrorNs(ref, rises, kOrigin), kTolNs) << Str(p) << ", " << steps << " steps";
    }
  }
}

// ---- 2. coordinates and independent axes --------------------------------------------

TEST(Coordinates, GotoAbsoluteAndRelative) {
  Rig rig;
  ASSERT_EQ(rig.GotoAxis(1, 300), X4_OK);
  Recording r = rig.Run();
  EXPECT_EQ(r.rises[1].size(), 300u);
  EXPECT_EQ(rig.Axis(1).position, 300);
  EXPECT_TRUE(r.events.back().data & X4_DIR_BIT(1));
  ASSERT_EQ(rig.GotoAxis(1, -200), X4_OK);  // absolute: 500 back
  r = rig.Run();
  EXPECT_EQ(r.rises[1].size(), 500u);
  EXPECT_FALSE(r.events.back().data & X4_DIR_BIT(1));
  EXPECT_EQ(rig.Axis(1).position, -200);
  ASSERT_EQ(rig.GotoAxis(1, 50, true), X4_OK);  // relative
  r = rig.Run();
  EXPECT_EQ(r.rises[1].size(), 50u);
  EXPECT_EQ(rig.Axis(1).position, -150);
  ASSERT_EQ(rig.GotoAxis(1, -75, true), X4_OK);
  rig.Run();
  EXPECT_EQ(rig.Axis(1).position, -225);
  EXPECT_EQ(rig.machine[1], -225);
  for (int a : {0, 2, 3}) EXPECT_EQ(rig.Axis(a).position, 0);
}

TEST(Coordinates, TheLongestGotosStepOnlyTheirAxis) {
  // 2^31 and 2^32 - 1 steps: twice the step count does not fit 32 bits,
  // and the other axes (not part of the move) must still never step.
  for (const auto &c : {std::pair<int32_t, int32_t>{-(1 << 30), 1 << 30}, {INT32_MIN, INT32_MAX}}) {
    Rig rig;
    ASSERT_EQ(rig.SetProfile(1, Prof(0, 0, 45000, 0, 0)), X4_OK);
    ASSERT_EQ(rig.SetPosition(0x2, {0, c.first}), X4_OK);
    ASSERT_EQ(rig.GotoAxis(1, c.second), X4_OK);
    uint8_t other_clocks = 0;
    rig.Run(2000, [&] { other_clocks |= rig.e.data & X4_CLK_MASK & ~X4_CLK_BIT(1); });
    EXPECT_EQ(other_clocks, 0) << c.first << " -> " << c.second;
    EXPECT_EQ(rig.machine[0], 0);
    EXPECT_EQ(rig.machine[2], 0);
    EXPECT_EQ(rig.machine[3], 0);
    EXPECT_EQ(rig.machine[1], 1000) << "1000 steps in 2000 events";
    x4_engine_stop(&rig.e);
  }
}

TEST(Coordinates, GotoTheCurrentPositionDoesNothing) {
  Rig rig;
  ASSERT_EQ(rig.SetPosition(0x3, {77, 5}), X4_OK);
  ASSERT_EQ(rig.GotoAxis(0, 77), X4_OK);
  EXPECT_FALSE(x4_engine_busy(&rig.e));
  ASSERT_EQ(rig.GotoAxis(0, 0, true), X4_OK);
  EXPECT_FALSE(x4_engine_busy(&rig.e));
  // In a mask with a moving axis: only that one runs.
  ASSERT_EQ(rig.Goto(0x3, {77, 15}), X4_OK);
  const Recording r = rig.Run();
  EXPECT_TRUE(r.rises[0].empty());
  EXPECT_EQ(r.rises[1].size(), 10u);
  EXPECT_EQ(rig.Axis(0).state, uint32_t(X4_AX_SYNC));
}

TEST(Coordinates, AxesRunAtTheSameTimeEachWithItsOwnProfile) {
  Rig rig;
  const x4_profile p1 = Prof(200, 100, 4000, 20000, 10000), p3 = Prof(0, 0, 2500, 5000, 8000),
                   p4 = Prof(1000, 1000, 9000, 50000, 60000);
  ASSERT_EQ(rig.SetProfile(0, p1), X4_OK);
  ASSERT_EQ(rig.SetProfile(2, p3), X4_OK);
  ASSERT_EQ(rig.SetProfile(3, p4), X4_OK);
  ASSERT_EQ(rig.Goto(0xd, {3000, 0, -2000, 5000}), X4_OK);
  const Recording r = rig.Run();
  ASSERT_EQ(r.rises[0].size(), 3000u);
  ASSERT_EQ(r.rises[2].size(), 2000u);
  ASSERT_EQ(r.rises[3].size(), 5000u);
  ExpectEdgeError(MaxErrorNs(ProfileRef(p1, 3000), r.rises[0], kOrigin), "side by side, axis 1");
  ExpectEdgeError(MaxErrorNs(ProfileRef(p3, 2000), r.rises[2], kOrigin), "side by side, axis 3");
  ExpectEdgeError(MaxErrorNs(ProfileRef(p4, 5000), r.rises[3], kOrigin), "side by side, axis 4");
  // The events interleave: axis 3 steps between axis 1's first and last.
  const auto between = std::count_if(r.rises[2].begin(), r.rises[2].end(), [&](uint64_t t) {
    return t > r.rises[0].front() && t < r.rises[0].back();
  });
  EXPECT_GT(between, 1000);
  EXPECT_EQ(rig.Axis(0).position, 3000);
  EXPECT_EQ(rig.Axis(2).position, -2000);
  EXPECT_EQ(rig.Axis(3).position, 5000);
  for (int a = 0; a < X4_AXES; a++) EXPECT_EQ(rig.machine[a], rig.Axis(a).position) << a;
}

TEST(Coordinates, AStaggeredStartRunsAsIfAlone) {
  Rig rig;
  const x4_profile p1 = Prof(0, 0, 3000, 6000, 6000), p2 = Prof(400, 0, 7000, 30000, 15000);
  ASSERT_EQ(rig.SetProfile(0, p1), X4_OK);
  ASSERT_EQ(rig.SetProfile(1, p2), X4_OK);
  ASSERT_EQ(rig.GotoAxis(0, -4000), X4_OK);
  Recording r1 = rig.Run(1001);
  const uint64_t start2 = rig.now;
  ASSERT_EQ(rig.GotoAxis(1, 2500), X4_OK);
  EXPECT_EQ(rig.GotoAxis(0, 0), X4_ERR_IS_ACTIVE) << "a busy axis";
  const Recording r2 = rig.Run();
  r1.rises[0].insert(r1.rises[0].end(), r2.rises[0].begin(), r2.rises[0].end());
  ExpectEdgeError(MaxErrorNs(ProfileRef(p1, 4000), r1.rises[0], kOrigin), "staggered start, axis 1");
  ExpectEdgeError(MaxErrorNs(ProfileRef(p2, 2500), r2.rises[1], start2 + X4_DIR_SETUP_NS),
                  "staggered start, axis 2");
  EXPECT_EQ(rig.machine[0], -4000) << "axis 2's direction setup left axis 1's direction alone";
  EXPECT_EQ(rig.machine[1], 2500);
}

TEST(Coordinates, BusyAxesAreActiveOthersFree) {
  Rig rig;
  ASSERT_EQ(rig.SetSwitches([] {
    x4_switches sw = NoSwitches();
    sw.ref[0] = 1;
    return sw;
  }()),
            X4_OK);
  ASSERT_EQ(rig.GotoAxis(0, 5000), X4_OK);
  rig.Run(11);
  const x4_engine before = rig.e;
  EXPECT_EQ(rig.GotoAxis(0, 10), X4_ERR_IS_ACTIVE);
  EXPECT_EQ(rig.Goto(0x3, {10, 10}), X4_ERR_IS_ACTIVE) << "one busy axis refuses the whole command";
  EXPECT_EQ(rig.Home(0, X4_HOME_PHASE1 | X4_HOME_PHASE2, 100, -100, 1000), X4_ERR_IS_ACTIVE);
  EXPECT_EQ(x4_engine_endless(&rig.e, 1, false, 1000, 10, rig.now), X4_ERR_IS_ACTIVE);
  EXPECT_EQ(rig.Start(Move(10, 10, 0, 0, 1000, 0)), X4_ERR_IS_ACTIVE);
  EXPECT_EQ(x4_switch_set(&rig.e, &rig.e.sw), X4_ERR_IS_ACTIVE);
  EXPECT_EQ(std::memcmp(&before.ch, &rig.e.ch, sizeof before.ch), 0) << "nothing started";
  EXPECT_EQ(rig.GotoAxis(1, 10), X4_OK);
  const Recording r = rig.Run();
  EXPECT_EQ(r.rises[1].size(), 10u);
  EXPECT_EQ(rig.Axis(0).position, 5000);
}

TEST(Coordinates, InterpolatedMoveBesideAnIndependentOne) {
  Rig rig;
  ASSERT_EQ(rig.SetPosition(0xf, {0, 100, 200, 300}), X4_OK);
  ASSERT_EQ(rig.GotoAxis(0, 3000), X4_OK);
  Recording r = rig.Run(501);
  // Axes 2..4 are idle: X4Load/X4Start may use them.
  ASSERT_EQ(rig.Start(Move(0, 500, -300, 77, 2000, 20)), X4_OK);
  EXPECT_TRUE(rig.Axis(1).state & X4_AX_RUN);
  EXPECT_TRUE(rig.Axis(0).state & X4_AX_RUN);
  const Recording r2 = rig.Run();
  EXPECT_EQ(rig.Axis(0).position, 3000);
  EXPECT_EQ(rig.Axis(1).position, 600);
  EXPECT_EQ(rig.Axis(2).position, -100);
  EXPECT_EQ(rig.Axis(3).position, 377);
  EXPECT_EQ(r.rises[0].size() + r2.rises[0].size(), 3000u);
  EXPECT_EQ(rig.machine[1], 500);
  EXPECT_EQ(rig.machine[2], -300);
  // The interpolated move ran at its own frequency: 2 kHz in the middle.
  EXPECT_EQ(r2.rises[1][250] - r2.rises[1][249], 500000u);
}

TEST(Coordinates, InterpolatedAndEndlessMovesUpdateTheCoordinates) {
  Rig rig;
  ASSERT_EQ(rig.SetPosition(0xf, {10, 20, 30, 40}), X4_OK);
  ASSERT_EQ(rig.Start(Move(100, -50, 0, 7, 1000, 10)), X4_OK);
  rig.Run(SIZE_MAX, [&] {
    for (int a = 0; a < X4_AXES; a++) ASSERT_EQ(rig.Axis(a).position, (a + 1) * 10 + rig.machine[a]) << a;
  });
  EXPECT_EQ(rig.Axis(0).position, 110);
  EXPECT_EQ(rig.Axis(1).position, -30);
  EXPECT_EQ(rig.Axis(2).position, 30);
  EXPECT_EQ(rig.Axis(3).position, 47);
  ASSERT_EQ(x4_engine_endless(&rig.e, 2, true, 2000, 50, rig.now), X4_OK);
  const Recording r = rig.Run(1 + 2 * 700);
  ASSERT_EQ(x4_engine_brake(&rig.e), X4_OK);
  const Recording r2 = rig.Run();
  EXPECT_EQ(rig.Axis(1).position, -30 - int32_t(r.rises[1].size() + r2.rises[1].size()));
  EXPECT_EQ(rig.Axis(1).position, 20 + rig.machine[1]);
  EXPECT_EQ(rig.Axis(0).position, 110) << "X4Start's step counter reset keeps the coordinates";
}

TEST(Coordinates, WrapAround32Bits) {
  Rig rig;
  ASSERT_EQ(rig.SetPosition(1, {INT32_MAX - 2}), X4_OK);
  ASSERT_EQ(rig.GotoAxis(0, 5, true), X4_OK);
  rig.Run();
  EXPECT_EQ(rig.Axis(0).position, INT32_MIN + 2);
  ASSERT_EQ(rig.GotoAxis(0, -5, true), X4_OK);
  rig.Run();
  EXPECT_EQ(rig.Axis(0).position, INT32_MAX - 2);
  ASSERT_EQ(rig.SetPosition(1, {INT32_MIN + 1}), X4_OK);
  ASSERT_EQ(rig.Start(Move(-3, 0, 0, 0, 1000, 0)), X4_OK);
  rig.Run();
  EXPECT_EQ(rig.Axis(0).position, INT32_MAX - 1);
}

TEST(Coordinates, AbsoluteTargetsAreSignedNotModular) {
  // An absolute goto is linear in the signed coordinate: from near
  // INT32_MIN to near INT32_MAX is 2^32 - 5 steps forward, not 5 back.
  Rig rig;
  ASSERT_EQ(rig.SetProfile(0, Prof(0, 0, 1000, 0, 0)), X4_OK);
  ASSERT_EQ(rig.SetPosition(1, {INT32_MIN + 2}), X4_OK);
  ASSERT_EQ(rig.GotoAxis(0, INT32_MAX - 2), X4_OK);
  EXPECT_EQ(rig.e.ch[0].run.abs_steps[0], 0xfffffffbu);
  EXPECT_EQ(rig.e.ch[0].run.sign[0], 1);
  rig.Run(20);
  EXPECT_EQ(rig.Axis(0).position, INT32_MIN + 2 + 10);
  EXPECT_EQ(rig.machine[0], 10);
  EXPECT_TRUE(rig.e.data & X4_CLK_BIT(0)) << "clock high: step 10 runs";
  ASSERT_TRUE(x4_engine_busy(&rig.e));
  EXPECT_EQ(x4_engine_stop(&rig.e), X4_OK);
}

TEST(Coordinates, VelocityOfMovesOfAtLeast2To31Steps) {
  // Moves this long are legal (relative INT32_MIN, absolute across the
  // range); their status must still show the speed.
  const struct {
    int32_t from, target;
    bool relative;
  } cases[] = {{0, INT32_MIN, true}, {INT32_MIN + 2, INT32_MAX - 2, false}, {0, INT32_MAX, true}};
  for (const auto &c : cases) {
    Rig rig;
    ASSERT_EQ(rig.SetProfile(0, Prof(0, 0, 1000, 0, 0)), X4_OK);  // at vm from the start
    ASSERT_EQ(rig.SetPosition(1, {c.from}), X4_OK);
    ASSERT_EQ(rig.GotoAxis(0, c.target, c.relative), X4_OK);
    rig.Run(20);
    ASSERT_TRUE(rig.e.data & X4_CLK_BIT(0));
    EXPECT_EQ(rig.Axis(0).velocity, 1000u) << c.from << " -> " << c.target << (c.relative ? " relative" : "");
    x4_engine_stop(&rig.e);
  }
}

TEST(Coordinates, ProfileChangesApplyToTheNextMove) {
  Rig rig;
  const x4_profile p = Prof(0, 0, 2000, 8000, 8000);
  ASSERT_EQ(rig.SetProfile(0, p), X4_OK);
  ASSERT_EQ(rig.GotoAxis(0, 1000), X4_OK);
  Recording r = rig.Run(101);
  ASSERT_EQ(rig.SetProfile(0, Prof(0, 0, 9000, 90000, 90000)), X4_OK);
  const Recording r2 = rig.Run();
  r.rises[0].insert(r.rises[0].end(), r2.rises[0].begin(), r2.rises[0].end());
  ExpectEdgeError(MaxErrorNs(ProfileRef(p, 1000), r.rises[0], kOrigin), "profile changed while running");
}

TEST(Coordinates, HaltPerAxis) {
  Rig rig;
  const x4_profile p = Prof(0, 0, 4000, 20000, 20000);
  ASSERT_EQ(rig.SetProfile(0, p), X4_OK);
  ASSERT_EQ(rig.SetProfile(1, p), X4_OK);
  ASSERT_EQ(rig.SetPosition(0x3, {0, 0}), X4_OK);
  ASSERT_EQ(rig.Goto(0x3, {20000, -20000}), X4_OK);
  Recording r = rig.Run(4000);
  ASSERT_EQ(x4_engine_halt(&rig.e, 0x1, false), X4_OK);  // brake axis 1 only
  EXPECT_EQ(x4_engine_halt(&rig.e, 0x4, false), X4_ERR_NOT_ACTIVE);
  const Recording r2 = rig.Run();
  r.rises[1].insert(r.rises[1].end(), r2.rises[1].begin(), r2.rises[1].end());
  EXPECT_LT(rig.Axis(0).position, 20000);
  EXPECT_EQ(rig.Axis(1).position, -20000) << "axis 2 ran on";
  ExpectEdgeError(MaxErrorNs(ProfileRef(p, 20000), r.rises[1], kOrigin), "axis 2 runs on beside a brake");
  EXPECT_EQ(rig.Axis(0).state, uint32_t(X4_AX_SYNC));
  EXPECT_EQ(rig.Axis(1).state, uint32_t(X4_AX_SYNC));
  // Stop one of two running axes: the other runs on and keeps its sync.
  ASSERT_EQ(rig.Goto(0x3, {0, 0}), X4_OK);
  rig.Run(1000);
  ASSERT_EQ(x4_engine_halt(&rig.e, 0x2, true), X4_OK);
  EXPECT_FALSE(rig.Axis(1).state & (X4_AX_RUN | X4_AX_SYNC));
  EXPECT_EQ(rig.e.data & X4_CLK_BIT(1), 0);
  rig.Run();
  EXPECT_EQ(rig.Axis(0).position, 0);
  EXPECT_TRUE(rig.Axis(0).state & X4_AX_SYNC);
  EXPECT_EQ(rig.Axis(1).position, int32_t(rig.machine[1]));
}

// ---- 3. limit switches -------------------------------------------------------------

namespace {

constexpr int64_t kFar = INT64_MAX / 4;

// E+ of `axis` on `input` active from `at` on; E- active up to `at`.
Switch Plus(int axis, int input, int64_t at) { return {axis, input, at, kFar}; }
Switch Minus(int axis, int input, int64_t at) { return {axis, input, -kFar, at}; }

// The rises of `axis` at or after engine time t.
size_t RisesFrom(const std::vector<uint64_t> &rises, uint64_t t) {
  return size_t(rises.end() - std::lower_bound(rises.begin(), rises.end(), t));
}

// Checks the move ended on the tick it saw the switch: no step of `axis`
// from the tick the input was first seen active, and the move's end event
// at the time its next step would have been due.
void ExpectStoppedAtTheTick(const Rig &rig, const Recording &r, int axis, int input) {
  const uint64_t t_act = rig.FirstActive(input);
  ASSERT_NE(t_act, 0u) << "input " << input << " never became active";
  const auto &t = r.rises[axis];
  EXPECT_EQ(RisesFrom(t, t_act), 0u) << "steps after the input went active";
  ASSERT_GE(t.size(), 2u);
  const uint64_t last_iv = t.back() - t[t.size() - 2];
  // The next interval: shorter while accelerating, a few % longer on a brake ramp.
  EXPECT_LE(r.events.back().t_ns - t.back(), last_iv + last_iv / 20 + uint64_t(kTolNs))
      << "ended within the next step";
}

x4_switches LimitWiring(int axis, int plus_input, int minus_input) {
  x4_switches sw = NoSwitches();
  sw.plus[axis] = uint8_t(plus_input);
  sw.minus[axis] = uint8_t(minus_input);
  return sw;
}

}  // namespace

class Limits : public ::testing::TestWithParam<bool> {
 protected:
  // A machine whose axis 1 has E+ at 500 on input 3 and E- at -400 on
  // input 4, normally closed if the parameter says so.
  void SetUp() override {
    if (GetParam()) rig.nc_wiring = 0x0c;
    rig.switches = {Plus(0, 3, 500), Minus(0, 4, -400)};
    ASSERT_EQ(rig.SetSwitches(LimitWiring(0, 3, 4)), X4_OK);
    ASSERT_EQ(rig.SetProfile(0, Prof(200, 0, 6000, 30000, 30000)), X4_OK);
    ASSERT_EQ(rig.SetPosition(1, {0}), X4_OK);
  }
  Rig rig;
};

TEST_P(Limits, GotoStopsOnTheTickEPlusGoesActive) {
  ASSERT_EQ(rig.GotoAxis(0, 2000), X4_OK);
  const Recording r = rig.Run();
  EXPECT_EQ(rig.machine[0], 500) << "the step onto the switch is the last";
  EXPECT_EQ(rig.Axis(0).position, 500);
  EXPECT_EQ(rig.Axis(0).error, uint32_t(X4_AXERR_LIMIT_POS));
  EXPECT_EQ(rig.Axis(0).state, uint32_t(X4_AX_ERROR)) << "stopped, error, sync lost";
  ExpectStoppedAtTheTick(rig, r, 0, 3);
  EXPECT_EQ(r.events.back().data & X4_CLK_MASK, 0);
  EXPECT_EQ(r.events.back().ctl & X4_CTL_AKTIV, 0);
}

TEST_P(Limits, EMinusAndMovingAway) {
  ASSERT_EQ(rig.GotoAxis(0, -1000), X4_OK);
  Recording r = rig.Run();
  EXPECT_EQ(rig.machine[0], -400);
  EXPECT_EQ(rig.Axis(0).error, uint32_t(X4_AXERR_LIMIT_NEG));
  ExpectStoppedAtTheTick(rig, r, 0, 4);
  // Toward the active limit: not a single step, the error again.
  ASSERT_EQ(rig.GotoAxis(0, -450), X4_OK);
  r = rig.Run();
  EXPECT_TRUE(r.rises[0].empty());
  EXPECT_EQ(rig.Axis(0).error, uint32_t(X4_AXERR_LIMIT_NEG));
  // Away from it: the whole way, and the error is cleared.
  ASSERT_EQ(rig.GotoAxis(0, 100), X4_OK);
  EXPECT_EQ(rig.Axis(0).error, 0u) << "cleared by the next command";
  r = rig.Run();
  EXPECT_EQ(rig.machine[0], 100);
  EXPECT_EQ(rig.Axis(0).state, 0u);
}

TEST_P(Limits, InterpolatedPartnersStopToo) {
  ASSERT_EQ(rig.SetPosition(0x3, {0, 0}), X4_OK);
  ASSERT_EQ(rig.Start(Move(1000, -600, 0, 0, 3000, 20)), X4_OK);
  const Recording r = rig.Run();
  EXPECT_EQ(rig.machine[0], 500);
  EXPECT_NEAR(double(rig.machine[1]), -300, 1) << "axis 2 stopped with axis 1";
  EXPECT_EQ(rig.Axis(0).error, uint32_t(X4_AXERR_LIMIT_POS));
  EXPECT_EQ(rig.Axis(1).error, 0u) << "the partner hit nothing";
  EXPECT_FALSE(rig.Axis(1).state & X4_AX_SYNC) << "but it stopped without a ramp";
  ExpectStoppedAtTheTick(rig, r, 0, 3);
  EXPECT_EQ(RisesFrom(r.rises[1], rig.FirstActive(3)), 0u);
}

TEST_P(Limits, LimitOfAMinorAxisStopsTheLeader) {
  rig.switches.push_back(Minus(1, 5, -250));
  x4_switches sw = LimitWiring(0, 3, 4);
  sw.minus[1] = 5;
  if (GetParam()) rig.nc_wiring |= 0x10;
  ASSERT_EQ(rig.SetSwitches(sw), X4_OK);
  ASSERT_EQ(rig.Start(Move(450, -300, 0, 0, 3000, 20)), X4_OK);
  const Recording r = rig.Run();
  EXPECT_EQ(rig.machine[1], -250);
  EXPECT_NEAR(double(rig.machine[0]), 375, 1);
  EXPECT_EQ(rig.Axis(1).error, uint32_t(X4_AXERR_LIMIT_NEG));
  EXPECT_EQ(rig.Axis(0).error, 0u);
  EXPECT_EQ(RisesFrom(r.rises[0], rig.FirstActive(5)), 0u);
}

TEST_P(Limits, EndlessMoveStops) {
  ASSERT_EQ(x4_engine_endless(&rig.e, 1, false, 5000, 100, rig.now), X4_OK);
  const Recording r = rig.Run(100000);
  EXPECT_FALSE(x4_engine_busy(&rig.e));
  EXPECT_EQ(rig.machine[0], 500);
  EXPECT_EQ(rig.Axis(0).error, uint32_t(X4_AXERR_LIMIT_POS));
  ExpectStoppedAtTheTick(rig, r, 0, 3);
}

TEST_P(Limits, WiringOfTheOtherKindSeesTheSwitchAtOnce) {
  // NO switches configured as NC (or the reverse) read active at rest:
  // a move toward them never starts stepping.
  rig.nc_wiring ^= 0x0c;
  ASSERT_EQ(rig.GotoAxis(0, 100), X4_OK);
  const Recording r = rig.Run();
  EXPECT_TRUE(r.rises[0].empty());
  EXPECT_EQ(rig.Axis(0).error, uint32_t(X4_AXERR_LIMIT_POS));
}

INSTANTIATE_TEST_SUITE_P(NoNc, Limits, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool> &i) { return i.param ? "NC" : "NO"; });

namespace {

// The SMC1500 wiring: every limit switch of axes 1..3 in parallel on
// input 1 (normally closed, as a series chain of NC contacts would be).
void SharedLimits(Rig &rig) {
  rig.nc_wiring = 0x01;
  rig.switches.clear();
  x4_switches sw = NoSwitches();
  for (int a = 0; a < 3; a++) {
    rig.switches.push_back(Plus(a, 1, 300));
    rig.switches.push_back(Minus(a, 1, -300));
    sw.plus[a] = sw.minus[a] = 1;
  }
  ASSERT_EQ(rig.SetSwitches(sw), X4_OK);
  ASSERT_EQ(rig.SetPosition(0x7, {0, 0, 0}), X4_OK);
}

}  // namespace

TEST(SharedLimits, HitIsAttributedToTheMovingAxis) {
  Rig rig;
  SharedLimits(rig);
  ASSERT_EQ(rig.GotoAxis(1, 1000), X4_OK);
  const Recording r = rig.Run();
  EXPECT_EQ(rig.machine[1], 300);
  EXPECT_EQ(rig.Axis(1).error, uint32_t(X4_AXERR_LIMIT_POS)) << "one axis moved: not ambiguous";
  EXPECT_EQ(rig.Axis(0).error, 0u);
  EXPECT_EQ(rig.Axis(2).error, 0u);
  EXPECT_TRUE(rig.Axis(0).state & X4_AX_SYNC);
  EXPECT_FALSE(rig.Axis(1).state & X4_AX_SYNC);
  ExpectStoppedAtTheTick(rig, r, 1, 1);
}

TEST(SharedLimits, TwoMovingAxesAreAmbiguous) {
  Rig rig;
  SharedLimits(rig);
  ASSERT_EQ(rig.SetProfile(0, Prof(0, 0, 5000, 50000, 50000)), X4_OK);
  ASSERT_EQ(rig.SetProfile(2, Prof(0, 0, 800, 8000, 8000)), X4_OK);
  ASSERT_EQ(rig.Goto(0x5, {1000, 0, -1000, 0}), X4_OK);
  const Recording r = rig.Run();
  EXPECT_EQ(rig.machine[0], 300) << "axis 1 reached its E+";
  EXPECT_GT(rig.machine[2], -300) << "axis 3 was still on its way";
  EXPECT_EQ(rig.Axis(0).error, uint32_t(X4_AXERR_LIMIT_POS | X4_AXERR_AMBIGUOUS));
  EXPECT_EQ(rig.Axis(2).error, uint32_t(X4_AXERR_LIMIT_NEG | X4_AXERR_AMBIGUOUS));
  EXPECT_EQ(rig.Axis(1).error, 0u);
  EXPECT_EQ(RisesFrom(r.rises[0], rig.FirstActive(1)), 0u);
  EXPECT_EQ(RisesFrom(r.rises[2], rig.FirstActive(1)), 0u);
  EXPECT_FALSE(rig.Axis(0).state & X4_AX_SYNC);
  EXPECT_FALSE(rig.Axis(2).state & X4_AX_SYNC);
}

namespace {

// Axis 2 of the shared wiring, stopped at its E+ (input 1 active).
void HitSharedPlus(Rig &rig) {
  SharedLimits(rig);
  ASSERT_EQ(rig.GotoAxis(1, 1000), X4_OK);
  rig.Run();
  ASSERT_EQ(rig.machine[1], 300);
  ASSERT_EQ(rig.Axis(1).error, uint32_t(X4_AXERR_LIMIT_POS));
}

}  // namespace

TEST(SharedLimits, BackingOffWithAnInterpolatedMove) {
  Rig rig;
  HitSharedPlus(rig);
  // Backing off in the opposite direction: E- is the same, active input.
  ASSERT_EQ(rig.Start(Move(0, -400, 0, 0, 2000, 0)), X4_OK);
  rig.Run();
  EXPECT_EQ(rig.machine[1], -100);
  EXPECT_EQ(rig.Axis(1).error, 0u);
}

TEST(SharedLimits, BackingOffWithAnEndlessMoveThenE_MinusArms) {
  Rig rig;
  HitSharedPlus(rig);
  ASSERT_EQ(x4_engine_endless(&rig.e, 2, true, 2000, 0, rig.now), X4_OK);
  const Recording r = rig.Run(100000);
  EXPECT_FALSE(x4_engine_busy(&rig.e));
  EXPECT_EQ(rig.machine[1], -300) << "once released, the input guards E- again";
  EXPECT_EQ(rig.Axis(1).error, uint32_t(X4_AXERR_LIMIT_NEG));
  EXPECT_EQ(r.rises[1].size(), 600u);
}

TEST(SharedLimits, BackingOffWithGoto) {
  Rig rig;
  HitSharedPlus(rig);
  ASSERT_EQ(rig.GotoAxis(1, 0), X4_OK);
  rig.Run();
  EXPECT_EQ(rig.machine[1], 0) << "goto away from the active shared limit";
  EXPECT_EQ(rig.Axis(1).error, 0u);
  // All the way through to the other end: stops at E-.
  Rig rig2;
  HitSharedPlus(rig2);
  ASSERT_EQ(rig2.GotoAxis(1, -1000), X4_OK);
  rig2.Run();
  EXPECT_EQ(rig2.machine[1], -300);
  EXPECT_EQ(rig2.Axis(1).error, uint32_t(X4_AXERR_LIMIT_NEG));
}

TEST(SharedLimits, TowardTheHitLimitStaysBlocked) {
  Rig rig;
  HitSharedPlus(rig);
  ASSERT_EQ(rig.GotoAxis(1, 400), X4_OK);
  const Recording r = rig.Run();
  EXPECT_TRUE(r.rises[1].empty());
  EXPECT_EQ(rig.machine[1], 300);
  EXPECT_EQ(rig.Axis(1).error, uint32_t(X4_AXERR_LIMIT_POS));
}

// ---- 4. reference runs ---------------------------------------------------------------

namespace {

struct HomeCase {
  const char *name;
  int64_t ref_lo, ref_hi;  // the REF switch's active range
  int64_t start;           // machine position at the start
  int32_t vref1, vref2;
  int64_t phase1_end;  // where phase 1 sees REF active
  int64_t zero;        // where phase 2 sees it change: coordinate 0
};

const HomeCase kHomeCases[] = {
    {"negative cam, back out +", -kFar, -1000, 0, -3000, 400, -1000, -999},
    {"positive cam, back out -", 800, kFar, 0, 3000, -400, 800, 799},
    {"narrow, on through +", 400, 420, 0, 3000, 300, 400, 421},
    {"narrow, on through -", -420, -400, 0, -3000, -300, -400, -421},
    {"start on the cam", -kFar, -1000, -1500, -3000, 400, -1500, -999},
    {"phase 1 slow, phase 2 fast", 250, kFar, 0, 500, -45000, 250, 249},
};

// Axis 1 with its REF switch on input 2 (and a spare E+ on input 5).
// Without X4_HOME_BRAKE phase 1 stops where it sees REF, as in ProStep4,
// and the cases' positions are exact.
void HomeRig(Rig &rig, const HomeCase &c) {
  rig.switches = {{0, 2, c.ref_lo, c.ref_hi}};
  rig.machine[0] = c.start;
  x4_switches sw = NoSwitches();
  sw.ref[0] = 2;
  ASSERT_EQ(rig.SetSwitches(sw), X4_OK);
  ASSERT_EQ(rig.SetPosition(1, {int32_t(c.start)}), X4_OK);
}

struct HomeTrace {
  Recording rec;
  std::vector<int64_t> pos;     // machine position after each step
  std::vector<uint32_t> state;  // the axis' state after each step
};

HomeTrace RunTraced(Rig &rig) {
  HomeTrace tr;
  int64_t last = rig.machine[0];
  tr.rec = rig.Run(SIZE_MAX, [&] {
    if (rig.machine[0] == last) return;
    last = rig.machine[0];
    tr.pos.push_back(last);
    tr.state.push_back(rig.Axis(0).state);
  });
  return tr;
}

void ExpectHomed(Rig &rig, const HomeCase &c) {
  EXPECT_EQ(rig.machine[0], c.zero) << c.name;
  const x4_axis_state st = rig.Axis(0);
  EXPECT_EQ(st.position, 0) << c.name;
  EXPECT_EQ(st.state, uint32_t(X4_AX_SYNC)) << c.name;
  EXPECT_EQ(st.error, 0u) << c.name;
}

}  // namespace

TEST(Homing, BothDirectionsAndPhaseOrders) {
  for (const auto &c : kHomeCases) {
    Rig rig;
    HomeRig(rig, c);
    ASSERT_EQ(rig.Home(0, X4_HOME_PHASE1 | X4_HOME_PHASE2, c.vref1, c.vref2, 100000), X4_OK) << c.name;
    EXPECT_FALSE(rig.Axis(0).state & X4_AX_SYNC) << "a reference run clears the sync";
    EXPECT_TRUE(rig.Axis(0).state & X4_AX_REF1) << c.name;
    const HomeTrace tr = RunTraced(rig);
    ExpectHomed(rig, c);
    // Phase 1 steps toward REF at vref1, phase 2 at vref2.
    const size_t n1 = size_t(std::llabs(c.phase1_end - c.start));
    ASSERT_EQ(tr.pos.size(), n1 + size_t(std::llabs(c.zero - c.phase1_end))) << c.name;
    for (size_t i = 0; i < tr.pos.size(); i++) {
      const bool p1 = i < n1;
      const int64_t from = i ? tr.pos[i - 1] : c.start;
      EXPECT_EQ(tr.pos[i] - from, (p1 ? c.vref1 : c.vref2) > 0 ? 1 : -1) << c.name << " step " << i;
      EXPECT_EQ(tr.state[i] & (X4_AX_REF1 | X4_AX_REF2 | X4_AX_RUN),
                uint32_t(X4_AX_RUN | (p1 ? X4_AX_REF1 : X4_AX_REF2)))
          << c.name << " step " << i;
    }
    const auto &t = tr.rec.rises[0];
    for (size_t i = 1; i < t.size(); i++) {
      if (i == n1) continue;  // the turn: a direction setup between the phases
      const double want = 1e9 / std::abs(i < n1 ? c.vref1 : c.vref2);
      ASSERT_NEAR(double(t[i] - t[i - 1]), want, 1.0) << c.name << " interval " << i;
    }
    // The coordinate works from the new zero.
    ASSERT_EQ(rig.GotoAxis(0, 25), X4_OK);
    rig.Run();
    EXPECT_EQ(rig.machine[0], c.zero + 25) << c.name;
    EXPECT_TRUE(rig.Axis(0).state & X4_AX_SYNC);
  }
}

// Phase 2 used to start when phase 1's next step was due, plus the
// direction setup, however much slower it was; now phase 1 brakes along
// the axis' ae first (with the default profile here).
TEST(Homing, ReversalIsAStopAndAStartFromRest) {
  // Homing runs without ramps: a reversal between the phases must look to
  // the motor like a stop and a start from rest, no speed jump larger than
  // a start from rest. So between the last step of phase 1 and the first
  // step of phase 2 in the other direction there is at least the longer
  // of the two phases' step periods, 1 / vref, plus the direction setup
  // time. (Not the intervals as run: phase 2 backs off the switch in one
  // step, and a phase 1 that ramps down to rest ends with long ones.)
  const struct {
    int32_t vref1, vref2;
    uint32_t dir_setup_ns;
  } cases[] = {
      {20000, -20000, X4_DIR_SETUP_NS}, {-20000, 20000, X4_DIR_SETUP_NS},
      {45000, -45000, X4_DIR_SETUP_NS}, {3000, -400, X4_DIR_SETUP_NS},
      {-3000, 400, X4_DIR_SETUP_NS},    {20000, -5000, 20000},
      {500, -45000, X4_DIR_SETUP_NS},   {-400, 3000, 0},
  };
  for (const auto &c : cases) {
    const std::string name = std::to_string(c.vref1) + " then " + std::to_string(c.vref2) +
                             " steps/s, setup " + std::to_string(c.dir_setup_ns) + " ns";
    Rig rig;
    const x4_timing t = {0, 0, c.dir_setup_ns, 0};
    ASSERT_EQ(x4_engine_configure(&rig.e, &t, X4_MODE_CLOCK_DIR), X4_OK);
    // REF on input 2, active from 800 steps on (phase 1 forward) or up to -800.
    rig.switches = {c.vref1 > 0 ? Switch{0, 2, 800, kFar} : Switch{0, 2, -kFar, -800}};
    x4_switches sw = NoSwitches();
    sw.ref[0] = 2;
    ASSERT_EQ(rig.SetSwitches(sw), X4_OK);
    ASSERT_EQ(rig.Home(0, X4_HOME_PHASE1 | X4_HOME_PHASE2, c.vref1, c.vref2, 100000), X4_OK) << name;
    const HomeTrace tr = RunTraced(rig);
    EXPECT_EQ(rig.Axis(0).state, uint32_t(X4_AX_SYNC)) << name << ": homed";
    // The turn: the first step whose direction differs from the one before.
    const auto &rises = tr.rec.rises[0];
    ASSERT_EQ(rises.size(), tr.pos.size()) << name;
    size_t turn = 2;
    while (turn < tr.pos.size() && (tr.pos[turn] - tr.pos[turn - 1]) == (tr.pos[turn - 1] - tr.pos[turn - 2]))
      turn++;
    ASSERT_LT(turn, tr.pos.size()) << name << ": no reversal";
    const uint64_t period1 = 1000000000u / std::abs(c.vref1), period2 = 1000000000u / std::abs(c.vref2);
    const uint64_t gap = rises[turn] - rises[turn - 1];
    std::printf("[ homing   ] %-46s turn after %7llu ns; step periods %7llu and %7llu ns\n", name.c_str(),
                (unsigned long long)gap, (unsigned long long)period1, (unsigned long long)period2);
    EXPECT_GE(gap, std::max(period1, period2) + c.dir_setup_ns)
        << name << ": step periods " << period1 << " and " << period2 << " ns";
  }
}

TEST(Homing, SemiAutomaticPhaseByPhase) {
  for (const auto &c : kHomeCases) {
    Rig rig;
    HomeRig(rig, c);
    ASSERT_EQ(rig.Home(0, X4_HOME_PHASE1, c.vref1, 0, 100000), X4_OK) << c.name;
    rig.Run();
    EXPECT_EQ(rig.machine[0], c.phase1_end) << c.name;
    x4_axis_state st = rig.Axis(0);
    EXPECT_EQ(st.state, 0u) << c.name << ": stopped at REF, not synchronized";
    EXPECT_EQ(st.error, 0u) << c.name;
    EXPECT_EQ(st.position, int32_t(c.phase1_end)) << c.name << ": coordinate not yet zeroed";
    ASSERT_EQ(rig.Home(0, X4_HOME_PHASE2, 0, c.vref2, 100000), X4_OK) << c.name;
    EXPECT_TRUE(rig.Axis(0).state & X4_AX_REF2) << c.name;
    rig.Run();
    ExpectHomed(rig, c);
  }
}

TEST(Homing, Phase1BrakesAlongTheAxisDecelerationBeforeItReverses) {
  // With X4_HOME_BRAKE, ae = 90 000 steps/s^2 from 3000 steps/s:
  // ceil(3000^2 / 2 ae) = 50 steps of brake after the step at which REF is
  // seen, then phase 2 reverses from rest.
  const int32_t ae = 90000, v1 = 3000;
  for (const HomeCase &c : {kHomeCases[0], kHomeCases[1]}) {
    Rig rig;
    HomeRig(rig, c);
    ASSERT_EQ(rig.SetProfile(0, Prof(0, 0, 1000, 1000, ae)), X4_OK);
    ASSERT_EQ(rig.Home(0, X4_HOME_AUTO | X4_HOME_BRAKE, c.vref1, c.vref2, 100000), X4_OK);
    const HomeTrace tr = RunTraced(rig);
    ExpectHomed(rig, c);
    // Phase 1 runs on 51 steps past where it saw REF, braking.
    const int dir = c.vref1 > 0 ? 1 : -1;
    const size_t n1 = size_t(std::llabs(c.phase1_end - c.start)) + 51;
    ASSERT_GT(tr.pos.size(), n1) << c.name;
    EXPECT_EQ(tr.pos[n1 - 1], c.phase1_end + dir * 51) << c.name;
    EXPECT_NE(tr.pos[n1] - tr.pos[n1 - 1], dir) << c.name << ": reversed after the brake";
    // The brake's mean speeds (1 / interval) fall, and never faster than
    // ae: under constant deceleration two neighbouring intervals' mean
    // speeds differ by ae times the time between their midpoints.
    const auto &t = tr.rec.rises[0];
    const size_t hit = n1 - 51;
    double dt_prev = double(t[hit - 1] - t[hit - 2]) / 1e9, v_prev = 1 / dt_prev;
    EXPECT_NEAR(v_prev, v1, 0.01) << c.name;
    for (size_t i = hit; i < n1; i++) {
      const double dt = double(t[i] - t[i - 1]) / 1e9, v = 1 / dt;
      EXPECT_LE(v, v_prev * (1 + 1e-5)) << c.name << " step " << i;  // 1 ns rounding
      EXPECT_LE((v_prev - v) / ((dt + dt_prev) / 2), ae * 1.001) << c.name << " step " << i;
      v_prev = v;
      dt_prev = dt;
    }
    EXPECT_LT(v_prev, 2 * std::sqrt(2.0 * ae)) << c.name << ": the brake ends near rest";
    // The reversal: from rest, after the settle time and the direction setup.
    EXPECT_GE(t[n1] - t[n1 - 1], X4_HOME_SETTLE_NS + X4_DIR_SETUP_NS) << c.name;
  }
}

TEST(Homing, Phase1BrakeMustFitTheRampLimits) {
  // Braking 45 000 steps/s with ae = 1 would take 12.5 hours.
  Rig rig;
  HomeRig(rig, kHomeCases[0]);
  ASSERT_EQ(rig.SetProfile(0, Prof(0, 0, 1000, 1000, 1)), X4_OK);
  EXPECT_EQ(rig.Home(0, X4_HOME_AUTO | X4_HOME_BRAKE, -45000, 400, 100000), X4_ERR_PARAM_FAIL);
  EXPECT_EQ(rig.Home(0, X4_HOME_AUTO, -45000, 400, 100000), X4_OK) << "without the brake, no ramp";
}

TEST(Homing, ThePauseBeforePhase2) {
  for (bool stop : {false, true}) {
    Rig rig;
    HomeRig(rig, kHomeCases[0]);
    ASSERT_EQ(rig.Home(0, X4_HOME_AUTO, -3000, 400, 100000), X4_OK);
    for (int n = 0; rig.e.ch[0].home != X4_HOME_PHASE2 && n < 100000; n++) rig.Run(1);
    ASSERT_EQ(rig.e.ch[0].home, X4_HOME_PHASE2);
    // Phase 2 is due after the pause; AKTIV stays high: the run goes on.
    EXPECT_GE(x4_engine_due(&rig.e), rig.now + X4_HOME_SETTLE_NS - 1000000);
    EXPECT_TRUE(rig.e.ctl & X4_CTL_AKTIV);
    EXPECT_TRUE(rig.Axis(0).state & X4_AX_REF2);
    // Halted in the pause: it ends at once, without a step or a direction change.
    const uint8_t data = rig.e.data;
    ASSERT_EQ(x4_engine_halt(&rig.e, 1, stop), X4_OK);
    for (int n = 0; x4_engine_busy(&rig.e) && n < 2; n++) x4_engine_fire(&rig.e, rig.now);  // due at once
    EXPECT_FALSE(x4_engine_busy(&rig.e)) << (stop ? "stop" : "brake");
    EXPECT_EQ(rig.e.data, data);
    EXPECT_EQ(rig.Axis(0).state, 0u) << "idle, not synchronized";
  }
}

TEST(Homing, TheBrakeIsPhase1s) {
  Rig rig;
  HomeRig(rig, kHomeCases[0]);
  EXPECT_EQ(rig.Home(0, X4_HOME_PHASE2 | X4_HOME_BRAKE, 0, 400, 100000), X4_ERR_PARAM_FAIL);
  EXPECT_EQ(rig.Home(0, X4_HOME_BRAKE, -3000, 400, 100000), X4_ERR_PARAM_FAIL);
  EXPECT_FALSE(x4_engine_busy(&rig.e));
}

TEST(Homing, ABrakeThatRunsOffTheSwitchEndsTheRun) {
  // The narrow cam (400..420) is shorter than the 50-step brake: phase 2
  // would find its far edge. The run ends there, not synchronized.
  Rig rig;
  HomeRig(rig, kHomeCases[2]);
  ASSERT_EQ(rig.SetProfile(0, Prof(0, 0, 1000, 1000, 90000)), X4_OK);
  ASSERT_EQ(rig.Home(0, X4_HOME_AUTO | X4_HOME_BRAKE, 3000, 300, 100000), X4_OK);
  rig.Run();
  EXPECT_EQ(rig.machine[0], 400 + 51);
  const x4_axis_state st = rig.Axis(0);
  EXPECT_EQ(st.error, uint32_t(X4_AXERR_REF_PASSED));
  EXPECT_EQ(st.state, uint32_t(X4_AX_ERROR)) << "idle, not synchronized";
}

TEST(Homing, Phase2AloneFromOffTheSwitchEndsWhenItBecomesActive) {
  // "Until it changes": from an inactive REF, phase 2 ends at its edge.
  Rig rig;
  const HomeCase c = {"", 600, kFar, 0, 0, 300, 0, 600};
  HomeRig(rig, c);
  ASSERT_EQ(rig.Home(0, X4_HOME_PHASE2, 0, 300, 100000), X4_OK);
  rig.Run();
  ExpectHomed(rig, c);
}

TEST(Homing, SrefExceeded) {
  {  // phase 1 never finds REF
    Rig rig;
    HomeRig(rig, kHomeCases[0]);  // REF at -1000
    ASSERT_EQ(rig.Home(0, X4_HOME_PHASE1 | X4_HOME_PHASE2, -3000, 400, 600), X4_OK);
    const Recording r = rig.Run();
    EXPECT_EQ(r.rises[0].size(), 600u);
    const x4_axis_state st = rig.Axis(0);
    EXPECT_EQ(st.error, uint32_t(X4_AXERR_REF_TRAVEL));
    EXPECT_EQ(st.state, uint32_t(X4_AX_ERROR)) << "not running, not synchronized";
    EXPECT_EQ(st.position, -600);
  }
  {  // phase 2 never leaves the cam (same direction as phase 1)
    Rig rig;
    HomeRig(rig, kHomeCases[1]);  // REF from 800 on
    ASSERT_EQ(rig.Home(0, X4_HOME_PHASE1 | X4_HOME_PHASE2, 3000, 300, 1000), X4_OK);
    rig.Run();
    EXPECT_EQ(rig.machine[0], 800 + 1000);
    EXPECT_EQ(rig.Axis(0).error, uint32_t(X4_AXERR_REF_TRAVEL));
    EXPECT_FALSE(rig.Axis(0).state & X4_AX_SYNC);
    EXPECT_EQ(rig.Axis(0).position, 1800);
  }
  {  // exactly enough travel is not an error
    Rig rig;
    HomeRig(rig, kHomeCases[0]);
    ASSERT_EQ(rig.Home(0, X4_HOME_PHASE1 | X4_HOME_PHASE2, -3000, 400, 1001), X4_OK);
    rig.Run();
    ExpectHomed(rig, kHomeCases[0]);
  }
}

TEST(Homing, SrefIsTheMaximumTravelInclusive) {
  // REF 1000 steps away and sref = 1000: the phase travels exactly sref
  // steps and finds the switch, which is "at most sref".
  Rig rig;
  HomeRig(rig, kHomeCases[0]);  // REF at -1000
  ASSERT_EQ(rig.Home(0, X4_HOME_PHASE1 | X4_HOME_PHASE2, -3000, 400, 1000), X4_OK);
  rig.Run();
  ExpectHomed(rig, kHomeCases[0]);
}

TEST(Homing, BrakeAndStopAbortWithoutSync) {
  for (bool stop : {false, true}) {
    // After the setup, in phase 1, in phase 2 (phase 1 ends at event 802).
    for (size_t events : {size_t(1), size_t(301), size_t(820)}) {
      Rig rig;
      HomeRig(rig, kHomeCases[2]);  // narrow REF at 400..420, both phases +
      ASSERT_EQ(rig.SetPosition(1, {0}), X4_OK);
      ASSERT_EQ(rig.Home(0, X4_HOME_PHASE1 | X4_HOME_PHASE2, 3000, 30, 100000), X4_OK);
      rig.Run(events);
      ASSERT_TRUE(x4_engine_busy(&rig.e));
      const uint32_t phase = rig.Axis(0).state & (X4_AX_REF1 | X4_AX_REF2);
      EXPECT_NE(phase, 0u);
      const int64_t at = rig.machine[0];
      ASSERT_EQ(x4_engine_halt(&rig.e, 1, stop), X4_OK);
      rig.Run();
      const x4_axis_state st = rig.Axis(0);
      EXPECT_EQ(st.state, 0u) << (stop ? "stop" : "brake") << " after " << events << " events";
      EXPECT_LE(rig.machine[0] - at, 1) << "no ramp to follow";
      EXPECT_EQ(int64_t(st.position), rig.machine[0]) << "coordinate not zeroed";
    }
  }
}

TEST(Homing, LimitDuringTheReferenceRunAborts) {
  Rig rig;
  rig.switches = {Minus(0, 2, -1000), Minus(0, 3, -500)};  // REF behind E-
  x4_switches sw = NoSwitches();
  sw.ref[0] = 2;
  sw.minus[0] = 3;
  ASSERT_EQ(rig.SetSwitches(sw), X4_OK);
  ASSERT_EQ(rig.Home(0, X4_HOME_PHASE1 | X4_HOME_PHASE2, -3000, 400, 100000), X4_OK);
  rig.Run();
  EXPECT_EQ(rig.machine[0], -500);
  EXPECT_EQ(rig.Axis(0).error, uint32_t(X4_AXERR_LIMIT_NEG));
  EXPECT_EQ(rig.Axis(0).state, uint32_t(X4_AX_ERROR));
}

TEST(Homing, ParameterErrorsChangeNothing) {
  Rig rig;
  x4_switches sw = NoSwitches();
  sw.ref[1] = 2;  // axis 2 has a REF input, axis 1 none
  ASSERT_EQ(rig.SetSwitches(sw), X4_OK);
  ASSERT_EQ(rig.SetPosition(0x3, {5, 6}), X4_OK);
  const x4_engine before = rig.e;
  const uint8_t both = X4_HOME_PHASE1 | X4_HOME_PHASE2;
  const struct {
    int axis;  // 1-based
    uint8_t phases;
    int32_t vref1, vref2;
    uint32_t sref;
  } bad[] = {
      {1, both, 100, -100, 1000},  // no REF input
      {2, both, 0, -100, 1000},    // vref1 0
      {2, both, 100, 0, 1000},     // vref2 0
      {2, X4_HOME_PHASE2, 100, 0, 1000}, {2, X4_HOME_PHASE1, 0, 100, 1000},
      {2, both, 100001, -100, 1000},  // too fast
      {2, both, -100001, 100, 1000},     {2, both, 100, 100001, 1000},
      {2, both, 100, -100001, 1000},     {2, both, INT32_MIN, 100, 1000},
      {2, both, 100, -100, 0},                                        // sref 0
      {2, both, 100, -100, 0x80000000u}, {2, 0, 100, -100, 1000},     // no phase
      {2, 4, 100, -100, 1000},           {0, both, 100, -100, 1000},  // axis
      {5, both, 100, -100, 1000},
  };
  for (const auto &b : bad) {
    EXPECT_EQ(x4_switch_home(&rig.e, b.axis, b.phases, b.vref1, b.vref2, b.sref, kStart), X4_ERR_PARAM_FAIL)
        << b.axis << " " << int(b.phases) << " " << b.vref1 << " " << b.vref2 << " " << b.sref;
  }
  EXPECT_EQ(std::memcmp(&before, &rig.e, sizeof before), 0);
  EXPECT_EQ(rig.Axis(1).state, uint32_t(X4_AX_SYNC));
  // The limits themselves are fine.
  EXPECT_EQ(x4_switch_home(&rig.e, 2, both, 45000, -45000, 0x7fffffff, kStart), X4_OK);
  EXPECT_EQ(x4_switch_home(&rig.e, 3, X4_HOME_PHASE2, 0, 100, 1, kStart), X4_ERR_PARAM_FAIL) << "no REF";
}

// ---- 5. synchronization ----------------------------------------------------------------

TEST(Sync, SetByStopAndZeroAndHoming) {
  Rig rig;
  EXPECT_EQ(rig.Axis(0).state, 0u) << "unknown at power-up";
  ASSERT_EQ(rig.SetPosition(0x5, {10, 0, -10}), X4_OK);
  EXPECT_EQ(rig.Axis(0).state, uint32_t(X4_AX_SYNC));
  EXPECT_EQ(rig.Axis(1).state, 0u);
  EXPECT_EQ(rig.Axis(2).state, uint32_t(X4_AX_SYNC));
  EXPECT_EQ(rig.Axis(2).position, -10);
  // Moves of every kind keep it.
  ASSERT_EQ(rig.GotoAxis(0, 100), X4_OK);
  rig.Run();
  ASSERT_EQ(rig.Start(Move(5, 5, 5, 5, 1000, 0)), X4_OK);
  rig.Run();
  EXPECT_EQ(rig.Axis(0).state, uint32_t(X4_AX_SYNC));
  EXPECT_EQ(rig.Axis(2).state, uint32_t(X4_AX_SYNC));
  EXPECT_EQ(rig.Axis(1).state, 0u);
}

TEST(Sync, ClearedByStopNotByBrake) {
  Rig rig;
  ASSERT_EQ(rig.SetPosition(0xf, {0, 0, 0, 0}), X4_OK);
  ASSERT_EQ(rig.Goto(0x3, {10000, 10000}), X4_OK);
  rig.Run(2001);
  ASSERT_EQ(x4_engine_brake(&rig.e), X4_OK);
  rig.Run();
  EXPECT_EQ(rig.Axis(0).state, uint32_t(X4_AX_SYNC));
  EXPECT_EQ(rig.Axis(1).state, uint32_t(X4_AX_SYNC));
  ASSERT_EQ(rig.Goto(0x3, {0, 0}), X4_OK);
  rig.Run(2001);
  ASSERT_EQ(x4_engine_stop(&rig.e), X4_OK);
  EXPECT_EQ(rig.Axis(0).state, 0u);
  EXPECT_EQ(rig.Axis(1).state, 0u);
  EXPECT_EQ(rig.Axis(2).state, uint32_t(X4_AX_SYNC)) << "idle axes keep theirs";
  // X4Stop of an interpolated move: all its axes.
  ASSERT_EQ(rig.Start(Move(0, 0, 100, 50, 1000, 0)), X4_OK);
  rig.Run(11);
  ASSERT_EQ(x4_engine_stop(&rig.e), X4_OK);
  EXPECT_EQ(rig.Axis(2).state, 0u);
  EXPECT_EQ(rig.Axis(3).state, 0u);
}

TEST(Sync, SetPositionStopsARunningAxis) {
  Rig rig;
  ASSERT_EQ(rig.GotoAxis(0, 10000), X4_OK);
  Recording r = rig.Run(2 + 2 * 100);  // the clock of step 100 is high
  ASSERT_TRUE(rig.e.data & X4_CLK_BIT(0));
  ASSERT_EQ(rig.SetPosition(1, {42}), X4_OK);
  EXPECT_FALSE(x4_engine_busy(&rig.e));
  EXPECT_EQ(rig.e.data & X4_CLK_MASK, 0);
  const x4_axis_state st = rig.Axis(0);
  EXPECT_EQ(st.position, 42);
  EXPECT_EQ(st.state, uint32_t(X4_AX_SYNC));
  r = rig.Run();
  EXPECT_TRUE(r.rises[0].empty());
  // With an interpolated partner: the partner stops and loses its sync.
  ASSERT_EQ(rig.SetPosition(0x3, {0, 0}), X4_OK);
  ASSERT_EQ(rig.Start(Move(1000, 500, 0, 0, 1000, 0)), X4_OK);
  rig.Run(101);
  ASSERT_EQ(rig.SetPosition(1, {0}), X4_OK);
  EXPECT_FALSE(x4_engine_busy(&rig.e));
  EXPECT_EQ(rig.Axis(0).state, uint32_t(X4_AX_SYNC));
  EXPECT_EQ(rig.Axis(1).state, 0u);
  // Of an idle axis while another runs: the other runs on.
  ASSERT_EQ(rig.GotoAxis(2, 300), X4_OK);
  rig.Run(11);
  ASSERT_EQ(rig.SetPosition(1, {-7}), X4_OK);
  EXPECT_TRUE(rig.Axis(2).state & X4_AX_RUN);
  rig.Run();
  EXPECT_EQ(rig.Axis(2).position, 300);
  EXPECT_EQ(rig.Axis(0).position, -7);
}

TEST(Sync, ClearedByALimitHitAndErrorsByTheNextCommand) {
  Rig rig;
  rig.switches = {Plus(0, 1, 50)};
  ASSERT_EQ(rig.SetSwitches(LimitWiring(0, 1, 0)), X4_OK);
  ASSERT_EQ(rig.SetPosition(1, {0}), X4_OK);
  ASSERT_EQ(rig.GotoAxis(0, 100), X4_OK);
  rig.Run();
  EXPECT_EQ(rig.Axis(0).state, uint32_t(X4_AX_ERROR));
  ASSERT_EQ(rig.GotoAxis(0, 50), X4_OK);  // already there: no move, but a command
  EXPECT_EQ(rig.Axis(0).state, 0u);
  EXPECT_EQ(rig.Axis(0).error, 0u);
  ASSERT_EQ(rig.GotoAxis(0, 100), X4_OK);
  rig.Run();
  ASSERT_EQ(rig.Axis(0).error, uint32_t(X4_AXERR_LIMIT_POS));
  ASSERT_EQ(rig.SetPosition(1, {0}), X4_OK);
  EXPECT_EQ(rig.Axis(0).state, uint32_t(X4_AX_SYNC)) << "stop and zero clears the error";
}

// ---- 6. validation ----------------------------------------------------------------------

TEST(Validation, ProfileRules) {
  const struct {
    x4_profile p;
    bool ok;
  } cases[] = {
      {Prof(0, 0, 1000, 1000, 1000), true},  // the default
      {Prof(0, 0, 1, 0, 0), true},
      {Prof(0, 0, 0, 1000, 1000), false},  // vm 0
      {Prof(0, 0, 100000, 1000, 1000), true},
      {Prof(0, 0, 100001, 1000, 1000), false},
      {Prof(1000, 0, 1000, 1000, 1000), true},  // v0 = vm
      {Prof(1001, 0, 1000, 1000, 1000), false},
      {Prof(0, 1000, 1000, 1000, 1000), true},
      {Prof(0, 1001, 1000, 1000, 1000), false},
      {Prof(0, 0, 1000, 1000000, 1000000), true},
      {Prof(0, 0, 1000, 1000001, 1000), false},
      {Prof(0, 0, 1000, 1000, 1000001), false},
      {Prof(0, 0, 3600, 1, 1), true},  // a ramp of 3600 s
      {Prof(0, 0, 3601, 1, 1000), false},
      {Prof(0, 0, 3601, 1000, 1), false},
      {Prof(0, 0, 45000, 13, 13), true},
      {Prof(0, 0, 45000, 12, 13), false},
      {Prof(0, 0, 45000, 13, 12), false},
      {Prof(45000, 45000, 45000, 0, 0), true},  // no ramps at all
      {Prof(0, 0, 45000, 0, 12), false},
  };
  for (const auto &c : cases) EXPECT_EQ(x4_profile_check(&c.p), c.ok ? X4_OK : X4_ERR_PARAM_FAIL) << Str(c.p);
  Rig rig;
  const x4_engine before = rig.e;
  for (const auto &c : cases) {
    if (!c.ok) {
      EXPECT_EQ(rig.SetProfile(0, c.p), X4_ERR_PARAM_FAIL) << Str(c.p);
    }
  }
  const x4_profile good = Prof(0, 0, 1000, 1000, 1000);
  EXPECT_EQ(x4_engine_set_profile(&rig.e, 0, &good), X4_ERR_PARAM_FAIL);
  EXPECT_EQ(x4_engine_set_profile(&rig.e, 5, &good), X4_ERR_PARAM_FAIL);
  EXPECT_EQ(std::memcmp(&before, &rig.e, sizeof before), 0);
  EXPECT_EQ(x4_engine_set_profile(&rig.e, 4, &good), X4_OK);
}

TEST(Validation, SwitchRanges) {
  Rig rig;
  const x4_engine before = rig.e;
  for (int field = 0; field < 3; field++)
    for (int axis = 0; axis < X4_AXES; axis++) {
      x4_switches sw = NoSwitches();
      uint8_t *f = field == 0 ? sw.ref : field == 1 ? sw.plus : sw.minus;
      f[axis] = 6;
      EXPECT_EQ(x4_switch_set(&rig.e, &sw), X4_ERR_PARAM_FAIL) << field << " " << axis;
      f[axis] = 5;
      EXPECT_EQ(x4_switch_set(&rig.e, &sw), X4_OK);
    }
  x4_switches sw = NoSwitches();
  sw.nc = 0x20;
  EXPECT_EQ(x4_switch_set(&rig.e, &sw), X4_ERR_PARAM_FAIL);
  sw.nc = 0x1f;
  EXPECT_EQ(x4_switch_set(&rig.e, &sw), X4_OK);
  EXPECT_EQ(rig.e.sw.nc, 0x1f);
  sw.nc = 0;
  ASSERT_EQ(x4_switch_set(&rig.e, &sw), X4_OK);
  EXPECT_EQ(std::memcmp(&before, &rig.e, sizeof before), 0);
}

TEST(Validation, GotoAndSetPositionMasks) {
  Rig rig;
  const x4_engine before = rig.e;
  const Targets t{1, 2, 3, 4};
  for (uint8_t axes : {0x00, 0x10, 0x1f, 0xff}) {
    EXPECT_EQ(x4_engine_goto(&rig.e, axes, t.data(), false, kStart), X4_ERR_PARAM_FAIL) << int(axes);
    EXPECT_EQ(x4_engine_goto(&rig.e, axes, t.data(), true, kStart), X4_ERR_PARAM_FAIL) << int(axes);
    EXPECT_EQ(x4_engine_set_position(&rig.e, axes, t.data()), X4_ERR_PARAM_FAIL) << int(axes);
  }
  EXPECT_EQ(std::memcmp(&before, &rig.e, sizeof before), 0);
  EXPECT_EQ(x4_engine_goto(&rig.e, 0x0f, t.data(), false, kStart), X4_OK);
}

TEST(Validation, GotoRespectsThePortTimingAndMode) {
  Rig rig;
  const x4_timing slow{20000, 20000, X4_DIR_SETUP_NS, 0};  // 40 us per step: 25000 steps/s at most
  ASSERT_EQ(x4_engine_configure(&rig.e, &slow, X4_MODE_CLOCK_DIR), X4_OK);
  ASSERT_EQ(rig.SetProfile(1, Prof(0, 0, 30000, 100000, 100000)), X4_OK);
  EXPECT_EQ(rig.GotoAxis(1, 100), X4_ERR_FREQ_TOO_HIGH);
  EXPECT_FALSE(x4_engine_busy(&rig.e));
  ASSERT_EQ(rig.SetProfile(1, Prof(0, 0, 25000, 100000, 100000)), X4_OK);
  EXPECT_EQ(rig.GotoAxis(1, 100), X4_OK);
  rig.Run();
  Rig smc;
  const x4_timing t{0, 0, X4_DIR_SETUP_NS, 0};
  ASSERT_EQ(x4_engine_configure(&smc.e, &t, X4_MODE_SMC_PHASE), X4_OK);
  EXPECT_EQ(smc.GotoAxis(3, 100), X4_ERR_PARAM_FAIL) << "the SMC boards drive 3 motors";
  EXPECT_EQ(smc.GotoAxis(2, 100), X4_OK);
}
