// SPDX-License-Identifier: GPL-2.0
// Unit tests of continuous paths (kmod/engine/x4_path.c): the segment
// queue, the look-ahead planner, hold/resume/abort, feed override. The
// checks look at what the engine emits, from outside: the step edges of
// every axis, turned back into path positions and times, must obey the
// physics (speed and acceleration limits, corners, stops at rest), and
// end exactly where the segments add up to.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "engine_ref.h"
extern "C" {
#include "x4_req.h"
#include "x4_track.h"
}

using namespace x4test;

namespace {

constexpr uint64_t kStart = 1000;

x4_segment Seg(int32_t x, int32_t y, int32_t z, int32_t a, uint32_t length, uint32_t v_max, uint32_t accel,
               uint32_t v_entry, uint64_t tag = 0) {
  x4_segment s{};
  s.steps[0] = x;
  s.steps[1] = y;
  s.steps[2] = z;
  s.steps[3] = a;
  s.length = length;
  s.v_max = v_max;
  s.accel = accel;
  s.v_entry = v_entry;
  s.tag = tag;
  return s;
}

int Leader(const x4_segment &s) {
  int lead = 0;
  for (int i = 1; i < X4_AXES; i++)
    if (std::abs(s.steps[i]) > std::abs(s.steps[lead])) lead = i;
  return lead;
}

struct Path {
  x4_engine e;
  std::vector<x4_path_slot> q;
  std::vector<x4_segment> sent;
  int32_t target[X4_AXES] = {0, 0, 0, 0};

  explicit Path(uint32_t depth = 256) : q(depth) {
    x4_engine_init(&e);
    EXPECT_EQ(x4_path_set_queue(&e, q.data(), depth), X4_OK);
  }
  // As the module's write(): check, queue, plan, kick.
  int Push(const x4_segment &s, uint64_t now = kStart) {
    const int ret = x4_path_check(&e, &s);
    if (ret) return ret;
    if (!x4_path_room(&e)) return -1;
    x4_path_push(&e, &s);
    x4_path_kick(&e, now);
    sent.push_back(s);
    for (int i = 0; i < X4_AXES; i++) target[i] += s.steps[i];
    return X4_OK;
  }
  x4_path_status Status() const {
    x4_path_status st;
    x4_path_get_status(&e, &st);
    return st;
  }
  void ExpectAtTarget() const {
    for (int i = 0; i < X4_AXES; i++)
      EXPECT_EQ(e.pos_base[i] + uint32_t(e.steps[i]), uint32_t(target[i])) << "axis " << i;
  }
  // What a driver counted from the pins: a step per rising clock edge, in
  // the direction its direction pin showed then.
  void ExpectPinsAtTarget(const Recording &r) const {
    int32_t pos[X4_AXES] = {0, 0, 0, 0};
    uint8_t data = 0;
    for (const x4_event &ev : r.events) {
      for (int i = 0; i < X4_AXES; i++)
        if (ev.data & ~data & X4_CLK_BIT(i)) pos[i] += ev.data & X4_DIR_BIT(i) ? 1 : -1;
      data = ev.data;
    }
    for (int i = 0; i < X4_AXES; i++) EXPECT_EQ(pos[i], target[i]) << "axis " << i << " as its pins say";
  }
};

// One leader step as the physics sees it: when, where along the path
// (units), and the segment it belongs to.
struct Sample {
  double t;  // s
  double s;  // path units
  size_t seg;
};

// The leader steps of each segment, from the axes' rising edges: each axis
// steps |steps[i]| times per segment, in time order.
std::vector<Sample> LeaderSteps(const Recording &r, const std::vector<x4_segment> &segs) {
  std::vector<Sample> out;
  size_t idx[X4_AXES] = {0, 0, 0, 0};
  double base = 0;
  for (size_t k = 0; k < segs.size(); k++) {
    const x4_segment &g = segs[k];
    const int lead = Leader(g);
    const uint32_t n = std::abs(g.steps[lead]);
    for (uint32_t j = 1; j <= n; j++) {
      if (idx[lead] + j - 1 >= r.rises[lead].size()) return out;
      out.push_back({r.rises[lead][idx[lead] + j - 1] * 1e-9, base + double(g.length) * j / n, k});
    }
    for (int i = 0; i < X4_AXES; i++) idx[i] += std::abs(g.steps[i]);
    base += g.length;
  }
  return out;
}

// Every triple of leader steps: the mean speeds of the two intervals
// differ by no more than the acceleration allows in the time between their
// middles (exact for constant acceleration), plus what rounding to whole
// ns and to whole steps/s adds. Speeds stay within v_max (override: pct).
// Returns the largest acceleration seen, as a fraction of the limit.
double CheckPhysics(const std::vector<Sample> &st, const std::vector<x4_segment> &segs, double pct = 100) {
  double worst = 0;
  for (size_t k = 2; k < st.size(); k++) {
    const Sample &a = st[k - 2], &b = st[k - 1], &c = st[k];
    const double dt1 = b.t - a.t, dt2 = c.t - b.t;
    if (dt1 <= 0 || dt2 <= 0) {
      ADD_FAILURE() << "steps out of order at " << k;
      return worst;
    }
    const double v1 = (b.s - a.s) / dt1, v2 = (c.s - b.s) / dt2;
    const x4_segment &g1 = segs[b.seg], &g2 = segs[c.seg];
    const double acc = std::max(g1.accel, g2.accel);
    const double unit = std::max(double(g1.length) / std::abs(g1.steps[Leader(g1)]),
                                 double(g2.length) / std::abs(g2.steps[Leader(g2)]));
    const double slack = 3 * unit + std::max(v1, v2) * 4e-9 / std::min(dt1, dt2);
    const double dv = std::fabs(v2 - v1), allowed = acc * (dt1 + dt2) / 2;
    worst = std::max(worst, (dv - slack) / allowed);
    if (dv > allowed * 1.001 + slack) {
      ADD_FAILURE() << "acceleration " << dv / ((dt1 + dt2) / 2) << " > " << acc << " at leader step " << k
                    << " (segment " << c.seg << ", v " << v1 << " -> " << v2 << ")";
      return worst;
    }
    const double vmax = std::max(g1.v_max, g2.v_max) * pct / 100;
    if (v2 > vmax * 1.001 + slack) {
      ADD_FAILURE() << "speed " << v2 << " > v_max " << vmax << " at leader step " << k;
      return worst;
    }
  }
  return worst;
}

// The last step came at the end of a ramp to rest: its interval is at least
// the time a stop from rest takes for one step.
void ExpectStopsAtRest(const std::vector<Sample> &st, const std::vector<x4_segment> &segs) {
  ASSERT_GE(st.size(), 2u);
  const Sample &a = st[st.size() - 2], &b = st.back();
  const double rest = std::sqrt(2 * (b.s - a.s) / segs[b.seg].accel);
  EXPECT_GE(b.t - a.t, 0.95 * rest) << "the path ends at speed " << (b.s - a.s) / (b.t - a.t);
}

// Runs the path to its end (at most max_events more events) and checks
// what every run that completes a path must show: each axis at the sum of
// the segments, by the engine's counters and by its pins; the physics
// (the largest acceleration into *worst); the last step at the end of a
// ramp to rest. Returns the leader steps.
std::vector<Sample> RunToEnd(Path &p, Recording &r, size_t max_events = SIZE_MAX, double *worst = nullptr) {
  record(p.e, r, max_events);
  p.ExpectAtTarget();
  p.ExpectPinsAtTarget(r);
  std::vector<Sample> st = LeaderSteps(r, p.sent);
  const double w = CheckPhysics(st, p.sent);
  if (worst) *worst = w;
  ExpectStopsAtRest(st, p.sent);
  return st;
}

// A polygon approximating a circle of radius r steps, n chords, at v_max
// units/s with accel; units = steps * 10. Corners from the chord angle.
std::vector<x4_segment> Circle(int r, int n, uint32_t v_max, uint32_t accel, uint32_t v_corner) {
  std::vector<x4_segment> out;
  int px = r, py = 0;
  for (int k = 1; k <= n; k++) {
    const int x = int(std::lround(r * std::cos(2 * M_PI * k / n)));
    const int y = int(std::lround(r * std::sin(2 * M_PI * k / n)));
    const double len = std::hypot(x - px, y - py);
    if (x != px || y != py)
      out.push_back(Seg(x - px, y - py, 0, 0, uint32_t(std::lround(len * 10)), v_max, accel, v_corner, k));
    px = x;
    py = y;
  }
  return out;
}

}  // namespace

// ---- validation ------------------------------------------------------------

TEST(PathCheck, BadSegmentsAreRefusedAndChangeNothing) {
  Path p;
  const x4_segment good = Seg(100, 50, 0, 0, 1000, 5000, 50000, 5000);
  EXPECT_EQ(x4_path_check(&p.e, &good), X4_OK);
  struct {
    x4_segment s;
    int err;
    const char *what;
  } cases[] = {
      {Seg(0, 0, 0, 0, 1000, 5000, 50000, 5000), X4_ERR_NO_STEPS, "no steps"},
      {Seg(100, 0, 0, 0, 0, 5000, 50000, 5000), X4_ERR_PARAM_FAIL, "zero length"},
      {Seg(100, 0, 0, 0, 1000, 0, 50000, 5000), X4_ERR_PARAM_FAIL, "no speed"},
      {Seg(100, 0, 0, 0, 1000, 5000, 0, 5000), X4_ERR_PARAM_FAIL, "no acceleration"},
      {Seg(100, 0, 0, 0, 1000, 5000, 2, 5000), X4_ERR_PARAM_FAIL, "ramp of 2500 s"},
      {Seg(100, 0, 0, 0, 100000, 500, 500, 5000), X4_ERR_PARAM_FAIL, "leader acceleration < 1"},
      {Seg(1000, 0, 0, 0, 1, 50, 2000, 5000), X4_ERR_PARAM_FAIL, "leader acceleration > 1e6"},
      {Seg(100, 0, 0, 0, 1000, 1000010, 5000000, 5000), X4_ERR_RATE_BUDGET, "100001 steps/s"},
      {Seg(100, 0, 0, 0, 0x80000000u, 5000, 50000, 5000), X4_ERR_PARAM_FAIL, "length 2^31"},
      {Seg(16777217, 0, 0, 0, 1000, 5000, 50000, 5000), X4_ERR_STEPS_TOO_HIGH, "2^24 + 1 steps"},
  };
  for (const auto &c : cases) EXPECT_EQ(x4_path_check(&p.e, &c.s), c.err) << c.what;
  for (const auto &c : cases) EXPECT_NE(p.Push(c.s), X4_OK) << c.what;
  const x4_path_status st = p.Status();
  EXPECT_EQ(st.queued, 0u);
  EXPECT_EQ(st.state, X4_PATH_IDLE);
  EXPECT_FALSE(x4_engine_busy(&p.e));
}

// The check the module runs on every record and libx4step on every
// segment (x4_segment_check()), at its edges; x4_path_check() gives the
// same answer for each (it adds only the port's checks).
TEST(PathCheck, SegmentCheckAtItsEdges) {
  Path p;
  struct {
    x4_segment s;
    uint32_t reserved;
    int err;
    const char *what;
  } cases[] = {
      {Seg(100, 0, 0, 0, 1000, 5000, 50000, 5000), 0, X4_OK, "good"},
      {Seg(16777216, -16777216, 0, 0, 16777216, 5000, 50000, 0), 0, X4_OK, "+-2^24 steps"},
      {Seg(-16777217, 0, 0, 0, 16777216, 5000, 50000, 0), 0, X4_ERR_STEPS_TOO_HIGH, "-2^24 - 1 steps"},
      {Seg(0, INT32_MIN, 0, 0, 1000, 5000, 50000, 0), 0, X4_ERR_STEPS_TOO_HIGH, "INT32_MIN steps"},
      {Seg(0, 0, INT32_MAX, 0, 1000, 5000, 50000, 0), 0, X4_ERR_STEPS_TOO_HIGH, "INT32_MAX steps"},
      {Seg(0, 0, 0, 0, 1000, 5000, 50000, 0), 0, X4_ERR_NO_STEPS, "no steps"},
      {Seg(0, 0, 0, 0, 0, 0, 0, 0), 1, X4_ERR_NO_STEPS, "no steps before reserved fields"},
      {Seg(100, 0, 0, 0, 0, 5000, 50000, 0), 0, X4_ERR_PARAM_FAIL, "zero length"},
      {Seg(100, 0, 0, 0, 1000, 5000, 50000, 0), 1, X4_ERR_PARAM_FAIL, "flags"},
      {Seg(100, 0, 0, 0, 1000, 5000, 50000, 0), 0x80000000u, X4_ERR_PARAM_FAIL, "reserved word"},
      {Seg(100, 0, 0, 0, 0x7fffffff, 0x7fffffff, 0x7fffffff, 0x7fffffff), 0, X4_OK, "values at 2^31 - 1"},
      {Seg(100, 0, 0, 0, 0x80000000u, 5000, 50000, 0), 0, X4_ERR_PARAM_FAIL, "length 2^31"},
      {Seg(100, 0, 0, 0, 1000, 0x80000000u, 0x7fffffff, 0), 0, X4_ERR_PARAM_FAIL, "v_max 2^31"},
      {Seg(100, 0, 0, 0, 1000, 5000, 50000, 0x80000000u), 0, X4_ERR_PARAM_FAIL, "v_entry 2^31"},
      {Seg(100, 0, 0, 0, 1000, 5000, 0x80000000u, 0), 0, X4_ERR_PARAM_FAIL, "accel 2^31"},
      {Seg(100, 0, 0, 0, 1000, 0, 50000, 0), 0, X4_ERR_PARAM_FAIL, "no speed"},
      {Seg(100, 0, 0, 0, 1000, 5000, 0, 0), 0, X4_ERR_PARAM_FAIL, "no acceleration"},
      {Seg(100, 0, 0, 0, 1000, 1800, 1, 0), 0, X4_ERR_PARAM_FAIL, "leader acceleration 0.1 steps/s^2"},
      {Seg(100, 0, 0, 0, 100000, 1800000, 1000, 0), 0, X4_OK, "ramp of 1800 s, leader at 1 step/s^2"},
      {Seg(100, 0, 0, 0, 100000, 1800001, 1000, 0), 0, X4_ERR_PARAM_FAIL, "ramp beyond 1800 s"},
      {Seg(1000, 0, 0, 0, 1000, 5000, 1000000, 0), 0, X4_OK, "leader acceleration 1e6"},
      {Seg(1000, 0, 0, 0, 1000, 5000, 1000001, 0), 0, X4_ERR_PARAM_FAIL, "leader acceleration 1e6 + 1"},
      {Seg(100, 0, 0, 0, 100, 100000, 1000000, 0), 0, X4_OK, "leader at the 100000 steps/s ceiling"},
      {Seg(100, 0, 0, 0, 100, 100001, 1000000, 0), 0, X4_ERR_RATE_BUDGET, "leader above the ceiling"},
      {Seg(16777216, 0, 0, 0, 1, 1, 1, 0), 0, X4_ERR_PARAM_FAIL, "2^24 steps in one unit: leader accel"},
  };
  for (const auto &c : cases) {
    EXPECT_EQ(x4_segment_check(&c.s, c.reserved), c.err) << c.what;
    if (!c.reserved) {
      EXPECT_EQ(x4_path_check(&p.e, &c.s), c.err) << c.what;
    }
  }
}

TEST(PathCheck, PathAndMovesExcludeEachOther) {
  Path p;
  x4_move m = Move(100, 0, 0, 0, 1000, 0);
  ASSERT_EQ(x4_engine_load(&p.e, &m), X4_OK);
  ASSERT_EQ(x4_engine_start(&p.e, kStart), X4_OK);
  EXPECT_EQ(p.Push(Seg(0, 100, 0, 0, 100, 1000, 10000, 1000)), X4_ERR_IS_ACTIVE);
  Recording r;
  record(p.e, r);
  ASSERT_EQ(p.Push(Seg(0, 100, 0, 0, 100, 1000, 10000, 1000)), X4_OK);
  EXPECT_EQ(x4_engine_load(&p.e, &m), X4_OK);
  EXPECT_EQ(x4_engine_start(&p.e, kStart), X4_ERR_IS_ACTIVE);
  EXPECT_EQ(x4_engine_endless(&p.e, 2, false, 1000, 0, kStart), X4_ERR_IS_LOADED);
}

// ---- one segment: the exact profile ----------------------------------------

// Units = steps: the leader step j is at s = j and its time comes from the
// trapezoid t(s) in closed form; the engine computes it in integer ns.
TEST(PathProfile, OneSegmentMatchesTheTrapezoid) {
  const double v = 4000, a = 40000;
  const int n = 1000;
  Path p;
  ASSERT_EQ(p.Push(Seg(n, 300, 0, 0, n, uint32_t(v), uint32_t(a), 0)), X4_OK);
  Recording r;
  record(p.e, r);
  const auto st = LeaderSteps(r, p.sent);
  ASSERT_EQ(st.size(), size_t(n));
  const double origin = (kStart + X4_DIR_SETUP_NS) * 1e-9, sa = v * v / (2 * a), ta = v / a;
  double worst = 0;
  for (const Sample &x : st) {
    double t;
    if (x.s <= sa)
      t = std::sqrt(2 * x.s / a);
    else if (x.s <= n - sa)
      t = ta + (x.s - sa) / v;
    else
      t = 2 * ta + (n - 2 * sa) / v - std::sqrt(2 * (n - x.s) / a);
    worst = std::max(worst, std::fabs(x.t - origin - t) * 1e9);
  }
  std::printf("[ edges    ] one segment against the trapezoid: max error %.1f ns\n", worst);
  EXPECT_LT(worst, 20);
  p.ExpectAtTarget();
  EXPECT_EQ(p.Status().done, 1u);
  EXPECT_EQ(p.Status().state, X4_PATH_IDLE);
}

// The timer runs a segment at whole leader steps/s^2: 1 unit/s^2 over 199
// steps in 100 units is 1.99 steps/s^2, run at 1. The plan must use what
// runs, or the second segment is entered too fast to stop in it.
TEST(PathProfile, LeaderAccelerationIsPlannedAsRun) {
  Path p;
  ASSERT_EQ(p.Push(Seg(1990, 0, 0, 0, 1000, 1000, 1, 1000)), X4_OK);
  ASSERT_EQ(p.Push(Seg(199, 0, 0, 0, 100, 1000, 1, 1000)), X4_OK);
  Recording r;
  RunToEnd(p, r);
}

// ---- many segments ---------------------------------------------------------

TEST(PathRun, CircleRunsThroughCornersAndEndsExactly) {
  Path p;
  const auto segs = Circle(2000, 72, 20000, 200000, 20000);
  for (const auto &s : segs) ASSERT_EQ(p.Push(s), X4_OK);
  Recording r;
  double worst = 0;
  const auto st = RunToEnd(p, r, SIZE_MAX, &worst);
  std::printf("[ physics  ] circle of 72 chords: largest acceleration %.3f of the limit\n", worst);
  // Look-ahead keeps speed through the corners: no interval at a
  // junction is longer than twice the longer of its neighbours.
  for (size_t k = 1; k + 1 < st.size(); k++) {
    if (st[k].seg == st[k + 1].seg || st[k].seg == 0) continue;
    const double before = st[k].t - st[k - 1].t, at = st[k + 1].t - st[k].t;
    const double after = k + 2 < st.size() ? st[k + 2].t - st[k + 1].t : at;
    EXPECT_LT(at, 2 * std::max(before, after)) << "gap at the junction before segment " << st[k + 1].seg;
  }
  // The path reached speed (about 20 000 units/s = 2000 steps/s).
  double fastest = 0;
  for (size_t k = 1; k < st.size(); k++)
    fastest = std::max(fastest, (st[k].s - st[k - 1].s) / (st[k].t - st[k - 1].t));
  EXPECT_GT(fastest, 19000);
  EXPECT_EQ(p.Status().done, segs.size());
}

// 400 collinear pieces of 10 steps, each far too short to reach speed and
// stop again alone: the look-ahead over the queue lets the path run at its
// speed through all of them.
std::vector<x4_segment> Line(int n, uint32_t v_max) {
  std::vector<x4_segment> out;
  for (int k = 0; k < n; k++) out.push_back(Seg(10, 3, 0, 0, 100, v_max, 100000, v_max, k));
  return out;
}

double Fastest(const std::vector<Sample> &st, size_t from = 1, size_t to = SIZE_MAX) {
  double v = 0;
  for (size_t k = std::max<size_t>(from, 1); k < std::min(to, st.size()); k++)
    v = std::max(v, (st[k].s - st[k - 1].s) / (st[k].t - st[k - 1].t));
  return v;
}

TEST(PathRun, LookAheadOverShortSegments) {
  Path p(512);
  for (const auto &s : Line(400, 20000)) ASSERT_EQ(p.Push(s), X4_OK);
  Recording r;
  const auto st = RunToEnd(p, r);
  EXPECT_GT(Fastest(st), 19900);  // alone, one would reach sqrt(2 a s) = 4472
}

// An override raised while the path runs raises the planned speeds of the
// whole queue (a full backward pass, not only the appended end).
TEST(PathOverride, RaisedOverrideReplansTheQueue) {
  Path p(512);
  ASSERT_EQ(x4_path_set_override(&p.e, 50), X4_OK);
  for (const auto &s : Line(400, 20000)) ASSERT_EQ(p.Push(s), X4_OK);
  Recording r;
  record(p.e, r, 1000);
  ASSERT_EQ(x4_path_set_override(&p.e, 100), X4_OK);
  x4_path_replan(&p.e);
  x4_path_kick(&p.e, x4_engine_due(&p.e));
  const auto st = RunToEnd(p, r);
  EXPECT_LT(Fastest(st, 1, 400), 10000 * 1.001 + 30);
  EXPECT_GT(Fastest(st, 1000), 19900);
}

// A sharp corner (the user's junction speed) slows the path down there.
TEST(PathRun, CornerSpeedIsKept) {
  Path p;
  ASSERT_EQ(p.Push(Seg(4000, 0, 0, 0, 4000, 4000, 40000, 0)), X4_OK);
  ASSERT_EQ(p.Push(Seg(0, 4000, 0, 0, 4000, 4000, 40000, 500)), X4_OK);
  Recording r;
  const auto st = RunToEnd(p, r);
  const size_t j = 4000;  // first step of segment 2
  ASSERT_EQ(st[j].seg, 1u);
  const double v = (st[j].s - st[j - 1].s) / (st[j].t - st[j - 1].t);
  EXPECT_LT(v, 500 * 1.01 + 40);  // + what accelerating over one step adds
  EXPECT_GT(v, 400);
}

// Segments arrive while the path runs, in bursts; the queue as planned
// always ends at rest: when the writer is late the path slows down and
// stops on it, and goes on when segments come.
TEST(PathRun, SlowWriterNeverBreaksTheLimits) {
  Path p(64);
  const auto segs = Circle(3000, 400, 30000, 300000, 30000);
  std::mt19937 rng(7);
  size_t next = 0;
  Recording r;
  std::vector<uint64_t> rests;  // when the path stood, dry
  ASSERT_EQ(p.Push(segs[next++]), X4_OK);
  uint64_t events = 0;
  while (next < segs.size() || x4_engine_busy(&p.e)) {
    if (!x4_engine_busy(&p.e)) {  // ran dry and stopped: the writer comes later
      rests.push_back(r.events.back().t_ns);
      ASSERT_EQ(p.Push(segs[next++], rests.back() + 5000000), X4_OK);
      continue;
    }
    record(p.e, r, 1);
    if (++events % (1 + rng() % 3000) == 0 && x4_engine_busy(&p.e)) {
      const int burst = rng() % 6;
      for (int k = 0; k < burst && next < segs.size() && x4_path_room(&p.e); k++)
        ASSERT_EQ(p.Push(segs[next++], x4_engine_due(&p.e)), X4_OK);
    }
  }
  const auto st = RunToEnd(p, r);  // it has ended: checks only
  // Every standstill in between came at the end of a ramp too.
  int stops = 0;
  for (size_t k = 2; k < st.size(); k++) {
    const auto stood = [&](uint64_t t) { return st[k - 1].t * 1e9 <= t && t < st[k].t * 1e9; };
    if (!std::any_of(rests.begin(), rests.end(), stood)) continue;
    stops++;
    const double last = st[k - 1].t - st[k - 2].t,
                 rest = std::sqrt(2 * (st[k - 1].s - st[k - 2].s) / segs[st[k - 1].seg].accel);
    EXPECT_GE(last, 0.95 * rest) << "stopped from speed before leader step " << k;
  }
  EXPECT_EQ(size_t(stops), rests.size());
  std::printf("[ stream   ] 400 chords, a slow writer: %d standstills, %llu starved\n", stops,
              (unsigned long long)p.Status().starved);
  EXPECT_GT(stops, 0);  // the writer was slow indeed
  EXPECT_GT(p.Status().starved, 0u);
}

// ---- the planner's cost (issue 28 item 6) -------------------------------------

// Short segments whose queue is far shorter than their stop distance (4
// steps each, 20000 steps/s, 1000 steps/s^2: 200 000 steps to stop, a
// queue of 4096 holds 16 384): every push can raise every entry.
x4_segment Short() { return Seg(4, 0, 0, 0, 4, 20000, 1000, 20000); }

// The plan of the whole queue at once, from the slots (x4_path.c's rule):
// each entry as high as its limit and the stop of what follows allow.
std::vector<uint32_t> FullPlan(const x4_engine &e) {
  const x4_path &pa = e.path;
  std::vector<uint32_t> v(pa.tail - pa.head);
  uint64_t exit = 0;
  for (size_t i = v.size(); i-- > 1;) {
    const x4_path_slot &s = pa.slot[(pa.head + i) & (pa.depth - 1)];
    v[i] = uint32_t(std::min<uint64_t>(s.limit, x4_isqrt(exit * exit + s.two_as)));
    exit = v[i];
  }
  return v;
}

// The queue as planned ends at rest: every segment can brake from its
// entry to the next one's (the last one's to rest), within its limit.
void ExpectSafe(const x4_engine &e, const std::string &when) {
  const x4_path &pa = e.path;
  uint64_t exit = 0;
  for (uint32_t i = pa.tail - pa.head; i-- > 1;) {
    const uint32_t k = pa.head + i;
    const x4_path_slot &s = pa.slot[k & (pa.depth - 1)];
    ASSERT_LE(s.entry, s.limit) << when << ", slot " << k;
    ASSERT_LE(uint64_t(s.entry) * s.entry, exit * exit + s.two_as)
        << when << ": slot " << k << " cannot stop";
    exit = s.entry;
  }
}

// A path of `n` Short() segments streamed through a queue of `depth`: the
// writer pushes whenever there is room, the timer runs between. Bounded:
// the module's push, and its work item going on with the pass every 4 ms
// (a jiffy at 250 Hz), X4_PATH_PLAN_WORK entries; else every pass run
// through at each push (the planner before it was bounded). Returns the
// path's time; *most: the most entries one push planned.
double Stream(Path &p, size_t n, bool bounded, uint64_t *most, const char *what) {
  Recording r;
  size_t next = 0;
  uint64_t work_at = 0;
  *most = 0;
  while (next < n || x4_engine_busy(&p.e)) {
    const uint64_t t = r.events.empty() ? kStart : r.events.back().t_ns;
    if (bounded && t >= work_at) {  // x4step_path_plan_work()
      x4_path_plan(&p.e, X4_PATH_PLAN_WORK);
      if (p.e.path.state != X4_PATH_IDLE) x4_path_kick(&p.e, t);
      work_at = t + 4000000;
    }
    while (next < n && x4_path_room(&p.e)) {
      const uint64_t before = p.e.path.planned;
      const x4_segment s = Short();
      const uint64_t now = r.events.empty() ? kStart : r.events.back().t_ns;
      if (x4_path_check(&p.e, &s)) {
        ADD_FAILURE() << "refused";
        return 0;
      }
      x4_path_push(&p.e, &s);
      if (!bounded)
        while (x4_path_plan(&p.e, UINT32_MAX)) {
        }
      *most = std::max(*most, p.e.path.planned - before);
      p.sent.push_back(s);
      p.target[0] += s.steps[0];
      x4_path_kick(&p.e, now);
      if (next % 97 == 0) ExpectSafe(p.e, std::string(what) + ", push " + std::to_string(next));
      next++;
    }
    record(p.e, r, 1);
  }
  RunToEnd(p, r);
  return (r.events.back().t_ns - kStart) * 1e-9;
}

// With the queue shorter than the stop distance, every push raised every
// entry back to the head: thousands of entries per push at depth 4096.
// Now a push plans at most X4_PATH_PLAN_BUDGET entries, whatever the
// depth, and the queue as planned still ends at rest after every push;
// the path obeys the physics and its time is within 1 % of the unbounded
// planner's (the entries near the head lag behind by a few passes).
TEST(PathPlanner, BoundedWorkPerPush) {
  for (uint32_t depth : {256u, 4096u}) {
    const size_t n = 3 * depth;
    Path ref(depth), p(depth);
    uint64_t ref_most = 0, most = 0;
    const double t_ref = Stream(ref, n, false, &ref_most, "unbounded");
    const double t = Stream(p, n, true, &most, "bounded");
    std::printf(
        "[ planner  ] depth %u, %zu short segments: most entries a push planned %llu (unbounded %llu); "
        "path %.4f s (unbounded %.4f s, %+.3f %%)\n",
        depth, n, (unsigned long long)most, (unsigned long long)ref_most, t, t_ref, (t / t_ref - 1) * 100);
    EXPECT_GT(ref_most, depth / 2) << "a push raises about every entry unbounded: the worst case";
    EXPECT_LE(most, uint64_t(X4_PATH_PLAN_BUDGET));
    EXPECT_LE(t, t_ref * 1.01);
  }
}

// Where the stop distance is shorter than a segment, an entry that does
// not change ends the pass: a push plans the entry before it, and stops
// at the one before that (at its limit).
TEST(PathPlanner, UnchangedEntryEndsThePass) {
  Path p(4096);
  const x4_segment s = Seg(1000, 0, 0, 0, 1000, 2000, 20000, 2000);  // 100 steps to stop
  uint64_t most = 0;
  for (int k = 0; k < 4096; k++) {
    const uint64_t before = p.e.path.planned;
    ASSERT_EQ(x4_path_check(&p.e, &s), X4_OK);
    x4_path_push(&p.e, &s);
    most = std::max(most, p.e.path.planned - before);
  }
  EXPECT_LE(most, 2u);
  EXPECT_EQ(FullPlan(p.e)[4000], 2000u);
  EXPECT_EQ(p.e.path.slot[4000].entry, 2000u);
}

// A pass that has not come through leaves entries lower, never higher,
// than the full plan; given the pushes' budget again and again it comes
// to exactly the full plan.
TEST(PathPlanner, ConvergesToTheFullPlan) {
  Path p(4096);
  for (int k = 0; k < 4096; k++) {
    const x4_segment s = Short();
    ASSERT_EQ(x4_path_check(&p.e, &s), X4_OK);
    x4_path_push(&p.e, &s);  // not started: the head stays
  }
  const std::vector<uint32_t> full = FullPlan(p.e);
  const x4_path &pa = p.e.path;
  size_t lower = 0;
  for (size_t i = 1; i < full.size(); i++) {
    const uint32_t entry = pa.slot[(pa.head + i) & (pa.depth - 1)].entry;
    ASSERT_LE(entry, full[i]) << "slot " << i;
    lower += entry < full[i];
  }
  EXPECT_GT(lower, 0u) << "the last pass had not come through";
  int calls = 0;
  while (x4_path_plan(&p.e, X4_PATH_PLAN_BUDGET) && calls < 4096) calls++;
  EXPECT_LE(calls, 4096 / X4_PATH_PLAN_BUDGET + 1);
  for (size_t i = 1; i < full.size(); i++)
    ASSERT_EQ(pa.slot[(pa.head + i) & (pa.depth - 1)].entry, full[i]) << "slot " << i;
  EXPECT_FALSE(x4_path_plan(&p.e, X4_PATH_PLAN_BUDGET)) << "through: nothing left";
  ExpectSafe(p.e, "converged");
  // The path it runs stops at its end, within the physics.
  p.sent.assign(4096, Short());
  p.target[0] = 4096 * 4;
  ASSERT_TRUE(x4_path_kick(&p.e, kStart));
  Recording r;
  RunToEnd(p, r);
}

// ---- hold, resume, abort, override -----------------------------------------

TEST(PathHold, HoldAndResumeChangeNoStep) {
  const auto segs = Circle(2000, 36, 20000, 100000, 20000);
  Path ref;
  for (const auto &s : segs) ASSERT_EQ(ref.Push(s), X4_OK);
  Recording rr;
  record(ref.e, rr);

  Path p;
  for (const auto &s : segs) ASSERT_EQ(p.Push(s), X4_OK);
  Recording r;
  record(p.e, r, 3000);
  ASSERT_EQ(x4_path_hold(&p.e, false), X4_OK);
  EXPECT_EQ(p.Status().state, X4_PATH_HOLDING);
  record(p.e, r);  // brakes along the path to rest
  EXPECT_EQ(p.Status().state, X4_PATH_HELD);
  EXPECT_FALSE(x4_engine_busy(&p.e));
  const x4_move m = Move(1, 0, 0, 0, 100, 0);
  EXPECT_EQ(x4_engine_load(&p.e, &m), X4_OK);
  EXPECT_EQ(x4_engine_start(&p.e, kStart), X4_ERR_IS_ACTIVE);  // the path owns the axes
  const uint64_t held_at = r.events.back().t_ns;
  ASSERT_EQ(x4_path_resume(&p.e, held_at + 100000000), X4_OK);
  const auto st = RunToEnd(p, r);
  for (int i = 0; i < X4_AXES; i++) EXPECT_EQ(r.rises[i].size(), rr.rises[i].size()) << "axis " << i;
  // The hold came to rest from speed along a ramp: find the standstill.
  bool found = false;
  for (size_t k = 2; k < st.size(); k++) {
    if (st[k].t - st[k - 1].t < 0.05) continue;
    found = true;
    const double last = st[k - 1].t - st[k - 2].t;
    EXPECT_GE(last, 0.95 * std::sqrt(2 * (st[k - 1].s - st[k - 2].s) / segs[st[k - 1].seg].accel));
  }
  EXPECT_TRUE(found);
  // The step order of every axis is that of the uninterrupted run.
  EXPECT_EQ(p.e.pos_base[0] + uint32_t(p.e.steps[0]), ref.e.pos_base[0] + uint32_t(ref.e.steps[0]));
}

// Six collinear segments of growing length, held at every event from the
// first to the last: each hold must brake to rest within the limits and
// stand on the path; a resume must end exactly where the path ends.
std::vector<x4_segment> Six() {
  std::vector<x4_segment> out;
  for (int j = 0; j < 6; j++) out.push_back(Seg(200 + 37 * j, 0, 0, 0, 200 + 37 * j, 4000, 20000, 4000));
  return out;
}

TEST(PathHold, AtEveryMomentBrakesAndResumes) {
  int holds = 0;
  for (size_t k = 1;; k += 3) {
    Path p(16);
    for (const auto &s : Six()) ASSERT_EQ(p.Push(s), X4_OK);
    Recording r;
    record(p.e, r, k);
    if (!x4_engine_busy(&p.e)) break;
    if (x4_path_hold(&p.e, false) != X4_OK) continue;
    holds++;
    record(p.e, r, 100000);
    ASSERT_FALSE(x4_engine_busy(&p.e)) << "hold at event " << k << " never stood";
    const x4_path_status st = p.Status();
    ASSERT_TRUE(st.state == X4_PATH_HELD || (st.state == X4_PATH_IDLE && !st.queued)) << "event " << k;
    if (st.state == X4_PATH_HELD) {
      ASSERT_EQ(x4_path_resume(&p.e, r.events.back().t_ns + 1000000), X4_OK);
    }
    RunToEnd(p, r, 100000);
    ASSERT_EQ(p.Status().state, X4_PATH_IDLE) << "event " << k;
    if (HasFailure()) {
      ADD_FAILURE() << "hold at event " << k;
      return;
    }
  }
  EXPECT_GT(holds, 500);
}

TEST(PathOverride, DropAtEveryMomentKeepsTheLimits) {
  for (uint32_t pct : {1u, 30u}) {
    for (size_t k = 1;; k += 7) {
      Path p(16);
      for (const auto &s : Six()) ASSERT_EQ(p.Push(s), X4_OK);
      Recording r;
      record(p.e, r, k);
      if (!x4_engine_busy(&p.e)) break;
      ASSERT_EQ(x4_path_set_override(&p.e, pct), X4_OK);
      x4_path_replan(&p.e);
      x4_path_kick(&p.e, x4_engine_due(&p.e));
      // At 1 %, event 2710: a brake to the new cruise speed that ends
      // at the last segment's end must still end at rest.
      RunToEnd(p, r);
      if (HasFailure()) {
        ADD_FAILURE() << "override " << pct << " % at event " << k;
        return;
      }
    }
  }
}

// A segment written while the channel still ends a path that ran dry (the
// direction hold after its last step) starts when that end comes.
TEST(PathRun, PushWhileADryPathEnds) {
  Path p(16);
  x4_timing t = p.e.timing;
  t.dir_hold_ns = 40000;
  ASSERT_EQ(x4_engine_configure(&p.e, &t, X4_MODE_CLOCK_DIR), X4_OK);
  ASSERT_EQ(p.Push(Seg(50, 0, 0, 0, 50, 2000, 20000, 2000)), X4_OK);
  Recording r;
  while (x4_engine_busy(&p.e) && p.e.path.head != p.e.path.tail) record(p.e, r, 1);
  ASSERT_TRUE(x4_engine_busy(&p.e));  // the hold time after the last step
  ASSERT_EQ(p.Push(Seg(50, 0, 0, 0, 50, 2000, 20000, 2000), x4_engine_due(&p.e) - 1), X4_OK);
  record(p.e, r);
  p.ExpectAtTarget();
  EXPECT_EQ(p.Status().state, X4_PATH_IDLE);
  EXPECT_EQ(p.Status().queued, 0u);
}

// A hold before the first step, then a resume: the path runs.
// A hold whose brake ends right at a junction into a segment with a
// longer leader step (in path units): the entry there rounds down to 0
// steps/s. The path must stand HELD at the segment's start, not plan a
// cruise at 0 steps/s (a division by zero in the timer), and a resume
// must run it to its end.
TEST(PathHold, BrakeEndingAtACoarserSegmentsStart) {
  Path p;
  ASSERT_EQ(p.Push(Seg(400, 0, 0, 0, 400, 4000, 2000, 0)), X4_OK);
  ASSERT_EQ(p.Push(Seg(100, 0, 0, 0, 300, 4000, 2000, 2)), X4_OK);
  Recording r;
  record(p.e, r, 516);
  ASSERT_EQ(x4_path_hold(&p.e, false), X4_OK);
  record(p.e, r);
  EXPECT_EQ(p.Status().state, X4_PATH_HELD);
  const uint64_t held_at = r.events.back().t_ns;
  ASSERT_EQ(x4_path_resume(&p.e, held_at + 100000000), X4_OK);
  record(p.e, r);
  EXPECT_EQ(p.Status().state, X4_PATH_IDLE);
  p.ExpectAtTarget();
  p.ExpectPinsAtTarget(r);
}

// A hold or a brake that comes while a write() has queued segments but not
// yet started them (the module's halts do not wait for the writer): the
// path stands HELD, the writer's kick does not start it, a resume does.
TEST(PathHold, HoldOrBrakeOfAQueuedPathBeforeItsStart) {
  for (bool brake : {false, true}) {
    SCOPED_TRACE(brake ? "brake" : "hold");
    Path p;
    const x4_segment s = Seg(300, 0, 0, 0, 300, 4000, 20000, 0);
    ASSERT_EQ(x4_path_check(&p.e, &s), X4_OK);
    x4_path_push(&p.e, &s);  // queued; the kick comes after the chunk
    p.sent.push_back(s);
    p.target[0] += s.steps[0];
    if (brake)
      EXPECT_EQ(x4_engine_brake(&p.e), X4_OK);
    else
      EXPECT_EQ(x4_path_hold(&p.e, false), X4_OK);
    EXPECT_EQ(p.Status().state, X4_PATH_HELD);
    EXPECT_FALSE(x4_path_kick(&p.e, kStart));
    Recording r;
    record(p.e, r);
    EXPECT_TRUE(r.rises[0].empty()) << "a held path moved";
    ASSERT_EQ(x4_path_resume(&p.e, kStart + 1000000), X4_OK);
    record(p.e, r);
    EXPECT_EQ(p.Status().state, X4_PATH_IDLE);
    p.ExpectAtTarget();
  }
}

TEST(PathHold, ResumeBeforeTheFirstStep) {
  Path p;
  ASSERT_EQ(p.Push(Seg(100, 0, 0, 0, 100, 2000, 20000, 0)), X4_OK);
  ASSERT_EQ(p.e.ch[0].phase, X4_SETUP);
  ASSERT_EQ(x4_path_hold(&p.e, false), X4_OK);
  ASSERT_EQ(x4_path_resume(&p.e, kStart), X4_OK);
  Recording r;
  record(p.e, r);
  p.ExpectAtTarget();
  EXPECT_EQ(p.Status().state, X4_PATH_IDLE);
}

// A path owns every axis: halting one it does not move now holds it too.
TEST(PathHold, HaltOfAnyAxisHoldsThePath) {
  Path p;
  ASSERT_EQ(p.Push(Seg(400, 0, 0, 0, 400, 2000, 20000, 0)), X4_OK);
  ASSERT_EQ(p.Push(Seg(0, 400, 0, 0, 400, 2000, 20000, 0)), X4_OK);
  Recording r;
  record(p.e, r, 100);  // in the first segment: only X moves
  ASSERT_EQ(x4_engine_halt(&p.e, 0x2, false), X4_OK);
  EXPECT_EQ(p.Status().state, X4_PATH_HOLDING);
  record(p.e, r);
  EXPECT_EQ(p.Status().state, X4_PATH_HELD);
}

TEST(PathHold, AbortAfterHoldFlushes) {
  Path p;
  for (const auto &s : Circle(2000, 36, 20000, 100000, 20000)) ASSERT_EQ(p.Push(s), X4_OK);
  Recording r;
  record(p.e, r, 2000);
  ASSERT_EQ(x4_path_hold(&p.e, true), X4_OK);  // hold, then abort
  record(p.e, r);
  const x4_path_status st = p.Status();
  EXPECT_EQ(st.state, X4_PATH_IDLE);
  EXPECT_EQ(st.queued, 0u);
  EXPECT_EQ(x4_path_resume(&p.e, kStart), X4_ERR_NOT_ACTIVE);
  CheckPhysics(LeaderSteps(r, p.sent), p.sent);
  // A new path starts from here.
  const int32_t x = p.e.pos_base[0] + int32_t(p.e.steps[0]);
  ASSERT_EQ(p.Push(Seg(100, 0, 0, 0, 1000, 20000, 100000, 0)), X4_OK);
  record(p.e, r);
  EXPECT_EQ(p.e.pos_base[0] + int32_t(p.e.steps[0]), x + 100);
}

TEST(PathHold, BrakeHoldsStopFlushes) {
  Path p;
  for (const auto &s : Circle(2000, 36, 20000, 100000, 20000)) ASSERT_EQ(p.Push(s), X4_OK);
  Recording r;
  record(p.e, r, 2000);
  ASSERT_EQ(x4_engine_brake(&p.e), X4_OK);
  EXPECT_EQ(p.Status().state, X4_PATH_HOLDING);
  record(p.e, r);
  EXPECT_EQ(p.Status().state, X4_PATH_HELD);
  EXPECT_GT(p.Status().queued, 0u);
  EXPECT_EQ(x4_engine_stop(&p.e), X4_OK);
  EXPECT_EQ(p.Status().state, X4_PATH_IDLE);
  EXPECT_EQ(p.Status().queued, 0u);
}

TEST(PathHold, EmergencyStopIsImmediate) {
  Path p;
  for (const auto &s : Circle(2000, 36, 20000, 100000, 20000)) ASSERT_EQ(p.Push(s), X4_OK);
  Recording r;
  record(p.e, r, 2000);
  const size_t rises = r.rises[0].size() + r.rises[1].size();
  ASSERT_EQ(x4_engine_stop(&p.e), X4_OK);
  record(p.e, r);
  EXPECT_LE(r.rises[0].size() + r.rises[1].size(), rises + 1);
  EXPECT_EQ(p.Status().state, X4_PATH_IDLE);
  EXPECT_EQ(p.Status().queued, 0u);
}

TEST(PathOverride, HalfSpeedFromTheNextStep) {
  Path p;
  ASSERT_EQ(p.Push(Seg(20000, 0, 0, 0, 20000, 10000, 100000, 0)), X4_OK);
  Recording r;
  record(p.e, r, 6000);  // cruising at 10 000 by now
  ASSERT_EQ(x4_path_set_override(&p.e, 50), X4_OK);
  x4_path_replan(&p.e);
  const auto st = RunToEnd(p, r);
  // The change began at once: the next intervals grow; later it cruises at 5000.
  const size_t k = r.rises[0].size() > 3100 ? 3000 : 0;
  ASSERT_GT(k, 0u);
  const double v_before = 1 / (st[k].t - st[k - 1].t);
  EXPECT_NEAR(v_before, 10000, 10);
  const double v_mid = 1 / (st[15000].t - st[14999].t);
  EXPECT_NEAR(v_mid, 5000, 5);
  EXPECT_EQ(x4_path_set_override(&p.e, 0), X4_ERR_PARAM_FAIL);
  EXPECT_EQ(x4_path_set_override(&p.e, 201), X4_ERR_PARAM_FAIL);
}

TEST(PathOverride, AboveHundredIsCappedByThePort) {
  Path p;
  // 200 % of 60000 steps/s: capped at the engine's ceiling (and the write budget's).
  ASSERT_EQ(p.Push(Seg(100000, 0, 0, 0, 100000, 60000, 1000000, 0)), X4_OK);
  ASSERT_EQ(x4_path_set_override(&p.e, 200), X4_OK);
  Recording r;
  record(p.e, r);
  const auto st = LeaderSteps(r, p.sent);
  double fastest = 0;
  for (size_t k = 1; k < st.size(); k++) fastest = std::max(fastest, 1 / (st[k].t - st[k - 1].t));
  EXPECT_LE(fastest, X4_VEL_MAX * 1.001);
  EXPECT_GT(fastest, X4_VEL_MAX * 0.99);
}

// ---- status, switches, directions -------------------------------------------

TEST(PathStatus, TagsAndCounts) {
  Path p;
  ASSERT_EQ(p.Push(Seg(300, 0, 0, 0, 300, 3000, 30000, 3000, 11)), X4_OK);
  ASSERT_EQ(p.Push(Seg(0, 300, 0, 0, 300, 3000, 30000, 3000, 22)), X4_OK);
  ASSERT_EQ(p.Push(Seg(-300, 0, 0, 0, 300, 3000, 30000, 3000, 33)), X4_OK);
  x4_path_status st = p.Status();
  EXPECT_EQ(st.queued, 3u);
  EXPECT_EQ(st.tag, 11u);
  EXPECT_EQ(st.state, X4_PATH_RUN);
  std::vector<uint64_t> tags;
  uint32_t fastest = 0;
  while (x4_engine_busy(&p.e)) {
    fire(p.e);
    st = p.Status();
    fastest = std::max(fastest, st.speed);
    if (st.queued && (tags.empty() || tags.back() != st.tag)) tags.push_back(st.tag);
  }
  EXPECT_EQ(tags, (std::vector<uint64_t>{11, 22, 33}));
  EXPECT_EQ(st.done, 3u);
  EXPECT_EQ(st.queued, 0u);
  EXPECT_NEAR(fastest, 3000, 30);
}

TEST(PathSwitches, LimitStopsThePathAtOnce) {
  Path p;
  x4_switches sw{};
  sw.minus[0] = 1;  // the circle's first chords move X toward E-
  ASSERT_EQ(x4_switch_set(&p.e, &sw), X4_OK);
  for (const auto &s : Circle(2000, 36, 20000, 100000, 20000)) ASSERT_EQ(p.Push(s), X4_OK);
  Recording r;
  record(p.e, r, 500);
  const size_t rises = r.rises[0].size();
  x4_switch_sense(&p.e, 0x01);  // E+ of X active: X moves toward it
  record(p.e, r);
  EXPECT_LE(r.rises[0].size(), rises + 1);
  EXPECT_TRUE(p.e.err[0] & X4_AXERR_LIMIT_NEG);
  EXPECT_EQ(p.Status().state, X4_PATH_IDLE);
  EXPECT_EQ(p.Status().queued, 0u);
}

// Runs two segments in which axis Y reverses at the joint; returns the
// events, the time Y's direction pin changed and Y's first step after it.
struct Reversal {
  Recording r;
  uint64_t dir_change = 0, y_step = 0;
};

Reversal RunReversal(Path &p, int32_t x, int32_t y, uint32_t v_max, uint32_t accel) {
  Reversal rv;
  EXPECT_EQ(p.Push(Seg(x, y, 0, 0, uint32_t(x), v_max, accel, v_max)), X4_OK);
  EXPECT_EQ(p.Push(Seg(x, -y, 0, 0, uint32_t(x), v_max, accel, v_max)), X4_OK);
  uint8_t data = p.e.data;
  bool started = false;
  while (x4_engine_busy(&p.e)) {
    const x4_event ev = fire(p.e);
    if (started && ((data ^ ev.data) & X4_DIR_BIT(1))) rv.dir_change = ev.t_ns;
    if (rv.dir_change && !rv.y_step && (ev.data & ~data & X4_CLK_BIT(1))) rv.y_step = ev.t_ns;
    started = started || (ev.data & X4_CLK_MASK);
    data = ev.data;
    rv.r.events.push_back(ev);
  }
  return rv;
}

std::vector<uint64_t> RisesOf(const Recording &r, int axis) {
  std::vector<uint64_t> out;
  uint8_t d = 0;
  for (const auto &ev : r.events) {
    if (ev.data & ~d & X4_CLK_BIT(axis)) out.push_back(ev.t_ns);
    d = ev.data;
  }
  return out;
}

// A path starts from rest as a move does: its directions go out when the
// timer fires, and the setup time, with the whole path, counts from then,
// not from the write() or resume that kicked it (the module plans the first
// piece in between, and its timer may be late): every edge of a path whose
// start fired 7 us late, and of its resume after a hold, comes exactly
// 7 us after the punctual run's, so none follows its direction change
// sooner than the setup time.
TEST(PathSignals, LateStartShiftsTheWholePath) {
  const std::vector<x4_segment> segs = {Seg(300, -100, 0, 0, 316, 8000, 200000, 0),
                                        Seg(-100, 200, 50, 0, 229, 8000, 200000, 3000)};
  Path punctual, late;
  for (const x4_segment &s : segs) {
    ASSERT_EQ(punctual.Push(s), X4_OK);
    ASSERT_EQ(late.Push(s), X4_OK);
  }
  constexpr uint64_t kLate = 7000;
  const auto run = [&](Path &p, uint64_t lateness, Recording &r) {
    r.events.push_back(fire(p.e, x4_engine_due(&p.e) + lateness));  // SETUP
    record(p.e, r, 150);                                            // into the first segment: hold there
    EXPECT_EQ(x4_path_hold(&p.e, false), X4_OK);
    record(p.e, r);
    const uint64_t t = kStart + 1000000000;  // 1 s: long after it stood
    EXPECT_LT(r.events.back().t_ns, t);
    EXPECT_EQ(x4_path_resume(&p.e, t), X4_OK);
    r.events.push_back(fire(p.e, t + lateness));  // SETUP of the resume
    record(p.e, r);
  };
  Recording a, b;
  run(punctual, 0, a);
  run(late, kLate, b);
  punctual.ExpectAtTarget();
  late.ExpectAtTarget();
  late.ExpectPinsAtTarget(b);
  ASSERT_EQ(a.events.size(), b.events.size());
  for (int axis = 0; axis < 3; axis++) {
    const std::vector<uint64_t> ra = RisesOf(a, axis), rb = RisesOf(b, axis);
    ASSERT_EQ(ra.size(), rb.size()) << "axis " << axis;
    size_t shifted = 0;
    for (size_t i = 0; i < ra.size(); i++) shifted += rb[i] == ra[i] + kLate;
    EXPECT_EQ(shifted, ra.size()) << "axis " << axis << ": steps 7 us after the punctual run's";
  }
  EXPECT_GE(RisesOf(b, 0).front(), kStart + kLate + X4_DIR_SETUP_NS);
}

// Item 9: an axis that reverses at a junction must not step before its
// direction setup time: the planner caps the junction speed so that its
// first step after the reversal comes late enough (the setup time after the
// direction change, which comes after the last step's high time and the
// hold time), rather than the whole path stopping for it in the middle of
// the junction, a velocity step. Cases: the minor axis Y reversing and due
// at the first, third and 12th leader step; the leader reversing; each with
// the default timing, a direction hold time and a configured pulse. The
// path never stalls (CheckPhysics), the reversing axis waits its setup time
// (the pins), and the cap costs no more speed than it must.
struct ReversalCase {
  int32_t x1, y1, x2, y2;
  int axis;        // the axis that reverses
  uint32_t first;  // its first step in the second segment, in leader steps
};

TEST(PathSignals, ReversingAxisCapsTheJunctionSpeed) {
  const ReversalCase cases[] = {{2000, 1000, 2000, -1000, 1, 1},
                                {2000, 400, 2000, -400, 1, 3},
                                {2000, 90, 2000, -90, 1, 12},
                                {2000, 0, -2000, 0, 0, 1}};
  struct Timing {
    uint32_t setup, hold, pulse;
  };
  const Timing timings[] = {{X4_DIR_SETUP_NS, 0, 0}, {100000, 40000, 0}, {50000, 20000, 10000}};
  for (const ReversalCase &k : cases) {
    for (const Timing &tm : timings) {
      SCOPED_TRACE("axis " + std::to_string(k.axis) + " first at " + std::to_string(k.first) + ", setup " +
                   std::to_string(tm.setup) + " hold " + std::to_string(tm.hold) + " pulse " +
                   std::to_string(tm.pulse));
      Path p;
      x4_timing t = p.e.timing;
      t.dir_setup_ns = tm.setup;
      t.dir_hold_ns = tm.hold;
      t.pulse_ns = tm.pulse;
      t.space_ns = tm.pulse;
      ASSERT_EQ(x4_engine_configure(&p.e, &t, X4_MODE_CLOCK_DIR), X4_OK);
      ASSERT_EQ(p.Push(Seg(k.x1, k.y1, 0, 0, 2000, 40000, 1000000, 0)), X4_OK);
      ASSERT_EQ(p.Push(Seg(k.x2, k.y2, 0, 0, 2000, 40000, 1000000, 40000)), X4_OK);
      Recording r;
      uint64_t dir_change = 0, first_step = 0;
      uint8_t data = p.e.data;
      bool started = false;
      while (x4_engine_busy(&p.e)) {
        const x4_event ev = fire(p.e);
        if (started && ((data ^ ev.data) & X4_DIR_BIT(k.axis))) dir_change = ev.t_ns;
        if (dir_change && !first_step && (ev.data & ~data & X4_CLK_BIT(k.axis))) first_step = ev.t_ns;
        started = started || (ev.data & X4_CLK_MASK);
        data = ev.data;
        r.events.push_back(ev);
      }
      p.ExpectAtTarget();
      p.ExpectPinsAtTarget(r);
      ASSERT_NE(first_step, 0u);
      EXPECT_GT(first_step - dir_change, tm.setup) << "stepped before its direction setup, or waited for it";
      const std::vector<uint64_t> x = RisesOf(r, 0);
      ASSERT_EQ(x.size(), 4000u);
      const double worst = CheckPhysics(LeaderSteps(r, p.sent), p.sent);
      EXPECT_LT(worst, 0.01) << "the path stalled at the junction";
      // The junction speed: what lets the first step come after the high
      // time (half the interval, or the pulse), the hold and the setup.
      // With the ramp from there: j = v D + a D^2 / 2, D = high + hold +
      // setup, high = 1 / (2 v) or the pulse.
      const double h = (tm.setup + tm.hold + tm.pulse) * 1e-9, a = 1e6;
      double cap = 40000;
      for (int it = 0; it < 50; it++) {
        const double d = h + (tm.pulse ? 0 : 0.5 / cap);
        cap = (k.first - (tm.pulse ? 0 : 0.5) - a * d * d / 2) / h;
      }
      // The leader's first step after the junction, from the entry speed.
      cap = std::min(cap, 40000.0);
      const double t1 = (std::sqrt(cap * cap + 2 * a) - cap) / a, dt = double(x[2000] - x[1999]) * 1e-9;
      EXPECT_GE(dt, t1 * 0.97) << "the junction is faster than its direction setup allows";
      EXPECT_LE(dt, t1 * 1.03) << "the junction is slower than it must be";
    }
  }
}

// The same where the segments' leader steps differ in length (units of
// 1/10 step; the second segment led by Y, whose steps are longer or
// shorter than the first's along the path): the high time of the step
// before the junction is the first segment's, the first step after it the
// second's. Y reverses, X does not.
TEST(PathSignals, ReversalCapAcrossDifferentStepLengths) {
  struct Case {
    int32_t x1, y1, x2, y2;
    uint32_t len1, len2;
  };
  const Case cases[] = {{2000, 1000, 500, -1000, 22360, 11180},
                        {2000, 1000, 1000, -1000, 22360, 14142},
                        {1000, 2000, 3000, -1000, 22360, 31623}};
  for (const Case &k : cases) {
    SCOPED_TRACE("len " + std::to_string(k.len1) + ", " + std::to_string(k.len2));
    Path p;
    x4_timing t = p.e.timing;
    t.dir_hold_ns = 20000;
    ASSERT_EQ(x4_engine_configure(&p.e, &t, X4_MODE_CLOCK_DIR), X4_OK);
    ASSERT_EQ(p.Push(Seg(k.x1, k.y1, 0, 0, k.len1, 300000, 5000000, 0)), X4_OK);
    ASSERT_EQ(p.Push(Seg(k.x2, k.y2, 0, 0, k.len2, 300000, 5000000, 300000)), X4_OK);
    Recording r;
    uint64_t dir_change = 0, first_step = 0;
    uint8_t data = p.e.data;
    bool started = false;
    while (x4_engine_busy(&p.e)) {
      const x4_event ev = fire(p.e);
      if (started && ((data ^ ev.data) & X4_DIR_BIT(1))) dir_change = ev.t_ns;
      if (dir_change && !first_step && (ev.data & ~data & X4_CLK_BIT(1))) first_step = ev.t_ns;
      started = started || (ev.data & X4_CLK_MASK);
      data = ev.data;
      r.events.push_back(ev);
    }
    p.ExpectAtTarget();
    p.ExpectPinsAtTarget(r);
    ASSERT_NE(first_step, 0u);
    EXPECT_GT(first_step - dir_change, X4_DIR_SETUP_NS)
        << "stepped before its direction setup, or waited for it";
    EXPECT_LT(first_step - dir_change, X4_DIR_SETUP_NS + 20000) << "a needlessly slow junction";
    EXPECT_LT(CheckPhysics(LeaderSteps(r, p.sent), p.sent), 0.01) << "the path stalled at the junction";
  }
}

// The cap plans the junction on time; a timer late for the direction
// change still makes the reversing axis wait for its setup time
// (dir_wait()), and only then: the junction's SETUP fired 60 us late.
TEST(PathSignals, LateDirectionChangeStillWaitsForTheSetup) {
  Path p;
  ASSERT_EQ(p.Push(Seg(2000, 1000, 0, 0, 2000, 40000, 1000000, 0)), X4_OK);
  ASSERT_EQ(p.Push(Seg(2000, -1000, 0, 0, 2000, 40000, 1000000, 40000)), X4_OK);
  Recording r;
  uint64_t dir_change = 0, first_step = 0;
  uint8_t data = p.e.data;
  bool started = false, late = false;
  while (x4_engine_busy(&p.e)) {
    const bool junction = started && p.e.ch[0].phase == X4_SETUP && p.e.ch[0].dir_fresh;
    late = late || junction;
    const uint64_t at = junction ? x4_engine_due(&p.e) + 60000 : 0;
    const x4_event ev = fire(p.e, at);
    if (started && ((data ^ ev.data) & X4_DIR_BIT(1))) dir_change = at ? at : ev.t_ns;  // when it went out
    if (dir_change && !first_step && (ev.data & ~data & X4_CLK_BIT(1))) first_step = ev.t_ns;
    started = started || (ev.data & X4_CLK_MASK);
    data = ev.data;
    r.events.push_back(ev);
  }
  ASSERT_TRUE(late);
  p.ExpectAtTarget();
  p.ExpectPinsAtTarget(r);
  ASSERT_NE(first_step, 0u);
  EXPECT_GE(first_step - dir_change, X4_DIR_SETUP_NS) << "stepped before its direction setup";
  EXPECT_LT(first_step - dir_change, X4_DIR_SETUP_NS + 1000) << "and waited no longer";
}

// A minor axis whose first step after the joint comes later than its setup
// time anyway (Y: 20 steps against 2000) does not make the path wait.
TEST(PathSignals, SlowReversingAxisLetsThePathRunOn) {
  Path p;
  const Reversal rv = RunReversal(p, 2000, 20, 2000, 20000);
  ASSERT_NE(rv.y_step, 0u);
  EXPECT_GE(rv.y_step - rv.dir_change, X4_DIR_SETUP_NS);
  p.ExpectAtTarget();
  p.ExpectPinsAtTarget(rv.r);
  const std::vector<uint64_t> x = RisesOf(rv.r, 0);
  ASSERT_EQ(x.size(), 4000u);
  for (size_t k = 1990; k < 2010; k++)
    EXPECT_NEAR(double(x[k + 1] - x[k]), 1e9 / 2000, 5) << "leader step " << k;
}

// Around a circle every axis reverses twice, minor at that moment: the
// pins must follow, and the path keeps its speed through the reversals.
TEST(PathSignals, CircleReversalsKeepSpeedAndPins) {
  Path p(512);
  // Chords of 4 steps at 10000 steps/s: a reversing axis' first step comes
  // as soon as 2 leader steps (200 us) after the junction.
  const auto segs = Circle(318, 500, 100000, 2000000, 100000);
  for (const auto &s : segs) ASSERT_EQ(p.Push(s), X4_OK);
  Recording r;
  const auto st = RunToEnd(p, r);
  for (size_t k = 1; k + 1 < st.size(); k++) {
    if (st[k].seg == st[k + 1].seg || st[k].seg < 100 || st[k].seg + 100 > segs.size()) continue;  // cruising
    const double v = (st[k + 1].s - st[k].s) / (st[k + 1].t - st[k].t);
    EXPECT_NEAR(v, 100000, 1000) << "junction before segment " << st[k + 1].seg;
  }
}

// An axis that stands still in a segment and moves again later, the other
// way, gets its direction pin set first: the pins, not the engine's own
// counters, must add up to the path (the QEMU test found the pin left as
// it was, so that such an axis stepped the wrong way).
TEST(PathSignals, AxisJoiningLaterGetsItsDirection) {
  Path p;
  ASSERT_EQ(p.Push(Seg(100, 100, 0, 0, 1414, 5000, 50000, 5000)), X4_OK);
  ASSERT_EQ(p.Push(Seg(100, 0, 0, 0, 1000, 5000, 50000, 5000)), X4_OK);
  ASSERT_EQ(p.Push(Seg(100, -100, 0, 0, 1414, 5000, 50000, 0)), X4_OK);
  Recording r;
  record(p.e, r);
  int pins[X4_AXES] = {0, 0, 0, 0};
  uint8_t data = 0;
  for (const auto &ev : r.events) {
    for (int i = 0; i < X4_AXES; i++)
      if ((ev.data & X4_CLK_BIT(i)) && !(data & X4_CLK_BIT(i))) pins[i] += (ev.data & X4_DIR_BIT(i)) ? 1 : -1;
    data = ev.data;
  }
  p.ExpectAtTarget();
  for (int i = 0; i < X4_AXES; i++) EXPECT_EQ(pins[i], p.target[i]) << "axis " << i << " from the pins";
}

// Segments of one step: every step ends a piece, and the clock's high time
// must fit the interval that follows, or each step delays the next.
TEST(PathRun, OneStepSegmentsKeepTheirSpeed) {
  Path p;
  for (int k = 0; k < 200; k++) ASSERT_EQ(p.Push(Seg(1, k % 3 == 0, 0, 0, 10, 30000, 3000000, 30000)), X4_OK);
  Recording r;
  const auto st = RunToEnd(p, r);
  double fastest = 0;
  for (size_t k = 1; k < st.size(); k++)
    fastest = std::max(fastest, (st[k].s - st[k - 1].s) / (st[k].t - st[k - 1].t));
  EXPECT_GT(fastest, 29000);  // 3000 steps/s, reached after 15 steps
}

// A segment appended while the path waits for its first step from rest
// cuts the running piece there; step 1's clock, high for half the time
// from rest, must not delay step 2 (the QEMU test saw step 2 0.3 ms late:
// a speed dip, then 1.4 times the acceleration limit).
TEST(PathRun, AppendDuringTheFirstStepKeepsTheRamp) {
  Path p;
  ASSERT_EQ(p.Push(Seg(0, 17, 0, 0, 170, 80000, 2000000, 0)), X4_OK);
  Recording r;
  record(p.e, r, 1);  // the directions are out, step 1 pending
  ASSERT_EQ(p.Push(Seg(-1, 17, 0, 0, 170, 80000, 2000000, 80000), x4_engine_due(&p.e)), X4_OK);
  RunToEnd(p, r);
  ASSERT_GE(r.rises[1].size(), 3u);
  const double a = 200000, t1 = std::sqrt(2 / a), t2 = std::sqrt(4 / a);
  EXPECT_NEAR((r.rises[1][1] - r.rises[1][0]) * 1e-9, t2 - t1, 1e-6);
}

// A full queue held, resumed, and refilled as room comes (as
// x4step::path::append() does): the path runs to its end.
TEST(PathHold, FullQueueHeldResumedAndRefilled) {
  for (size_t k : {0u, 1u, 2u, 5u, 40u, 400u}) {
    Path p;
    const x4_segment s = Seg(10, 0, 0, 0, 10, 2000, 20000, 2000);
    size_t pushed = 0;
    while (pushed < 256 && p.Push(s) == X4_OK) pushed++;
    ASSERT_EQ(pushed, 256u);
    Recording r;
    if (k) record(p.e, r, k);
    ASSERT_EQ(x4_path_hold(&p.e, false), X4_OK);
    record(p.e, r);
    ASSERT_EQ(p.Status().state, X4_PATH_HELD) << "hold after " << k << " events";
    const uint64_t t = r.events.empty() ? kStart + 1000000 : r.events.back().t_ns + 1000000;
    ASSERT_EQ(x4_path_resume(&p.e, t), X4_OK);
    while (x4_engine_busy(&p.e)) {
      record(p.e, r, 1);
      if (pushed < 300 && x4_path_room(&p.e) && p.Push(s, r.events.back().t_ns) == X4_OK) pushed++;
    }
    EXPECT_EQ(pushed, 300u);
    p.ExpectAtTarget();
    EXPECT_EQ(p.Status().state, X4_PATH_IDLE) << "hold after " << k << " events";
    EXPECT_EQ(p.Status().queued, 0u) << "hold after " << k << " events";
  }
}

// Pieces end at whole ns: a path of a thousand short pieces at its feed
// carries the fractions over, so its steps keep the pace of its speed
// (without the carry it ran 0.45 ns a piece ahead: 450 ns here).
TEST(PathRun, ThousandPiecesKeepThePace) {
  Path p(1024);
  for (int k = 0; k < 1000; k++) ASSERT_EQ(p.Push(Seg(7, 0, 0, 0, 7, 3000, 30000, 3000)), X4_OK);
  Recording r;
  RunToEnd(p, r);
  const std::vector<uint64_t> &t = r.rises[0];
  ASSERT_EQ(t.size(), 7000u);
  const size_t i = 1000, j = 6500;  // both in the cruise at 3000 steps/s
  const double ideal = (j - i) * 1e9 / 3000;
  EXPECT_NEAR(double(t[j] - t[i]), ideal, 2.0);
}

// ---- a hold is never forgotten (issue 28) ----------------------------------

namespace {

int32_t PosX(const Path &p) { return int32_t(p.e.pos_base[0] + uint32_t(p.e.steps[0])); }

// Records until axis X made `steps` steps (or the engine rests).
void RecordToStep(Path &p, Recording &r, size_t steps) {
  while (x4_engine_busy(&p.e) && size_t(PosX(p)) < steps) record(p.e, r, 1);
}

// Until the channel ends a path whose queue ran dry, or held: the settle
// window (dir_hold_ns, or a phase mode's last step period) after its last step.
void RecordToEnd(Path &p, Recording &r) {
  while (x4_engine_busy(&p.e) && p.e.ch[0].phase != X4_END) record(p.e, r, 1);
}

void Configure(Path &p, int mode) {
  x4_timing t = p.e.timing;
  if (mode == X4_MODE_CLOCK_DIR) t.dir_hold_ns = 40000;
  ASSERT_EQ(x4_engine_configure(&p.e, &t, mode), X4_OK);
}

}  // namespace

// Scenario A: a hold (or an abort) during a lone segment's final brake.
// The path comes to rest at the queue's end: it stands HELD (an abort:
// flushed), and a segment written then waits for a resume.
TEST(PathHoldAtTheEnd, HoldInTheFinalBrakeEndsHeld) {
  Path p;
  ASSERT_EQ(p.Push(Seg(2000, 0, 0, 0, 2000, 4000, 40000, 0)), X4_OK);
  Recording r;
  RecordToStep(p, r, 1900);
  ASSERT_EQ(PosX(p), 1900);
  const uint32_t flushes = p.e.path.flushes;
  ASSERT_EQ(x4_path_hold(&p.e, false), X4_OK);
  record(p.e, r);
  EXPECT_EQ(PosX(p), 2000);
  EXPECT_EQ(p.Status().state, X4_PATH_HELD);
  EXPECT_EQ(p.e.path.flushes, flushes);
  ASSERT_EQ(p.Push(Seg(3000, 0, 0, 0, 3000, 4000, 40000, 0), r.events.back().t_ns + 1000), X4_OK);
  record(p.e, r);
  EXPECT_EQ(PosX(p), 2000) << "a held path ran on without a resume";
  EXPECT_EQ(p.Status().state, X4_PATH_HELD);
  ASSERT_EQ(x4_path_resume(&p.e, r.events.back().t_ns + 1000000), X4_OK);
  record(p.e, r);
  EXPECT_EQ(PosX(p), 5000);
  EXPECT_EQ(p.Status().state, X4_PATH_IDLE);
}

TEST(PathHoldAtTheEnd, AbortInTheFinalBrakeFlushes) {
  Path p;
  ASSERT_EQ(p.Push(Seg(2000, 0, 0, 0, 2000, 4000, 40000, 0)), X4_OK);
  Recording r;
  RecordToStep(p, r, 1900);
  const uint32_t flushes = p.e.path.flushes;
  ASSERT_EQ(x4_path_hold(&p.e, true), X4_OK);
  record(p.e, r);
  EXPECT_EQ(PosX(p), 2000);
  EXPECT_EQ(p.Status().state, X4_PATH_IDLE);
  EXPECT_EQ(p.e.path.flushes, flushes + 1) << "an abort at the queue's end flushed nothing";
}

// Scenario B: the queue ran dry, a segment came in the settle window after
// the last step, then the controller went away (the glue's hold with
// abort, x4step_motion_path_brake_locked()): the path never moves again. A mere hold
// there stands HELD with the segment queued.
class PathSettle : public ::testing::TestWithParam<int> {};

TEST_P(PathSettle, AbortAfterARefillInTheSettleWindowFlushes) {
  Path p(16);
  Configure(p, GetParam());
  ASSERT_EQ(p.Push(Seg(50, 0, 0, 0, 50, 2000, 20000, 0)), X4_OK);
  Recording r;
  RecordToEnd(p, r);
  ASSERT_TRUE(x4_engine_busy(&p.e));
  ASSERT_EQ(p.e.path.head, p.e.path.tail);
  ASSERT_EQ(p.Push(Seg(3000, 0, 0, 0, 3000, 2000, 20000, 0), x4_engine_due(&p.e) - 1), X4_OK);
  const uint32_t flushes = p.e.path.flushes;
  ASSERT_EQ(x4_path_hold(&p.e, true), X4_OK);
  record(p.e, r);
  EXPECT_EQ(PosX(p), 50) << "the path ran on after its controller was gone";
  EXPECT_EQ(p.Status().state, X4_PATH_IDLE);
  EXPECT_EQ(p.Status().queued, 0u);
  EXPECT_EQ(p.e.path.flushes, flushes + 1);
}

TEST_P(PathSettle, HoldAfterARefillInTheSettleWindowEndsHeld) {
  Path p(16);
  Configure(p, GetParam());
  ASSERT_EQ(p.Push(Seg(50, 0, 0, 0, 50, 2000, 20000, 0)), X4_OK);
  Recording r;
  RecordToEnd(p, r);
  ASSERT_TRUE(x4_engine_busy(&p.e));
  ASSERT_EQ(p.Push(Seg(300, 0, 0, 0, 300, 2000, 20000, 0), x4_engine_due(&p.e) - 1), X4_OK);
  ASSERT_EQ(x4_path_hold(&p.e, false), X4_OK);
  record(p.e, r);
  EXPECT_EQ(PosX(p), 50);
  EXPECT_EQ(p.Status().state, X4_PATH_HELD);
  EXPECT_EQ(p.Status().queued, 1u);
  ASSERT_EQ(x4_path_resume(&p.e, r.events.back().t_ns + 1000000), X4_OK);
  record(p.e, r);
  EXPECT_EQ(PosX(p), 350);
  EXPECT_EQ(p.Status().state, X4_PATH_IDLE);
}

// Item 3: a resume in the settle window after a hold's last step goes on
// (mid-queue: the path runs to its end; at the queue's end: it is idle).
TEST_P(PathSettle, ResumeWhileAHoldEndsGoesOn) {
  Path p(16);
  Configure(p, GetParam());
  ASSERT_EQ(p.Push(Seg(400, 0, 0, 0, 400, 2000, 20000, 0)), X4_OK);
  ASSERT_EQ(p.Push(Seg(400, 0, 0, 0, 400, 2000, 20000, 2000)), X4_OK);
  Recording r;
  RecordToStep(p, r, 200);
  ASSERT_EQ(x4_path_hold(&p.e, false), X4_OK);
  RecordToEnd(p, r);
  ASSERT_TRUE(x4_engine_busy(&p.e));
  ASSERT_LT(PosX(p), 800);
  ASSERT_EQ(x4_path_resume(&p.e, x4_engine_due(&p.e) - 1), X4_OK);
  record(p.e, r);
  EXPECT_EQ(PosX(p), 800);
  EXPECT_EQ(p.Status().state, X4_PATH_IDLE) << "a resume in the settle window was lost";
  EXPECT_EQ(p.Status().queued, 0u);
  EXPECT_EQ(p.Status().starved, 0u) << "a hold is no want of segments";
  p.ExpectAtTarget();
  if (GetParam() == X4_MODE_CLOCK_DIR) {
    p.ExpectPinsAtTarget(r);
    CheckPhysics(LeaderSteps(r, p.sent), p.sent);
  }
}

TEST_P(PathSettle, ResumeWhileAHoldEndsAtTheQueuesEnd) {
  Path p(16);
  Configure(p, GetParam());
  ASSERT_EQ(p.Push(Seg(400, 0, 0, 0, 400, 2000, 20000, 0)), X4_OK);
  Recording r;
  RecordToStep(p, r, 380);
  ASSERT_EQ(x4_path_hold(&p.e, false), X4_OK);
  RecordToEnd(p, r);
  ASSERT_TRUE(x4_engine_busy(&p.e));
  ASSERT_EQ(x4_path_resume(&p.e, x4_engine_due(&p.e) - 1), X4_OK);
  record(p.e, r);
  EXPECT_EQ(PosX(p), 400);
  EXPECT_EQ(p.Status().state, X4_PATH_IDLE);
}

// Item 9: in the SMC phase modes a segment that comes in the settle window
// after a dry end restarts the path: the motors stay energized, as through
// any junction (the rest writes were cut short: motor X went off, and stayed
// off through a segment that moves only Y). Every pattern written until the
// path really ends is a motor's running pattern.
TEST(PathSettleSmc, RestartAfterADryEndKeepsTheMotorsOn) {
  const uint8_t kRun[8] = {0x03, 0x09, 0x38, 0x29, 0x27, 0x2d, 0x1c, 0x0d};  // x4_phase.c: smc_run
  for (const int mode : {int(X4_MODE_SMC_PHASE), int(X4_MODE_SMC_PHASE_HOLD)}) {
    Path p(16);
    Configure(p, mode);
    ASSERT_EQ(p.Push(Seg(50, 0, 0, 0, 50, 2000, 20000, 0)), X4_OK);
    ASSERT_EQ(p.Push(Seg(0, 20, 0, 0, 20, 2000, 20000, 0)), X4_OK);
    Recording r;
    RecordToEnd(p, r);
    ASSERT_TRUE(x4_engine_busy(&p.e));
    ASSERT_EQ(p.e.path.head, p.e.path.tail);
    const size_t from = r.events.size();
    ASSERT_EQ(p.Push(Seg(0, 300, 0, 0, 300, 2000, 20000, 0), x4_engine_due(&p.e) - 1), X4_OK);
    size_t y_steps = 0;
    do {  // from the end of the settle window to the end of the new segment
      record(p.e, r, 1);
      const uint8_t d = r.events.back().data;
      const int motor = d >> 6;
      if (motor < 2) {
        EXPECT_NE(std::find(std::begin(kRun), std::end(kRun), d & 0x3f), std::end(kRun))
            << "motor " << motor << " at rest (pattern " << (d & 0x3f) << ") at event "
            << r.events.size() - from;
      }
      y_steps += motor == 1;
    } while (x4_engine_busy(&p.e) && p.e.ch[0].phase != X4_END);
    EXPECT_GE(y_steps, 300u);
    record(p.e, r);
    EXPECT_EQ(p.e.pos_base[1] + uint32_t(p.e.steps[1]), 320u);
    EXPECT_EQ(p.Status().state, X4_PATH_IDLE);
  }
}

INSTANTIATE_TEST_SUITE_P(Modes, PathSettle, ::testing::Values(int(X4_MODE_CLOCK_DIR), int(X4_MODE_SMC_PHASE)),
                         [](const ::testing::TestParamInfo<int> &i) {
                           return std::string(i.param ? "SmcPhase" : "ClockDir");
                         });

// ---- who aborts a path, and what the event stream says (issue 28) ----------

// Item 8: an emergency brake aborts a path, as a close does; a brake key
// only with X4STEP_PATH_KEYS_ABORT; X4STEP_BRAKE and HALT only hold it.
TEST(PathAbort, EmergencyBrakeAbortsAsACloseDoes) {
  EXPECT_TRUE(x4_req_brake_aborts_path(X4STEP_SRC_ESTOP, 0));
  EXPECT_TRUE(x4_req_brake_aborts_path(X4STEP_SRC_CLOSE, 0));
  EXPECT_FALSE(x4_req_brake_aborts_path(X4STEP_SRC_KEY, 0));
  EXPECT_TRUE(x4_req_brake_aborts_path(X4STEP_SRC_KEY, X4STEP_PATH_KEYS_ABORT));
  EXPECT_FALSE(x4_req_brake_aborts_path(X4STEP_SRC_IOCTL, X4STEP_PATH_KEYS_ABORT));
}

namespace {

struct Pushed {
  uint32_t type, axes, how;
};
std::vector<Pushed> pushed;

void PushEvent(x4_track *, u32 type, u32 axes, u32 how, u32, u32) { pushed.push_back({type, axes, how}); }

}  // namespace

// Item 9: the abort of a held path (no channel runs it) ends it in the
// event stream at once; a running path's abort is told by its end; the
// abort of no path marks nothing (the next path's end would say ABORTED).
TEST(PathAbort, AbortOfAHeldPathIsToldAtOnce) {
  x4_track t{};
  t.push = PushEvent;
  pushed.clear();
  {
    Path p;
    ASSERT_EQ(p.Push(Seg(2000, 0, 0, 0, 2000, 4000, 40000, 0)), X4_OK);
    Recording r;
    record(p.e, r, 200);
    ASSERT_EQ(x4_track_path_abort(&t, &p.e), X4_OK);  // running: its end tells
    EXPECT_TRUE(t.path_aborting);
    EXPECT_TRUE(pushed.empty());
  }
  t.path_aborting = false;
  Path p;
  ASSERT_EQ(p.Push(Seg(2000, 0, 0, 0, 2000, 4000, 40000, 0)), X4_OK);
  Recording r;
  record(p.e, r, 200);
  ASSERT_EQ(x4_path_hold(&p.e, false), X4_OK);
  record(p.e, r);
  ASSERT_EQ(p.Status().state, X4_PATH_HELD);
  ASSERT_EQ(x4_track_path_abort(&t, &p.e), X4_OK);
  EXPECT_EQ(p.Status().state, X4_PATH_IDLE);
  ASSERT_EQ(pushed.size(), 1u);
  EXPECT_EQ(pushed[0].type, uint32_t(X4STEP_EV_MOVE_ENDED));
  EXPECT_EQ(pushed[0].how, uint32_t(X4STEP_END_ABORTED));
  EXPECT_EQ(pushed[0].axes, 0x0fu) << "the path's axes: every axis of the mode";
  pushed.clear();
  EXPECT_NE(x4_track_path_abort(&t, &p.e), X4_OK);  // no path: nothing to tell
  EXPECT_FALSE(t.path_aborting);
  EXPECT_TRUE(pushed.empty());
  // Segments queued, the path not started: flushed, and nothing to tell.
  const x4_segment s = Seg(2000, 0, 0, 0, 2000, 4000, 40000, 0);
  x4_path_push(&p.e, &s);
  ASSERT_EQ(x4_track_path_abort(&t, &p.e), X4_OK);
  EXPECT_EQ(p.Status().queued, 0u);
  EXPECT_FALSE(t.path_aborting);
  EXPECT_TRUE(pushed.empty());
}

// Item 9: a path's events name the path's axes, every axis of the output
// mode (a path owns them all while it is active), not those of the segment
// that happened to run when it started or came to rest: a path that starts
// with an X segment, is held in a Y segment, resumed and aborted there.
TEST(PathAbort, EventsNameThePathsAxes) {
  for (const int mode : {int(X4_MODE_CLOCK_DIR), int(X4_MODE_SMC_PHASE)}) {
    x4_track t{};
    t.push = PushEvent;
    pushed.clear();
    Path p;
    ASSERT_EQ(x4_engine_configure(&p.e, &p.e.timing, mode), X4_OK);
    const uint32_t all = mode == X4_MODE_CLOCK_DIR ? 0x0f : 0x07;  // the axes of the mode
    ASSERT_EQ(p.Push(Seg(200, 0, 0, 0, 200, 4000, 40000, 0)), X4_OK);
    ASSERT_EQ(p.Push(Seg(0, 2000, 0, 0, 2000, 4000, 40000, 0)), X4_OK);
    x4_track_update(&t, &p.e, -1, X4STEP_KIND_PATH);
    Recording r;
    const auto run = [&](size_t events) {
      record(p.e, r, events, [&] { x4_track_fired(&t, &p.e, 0); });
      x4_track_fired(&t, &p.e, 0);
    };
    run(600);  // into the Y segment
    ASSERT_GT(p.e.steps[1], 0);
    ASSERT_EQ(x4_path_hold(&p.e, false), X4_OK);
    run(SIZE_MAX);
    ASSERT_EQ(p.Status().state, X4_PATH_HELD);
    ASSERT_EQ(x4_path_resume(&p.e, r.events.back().t_ns + 1000000), X4_OK);
    x4_track_update(&t, &p.e, -1, X4STEP_KIND_PATH);
    run(50);
    ASSERT_EQ(x4_path_hold(&p.e, false), X4_OK);
    run(SIZE_MAX);
    ASSERT_EQ(p.Status().state, X4_PATH_HELD);
    ASSERT_EQ(x4_track_path_abort(&t, &p.e), X4_OK);
    const std::vector<std::pair<uint32_t, uint32_t>> want = {{X4STEP_EV_MOVE_STARTED, X4STEP_KIND_PATH},
                                                             {X4STEP_EV_MOVE_ENDED, X4STEP_END_HELD},
                                                             {X4STEP_EV_MOVE_STARTED, X4STEP_KIND_PATH},
                                                             {X4STEP_EV_MOVE_ENDED, X4STEP_END_HELD},
                                                             {X4STEP_EV_MOVE_ENDED, X4STEP_END_ABORTED}};
    ASSERT_EQ(pushed.size(), want.size()) << "mode " << mode;
    for (size_t i = 0; i < want.size(); i++) {
      EXPECT_EQ(pushed[i].type, want[i].first) << "event " << i;
      EXPECT_EQ(pushed[i].how, want[i].second) << "event " << i;
      EXPECT_EQ(pushed[i].axes, all) << "event " << i << ", mode " << mode;
    }
  }
}

// ---- issue 28: an override never jumps, a resume keeps the plan, junctions in steps

namespace {

// Runs the queue `segs` (units = steps unless the segments say otherwise)
// for `events` events, sets the override to pct (as PATH_CTL does: set,
// replan, kick), runs it to its end and returns CheckPhysics' largest
// acceleration as a fraction of the limit (RunToEnd's checks apply).
double DropAt(const std::vector<x4_segment> &segs, size_t events, uint32_t pct, Recording &r, Path &p) {
  for (const auto &s : segs) EXPECT_EQ(p.Push(s), X4_OK);
  record(p.e, r, events);
  EXPECT_EQ(x4_path_set_override(&p.e, pct), X4_OK);
  x4_path_replan(&p.e);
  x4_path_kick(&p.e, x4_engine_due(&p.e));
  double worst = 0;
  RunToEnd(p, r, SIZE_MAX, &worst);
  return worst;
}

// The queue: a long fast segment, a 20-step one entered at 1000,
// two slow ones. Lengths in steps, acceleration 10 000 steps/s^2.
std::vector<x4_segment> LongShortSlow() {
  return {Seg(20000, 0, 0, 0, 20000, 10000, 10000, 0), Seg(20, 0, 0, 0, 20, 10000, 10000, 1000),
          Seg(4000, 0, 0, 0, 4000, 2000, 10000, 2000), Seg(4000, 0, 0, 0, 4000, 2000, 10000, 2000)};
}

}  // namespace

// Issue 28, item 2: the override drops to 10 % at leader step 20 000 (the
// long segment's end, the 20-step segment's entry already fixed at 1000):
// the 20-step segment cannot brake to the slow segments' new entry (200),
// and must not start lower than it is entered; it brakes at the limit and
// the slow segment goes on braking.
TEST(PathOverride, DropBeforeAShortSegmentBrakesAtTheLimit) {
  double worst_all = 0;
  for (size_t back = 0; back < 6; back++) {
    Path p;
    for (const auto &s : LongShortSlow()) ASSERT_EQ(p.Push(s), X4_OK);
    Recording r;
    while (r.rises[0].size() + back < 20000) record(p.e, r, 1);
    ASSERT_EQ(x4_path_set_override(&p.e, 10), X4_OK);
    x4_path_replan(&p.e);
    x4_path_kick(&p.e, x4_engine_due(&p.e));
    double worst = 0;
    RunToEnd(p, r, SIZE_MAX, &worst);
    worst_all = std::max(worst_all, worst);
    if (HasFailure()) {
      ADD_FAILURE() << "override dropped " << back << " steps before leader step 20000";
      break;
    }
  }
  std::printf("[ override ] drop to 10 %% before a 20-step segment: largest acceleration %.3f of the limit\n",
              worst_all);
  EXPECT_LE(worst_all, 1.0);
}

namespace {

// The event indices at which to drop the override on `segs`: a coarse
// sweep over the whole run and, where `junctions`, the last events before
// every junction (where the running segment's exit is already fixed).
std::vector<size_t> Moments(const std::vector<x4_segment> &segs, size_t coarse, bool junctions) {
  Path p(1024);
  for (const auto &s : segs) EXPECT_EQ(p.Push(s), X4_OK);
  Recording r;
  record(p.e, r);
  std::vector<size_t> out;
  const size_t n = r.events.size();
  for (size_t k = 1; k < n; k += std::max<size_t>(1, n / coarse)) out.push_back(k);
  if (!junctions) return out;
  size_t idx[X4_AXES] = {0, 0, 0, 0};
  for (size_t k = 0; k + 1 < segs.size(); k++) {
    const int lead = Leader(segs[k]);
    for (int i = 0; i < X4_AXES; i++) idx[i] += std::abs(segs[k].steps[i]);
    const uint64_t t = r.rises[lead][idx[lead] - 1];  // the segment's last leader step
    const auto it = std::lower_bound(r.events.begin(), r.events.end(), t,
                                     [](const x4_event &ev, uint64_t v) { return ev.t_ns < v; });
    const size_t e = size_t(it - r.events.begin());
    for (size_t d = 0; d < 12 && d < e; d++) out.push_back(e - d);
    out.push_back(e + 1);
  }
  return out;
}

}  // namespace

// Issue 28, item 2, on every queue shape: an override dropped at any moment
// (a coarse sweep, and the events around each junction) to 50, 10 or 1 %
// is approached at the acceleration limit, never by a velocity step. The
// chain: short segments whose cruise stays above their entry at 50 %, too
// short together to brake from the long segment's exit to the slow one's
// new top speed.
TEST(PathOverride, DropOnEveryQueueShapeKeepsTheAcceleration) {
  std::vector<x4_segment> chain = {Seg(6000, 0, 0, 0, 6000, 8000, 10000, 0)};
  for (int k = 0; k < 8; k++) chain.push_back(Seg(15, 5, 0, 0, 16, 20000, 10000, 8000));
  chain.push_back(Seg(3000, 0, 0, 0, 3000, 1500, 10000, 1500));
  chain.push_back(Seg(0, 3000, 0, 0, 3000, 1500, 10000, 300));
  std::vector<x4_segment> mixed;
  for (int k = 0; k < 30; k++)
    mixed.push_back(k % 3 == 2 ? Seg(40, 40, 0, 0, 57, 4000 + 500 * (k % 4), 20000, 1000 * (k % 5))
                               : Seg(-7 * (k % 2), 60 + k, 0, 0, 60 + k, 3000 + 300 * (k % 7), 20000, 4000));
  const struct {
    const char *name;
    std::vector<x4_segment> segs;
    size_t coarse;
    bool junctions;
  } shapes[] = {
      {"long, short, slow", LongShortSlow(), 20, true},
      {"long, 8 short, slow, corner", chain, 20, true},
      {"line of 10-step pieces", Line(80, 20000), 60, false},
      {"circle of 36 chords", Circle(2000, 36, 20000, 100000, 20000), 60, false},
      {"mixed lengths, speeds, corners", mixed, 30, true},
  };
  for (const auto &shape : shapes) {
    double worst = 0;
    size_t runs = 0;
    for (uint32_t pct : {50u, 10u, 1u}) {
      for (size_t k : Moments(shape.segs, shape.coarse, shape.junctions)) {
        Path p(1024);
        Recording r;
        worst = std::max(worst, DropAt(shape.segs, k, pct, r, p));
        runs++;
        if (HasFailure()) {
          ADD_FAILURE() << shape.name << ": override " << pct << " % at event " << k;
          return;
        }
      }
    }
    std::printf("[ override ] %-32s %3zu drops: largest acceleration %.3f of the limit\n", shape.name, runs,
                worst);
  }
}

// Issue 28, item 2: a drop the running segment has room to obey is obeyed
// before the next segment: the long segment brakes to the slow segment's
// new top speed (200) before it, not only to its own (1000).
TEST(PathOverride, DropWithRoomIsObeyedBeforeTheNextSegment) {
  Path p;
  ASSERT_EQ(p.Push(Seg(20000, 0, 0, 0, 20000, 10000, 10000, 0)), X4_OK);
  ASSERT_EQ(p.Push(Seg(4000, 0, 0, 0, 4000, 2000, 10000, 2000)), X4_OK);
  ASSERT_EQ(p.Push(Seg(0, 4000, 0, 0, 4000, 2000, 10000, 2000)), X4_OK);
  Recording r;
  while (r.rises[0].size() < 10000) record(p.e, r, 1);  // cruising at 10 000
  ASSERT_EQ(x4_path_set_override(&p.e, 10), X4_OK);
  x4_path_replan(&p.e);
  x4_path_kick(&p.e, x4_engine_due(&p.e));
  const auto st = RunToEnd(p, r);
  double fastest = 0;
  for (size_t k = 20001; k < st.size(); k++)
    fastest = std::max(fastest, (st[k].s - st[k - 1].s) / (st[k].t - st[k - 1].t));
  std::printf("[ override ] 10 %% with room to obey: fastest after the junction %.1f (top 200)\n", fastest);
  EXPECT_LT(fastest, 200 * 1.001 + 3);
}

// Issue 28, item 4: a segment that started alone (exit: rest) is held; a
// segment appended while it holds or stands is part of the plan when it
// resumes: the path passes the junction at the plan's 4000, not at rest.
TEST(PathHold, ResumeTakesTheSegmentAppendedMeanwhile) {
  for (bool held : {true, false}) {
    Path p;
    ASSERT_EQ(p.Push(Seg(4000, 0, 0, 0, 4000, 4000, 40000, 0)), X4_OK);
    Recording r;
    record(p.e, r, 2000);  // cruising at 4000
    ASSERT_EQ(x4_path_hold(&p.e, false), X4_OK);
    if (held) {
      record(p.e, r);
      ASSERT_EQ(p.Status().state, X4_PATH_HELD);
    } else {
      record(p.e, r, 50);
      ASSERT_EQ(p.Status().state, X4_PATH_HOLDING);
    }
    const uint64_t now = held ? r.events.back().t_ns + 1000000 : x4_engine_due(&p.e);
    ASSERT_EQ(p.Push(Seg(4000, 0, 0, 0, 4000, 4000, 40000, 4000), now), X4_OK);
    ASSERT_EQ(x4_path_resume(&p.e, now), X4_OK);
    const auto st = RunToEnd(p, r);
    ASSERT_GT(st.size(), 4001u);
    ASSERT_EQ(st[4000].seg, 1u);
    const double v = (st[4000].s - st[3999].s) / (st[4000].t - st[3999].t);
    std::printf("[ resume   ] appended while %s: %.0f steps/s at the junction\n", held ? "held" : "holding",
                v);
    EXPECT_GT(v, 3950) << (held ? "appended while held" : "appended while holding");
    EXPECT_EQ(p.Status().starved, 0u) << "it stood for the hold, not for want of segments";
  }
}

// Issue 28, item 5: units coarser than a step (mm at 80 steps/mm, as
// through the raw API): a path accelerating across junctions must not lose
// up to 79 steps/s at each (to whole mm/s); straight and diagonal pieces,
// so that the leader's steps per unit change at the junctions too.
TEST(PathRun, CoarseUnitsKeepTheSpeedAtJunctions) {
  Path p;
  for (int k = 0; k < 40; k++)
    ASSERT_EQ(p.Push(k % 2 ? Seg(160, 0, 0, 0, 2, 100, 200, 100) : Seg(240, 240, 0, 0, 4, 100, 200, 100)),
              X4_OK);
  Recording r;
  double worst = 0;
  RunToEnd(p, r, SIZE_MAX, &worst);
  std::printf("[ units    ] 80 steps/mm, 40 junctions: largest acceleration %.3f of the limit\n", worst);
  EXPECT_LE(worst, 1.0);
}
