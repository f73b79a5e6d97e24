// SPDX-License-Identifier: GPL-2.0
// Unit tests of probing segments (kmod/engine/x4_path.c, G38.2..G38.5):
// a probe switch at a known position on the machine, sampled as the
// module's glue samples (before every step tick the engine watches); the
// latch must be every axis' position at the step at which the input
// changed, at any feed, toward and away, and the path must brake along it
// and be flushed. Also: a start with the input tripped already, a segment
// that ends without a trip, the refusal without an input, hold and resume
// while probing, and what the event tracker tells.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "engine_ref.h"
extern "C" {
#include "x4_req.h"
#include "x4_track.h"
}

using namespace x4test;

namespace {

constexpr uint64_t kStart = 1000;
constexpr uint8_t kInput = 3;  // the probe on input 3 (X4GetIn bit 2)

x4_segment Seg(int32_t x, int32_t y, uint32_t v_max, uint32_t accel, uint8_t probe = X4_PROBE_NONE,
               uint64_t tag = 0, uint32_t v_entry = 0) {
  x4_segment s{};
  s.steps[0] = x;
  s.steps[1] = y;
  // One unit a step of the leader: speeds in leader steps/s.
  s.length = uint32_t(std::max(std::abs(x), std::abs(y)));
  s.v_max = v_max;
  s.accel = accel;
  s.v_entry = v_entry;
  s.tag = tag;
  s.probe = probe;
  return s;
}

using Pos = std::array<int32_t, X4_AXES>;

// An engine with a path queue and a probe switch on an axis: active at
// the axis' position `at` and beyond (above) or at it and below.
struct Probing {
  x4_engine e;
  std::vector<x4_path_slot> q = std::vector<x4_path_slot>(256);
  int axis = 0;
  int32_t at = 0;
  bool above = true;
  bool nc = false;
  bool was_active = false;
  bool changed = false;
  Pos at_change{};  // every axis' position when the switch changed first
  size_t rises_at_change = 0;
  Recording r;

  explicit Probing(bool nc_probe = false) : nc(nc_probe) {
    x4_engine_init(&e);
    EXPECT_EQ(x4_path_set_queue(&e, q.data(), 256), X4_OK);
    EXPECT_EQ(x4_path_set_probe(&e, kInput, nc), X4_OK);
  }
  Pos Now() const {
    Pos p;
    for (int i = 0; i < X4_AXES; i++) p[i] = int32_t(e.pos_base[i] + uint32_t(e.steps[i]));
    return p;
  }
  bool Active() const {
    const int32_t p = Now()[axis];
    return above ? p >= at : p <= at;
  }
  uint8_t Levels() const { return Active() != nc ? uint8_t(1u << (kInput - 1)) : 0; }
  // The glue: the inputs sampled before a step tick the engine watches.
  void Sense() {
    const bool a = Active();
    if (a != was_active && !changed) {
      changed = true;
      at_change = Now();
      rises_at_change = Rises();
    }
    was_active = a;
    if (x4_engine_rise_watched(&e)) x4_switch_sense(&e, Levels());
  }
  size_t Rises() const {
    size_t n = 0;
    for (const auto &v : r.rises) n += v.size();
    return n;
  }
  int Push(const x4_segment &s) {
    const int ret = x4_path_check(&e, &s);
    if (ret) return ret;
    x4_path_push(&e, &s);
    x4_path_kick(&e, kStart);
    return X4_OK;
  }
  void Start() { was_active = Active(); }
  void Run(size_t max_events = SIZE_MAX) {
    record(e, r, max_events, [this] { Sense(); });
  }
  Pos Latch() const {
    Pos p;
    for (int i = 0; i < X4_AXES; i++) p[i] = e.path.latch.position[i];
    return p;
  }
  x4_path_status Status() const {
    x4_path_status st;
    x4_path_get_status(&e, &st);
    return st;
  }
  // Leader steps after the trip: within what a brake from v (steps/s)
  // with a (steps/s^2) needs, and the last one from rest's pace.
  void ExpectBrakedFrom(double v, double a) const {
    const size_t after = r.rises[axis].size() - std::min(r.rises[axis].size(), rises_at_change);
    EXPECT_LE(double(after), v * v / (2 * a) + 2) << "steps after the trip at " << v << " steps/s";
    const auto &t = r.rises[axis];
    if (after >= 2) {
      const double last = (t.back() - t[t.size() - 2]) * 1e-9;
      EXPECT_GE(last, 0.95 * std::sqrt(2 / a)) << "it stops at speed " << 1 / last;
    }
  }
};

// The speed (steps/s) of a segment of `steps` steps at `at` steps from its
// start: the trapezoid from rest to rest.
double SpeedAt(double steps, double v_max, double a, double at) {
  return std::min({v_max, std::sqrt(2 * a * at), std::sqrt(2 * a * std::max(0.0, steps - at))});
}

class ProbeFeed : public ::testing::TestWithParam<uint32_t> {};

// G38.2: toward the switch at 5000 on X, Y the minor axis; a segment queued
// after it never runs. At every feed the latch is every axis' position at
// the step the switch became active, and the path brakes from the trip.
TEST_P(ProbeFeed, TowardLatchesTheStepAtWhichTheInputChanged) {
  const uint32_t feed = GetParam();
  const uint32_t accel = 200000;
  Probing p;
  p.at = 5000;
  ASSERT_EQ(p.Push(Seg(20000, 7001, feed, accel, X4_PROBE_TOWARD, 77)), X4_OK);
  ASSERT_EQ(p.Push(Seg(0, 500, feed, accel, X4_PROBE_NONE, 78)), X4_OK);
  const uint32_t flushes = p.e.path.flushes;
  p.Start();
  p.Run();
  ASSERT_TRUE(p.changed);
  EXPECT_EQ(p.at_change[0], 5000);
  EXPECT_TRUE(p.e.path.latch.tripped);
  EXPECT_EQ(p.Latch(), p.at_change) << "feed " << feed;
  EXPECT_EQ(p.e.path.latch.tag, 77u);
  EXPECT_EQ(p.e.path.latch.runs, 1u);
  EXPECT_EQ(p.e.path.latch.trips, 1u);
  EXPECT_EQ(p.Status().state, X4_PATH_IDLE);
  EXPECT_EQ(p.Status().queued, 0u) << "the queue is flushed";
  EXPECT_EQ(p.e.path.flushes, flushes + 1);
  EXPECT_LT(p.Now()[0], 20000) << "it stopped on the way";
  EXPECT_EQ(p.Now()[1] - p.Latch()[1], std::lround(double(p.Now()[0]) * 7001 / 20000) - p.Latch()[1])
      << "Y on the line (the next segment's steps never came)";
  p.ExpectBrakedFrom(SpeedAt(20000, feed, accel, 5000), accel);
  if (feed >= 20000) {
    EXPECT_GT(p.Now()[0], 5000) << "at speed it brakes past the switch, not at once";
  }
}

INSTANTIATE_TEST_SUITE_P(Feeds, ProbeFeed, ::testing::Values(50u, 700u, 5000u, 20000u, 60000u));

// G38.4: away from a switch that is active at 5000 and above, from 8000
// down: the latch is 4999, where it cleared; also with a normally closed
// probe (the levels inverted).
TEST(Probe, AwayLatchesWhereTheInputCleared) {
  for (const bool nc : {false, true}) {
    Probing p(nc);
    p.at = 5000;
    const int32_t from[X4_AXES] = {8000, -300, 0, 0};
    ASSERT_EQ(x4_engine_set_position(&p.e, 0x0f, from), X4_OK);
    ASSERT_EQ(p.Push(Seg(-6000, -1500, 3000, 50000, X4_PROBE_AWAY, 5)), X4_OK);
    p.Start();
    ASSERT_TRUE(p.was_active);
    p.Run();
    ASSERT_TRUE(p.changed);
    EXPECT_EQ(p.at_change[0], 4999);
    EXPECT_TRUE(p.e.path.latch.tripped) << "nc " << nc;
    EXPECT_EQ(p.Latch(), p.at_change) << "nc " << nc;
    EXPECT_GT(p.Now()[0], 2000) << "it stopped before the segment's end";
    p.ExpectBrakedFrom(3000, 50000);
  }
}

// A normally closed probe toward the switch: active while LOW. The probe
// has its own polarity: the switches' NO/NC of its input does not apply.
TEST(Probe, ProbePolarityIsItsOwn) {
  for (const bool nc : {false, true}) {
    for (const uint8_t sw_nc : {uint8_t(0), uint8_t(1u << (kInput - 1))}) {
      Probing p(nc);
      x4_switches sw{};
      sw.nc = sw_nc;
      ASSERT_EQ(x4_switch_set(&p.e, &sw), X4_OK);
      p.at = 1234;
      ASSERT_EQ(p.Push(Seg(3000, 0, 4000, 80000, X4_PROBE_TOWARD)), X4_OK);
      p.Start();
      p.Run();
      EXPECT_TRUE(p.e.path.latch.tripped) << "nc " << nc << ", switches' nc " << int(sw_nc);
      EXPECT_EQ(p.Latch()[0], 1234) << "nc " << nc << ", switches' nc " << int(sw_nc);
      EXPECT_LT(p.Now()[0], 3000);
    }
  }
}

// The input is in the awaited state when the segment starts from rest:
// it trips at its first tick, latches where it stands, and no axis steps;
// the queue behind it is flushed.
TEST(Probe, TrippedAtTheStartMovesNothing) {
  for (const uint8_t mode : {uint8_t(X4_PROBE_TOWARD), uint8_t(X4_PROBE_AWAY)}) {
    Probing p;
    p.at = mode == X4_PROBE_TOWARD ? 0 : 1;  // active at 0 and up: toward trips; inactive: away trips
    const int32_t from[X4_AXES] = {0, 17, -5, 3};
    ASSERT_EQ(x4_engine_set_position(&p.e, 0x0f, from), X4_OK);
    ASSERT_EQ(p.Push(Seg(2000, 100, 2000, 20000, mode, 9)), X4_OK);
    ASSERT_EQ(p.Push(Seg(2000, 0, 2000, 20000)), X4_OK);
    p.Start();
    p.Run();
    EXPECT_EQ(p.Rises(), 0u) << "mode " << int(mode) << ": no step";
    EXPECT_TRUE(p.e.path.latch.tripped);
    EXPECT_EQ(p.Latch(), (Pos{0, 17, -5, 3}));
    EXPECT_EQ(p.Now(), (Pos{0, 17, -5, 3}));
    EXPECT_EQ(p.Status().state, X4_PATH_IDLE);
    EXPECT_EQ(p.Status().queued, 0u);
  }
}

// A probing segment after one that ends at rest, its input tripped by
// then: it starts from rest and makes no step (the one before ran whole).
TEST(Probe, TrippedAtAJunctionFromRestMovesNothing) {
  Probing p;
  p.at = 500;  // X passes it in the first segment, which does not probe
  ASSERT_EQ(p.Push(Seg(1000, 0, 3000, 30000)), X4_OK);
  ASSERT_EQ(p.Push(Seg(0, 1000, 3000, 30000, X4_PROBE_TOWARD, 2)), X4_OK);
  p.Start();
  p.Run();
  EXPECT_EQ(p.Now(), (Pos{1000, 0, 0, 0}));
  EXPECT_TRUE(p.r.rises[1].empty()) << "Y never stepped";
  EXPECT_TRUE(p.e.path.latch.tripped);
  EXPECT_EQ(p.Latch(), (Pos{1000, 0, 0, 0}));
}

// No trip: the probing segment ends, the path goes on, and the latch says
// it ran (its tag) without a trip.
TEST(Probe, NoTripLetsThePathGoOn) {
  Probing p;
  p.at = 100000;
  ASSERT_EQ(p.Push(Seg(3000, 1000, 5000, 50000, X4_PROBE_TOWARD, 31)), X4_OK);
  ASSERT_EQ(p.Push(Seg(0, 2000, 5000, 50000, X4_PROBE_NONE, 32)), X4_OK);
  p.Start();
  p.Run();
  EXPECT_EQ(p.Now(), (Pos{3000, 3000, 0, 0})) << "both segments ran whole";
  EXPECT_FALSE(p.e.path.latch.tripped);
  EXPECT_EQ(p.Latch(), (Pos{0, 0, 0, 0}));
  EXPECT_EQ(p.e.path.latch.tag, 31u);
  EXPECT_EQ(p.e.path.latch.runs, 1u);
  EXPECT_EQ(p.e.path.latch.trips, 0u);
  EXPECT_EQ(p.Status().done, 2u);
  // The switch is ahead of the second segment's axis, which does not probe.
  Probing q;
  q.axis = 1;
  q.at = 1500;
  ASSERT_EQ(q.Push(Seg(3000, 0, 5000, 50000, X4_PROBE_TOWARD, 1)), X4_OK);
  ASSERT_EQ(q.Push(Seg(0, 3000, 5000, 50000)), X4_OK);
  q.Start();
  q.Run();
  EXPECT_EQ(q.Now(), (Pos{3000, 3000, 0, 0})) << "a segment that does not probe ignores the input";
  EXPECT_FALSE(q.e.path.latch.tripped);
}

// A path whose last segment probed without a trip: the moves after it on
// the same channel do not watch the input.
TEST(Probe, MovesAfterAProbingPathIgnoreTheInput) {
  Probing p;
  p.at = 5000;
  ASSERT_EQ(p.Push(Seg(1000, 0, 5000, 50000, X4_PROBE_TOWARD)), X4_OK);
  p.Start();
  p.Run();
  ASSERT_FALSE(p.e.path.latch.tripped);
  ASSERT_EQ(p.Now()[0], 1000);
  const x4_move m = Move(8000, 0, 0, 0, 5000, 20);
  ASSERT_EQ(x4_engine_load(&p.e, &m), X4_OK);
  ASSERT_EQ(x4_engine_start(&p.e, p.r.events.back().t_ns + 1000000), X4_OK);
  p.Run();
  EXPECT_EQ(p.Now()[0], 9000) << "the move passed the switch at 5000";
  EXPECT_EQ(p.e.path.latch.trips, 0u);
}

// A new probing segment clears the latch of the one before.
TEST(Probe, NextProbingSegmentClearsTheLatch) {
  Probing p;
  p.at = 1000;
  ASSERT_EQ(p.Push(Seg(2000, 0, 2000, 40000, X4_PROBE_TOWARD, 1)), X4_OK);
  p.Start();
  p.Run();
  ASSERT_TRUE(p.e.path.latch.tripped);
  ASSERT_EQ(p.Latch()[0], 1000);
  p.at = 100000;  // the switch gone: the next one does not trip
  ASSERT_EQ(p.Push(Seg(500, 0, 2000, 40000, X4_PROBE_TOWARD, 2)), X4_OK);
  p.Start();
  p.Run();
  EXPECT_FALSE(p.e.path.latch.tripped);
  EXPECT_EQ(p.Latch(), (Pos{0, 0, 0, 0}));
  EXPECT_EQ(p.e.path.latch.tag, 2u);
  EXPECT_EQ(p.e.path.latch.runs, 2u);
  EXPECT_EQ(p.e.path.latch.trips, 1u);
}

// Probing without a probe input is refused, and so is a mode that is
// none of the three; the input changes only while no path is active.
TEST(Probe, RefusedWithoutAnInput) {
  x4_engine e;
  x4_engine_init(&e);
  std::vector<x4_path_slot> q(256);
  ASSERT_EQ(x4_path_set_queue(&e, q.data(), 256), X4_OK);
  x4_segment s = Seg(1000, 0, 1000, 10000, X4_PROBE_TOWARD);
  EXPECT_EQ(x4_path_check(&e, &s), X4_ERR_PARAM_FAIL);
  s.probe = X4_PROBE_AWAY;
  EXPECT_EQ(x4_path_check(&e, &s), X4_ERR_PARAM_FAIL);
  s.probe = 3;
  EXPECT_EQ(x4_segment_check(&s, 0), X4_ERR_PARAM_FAIL);
  EXPECT_EQ(x4_path_set_probe(&e, 6, false), X4_ERR_PARAM_FAIL);
  EXPECT_EQ(e.path.probe_input, 0);
  ASSERT_EQ(x4_path_set_probe(&e, 5, false), X4_OK);
  s.probe = X4_PROBE_TOWARD;
  EXPECT_EQ(x4_path_check(&e, &s), X4_OK);
  s.probe = X4_PROBE_NONE;
  x4_path_push(&e, &s);  // queued: the path is active
  EXPECT_EQ(x4_path_set_probe(&e, 5, false), X4_OK) << "as it is";
  EXPECT_EQ(x4_path_set_probe(&e, 4, false), X4_ERR_IS_ACTIVE);
  EXPECT_EQ(x4_path_set_probe(&e, 5, true), X4_ERR_IS_ACTIVE);
  EXPECT_EQ(x4_path_set_probe(&e, 0, false), X4_ERR_IS_ACTIVE);
  EXPECT_EQ(e.path.probe_input, 5);
  EXPECT_FALSE(e.path.probe_nc);
}

// A hold while probing, and the resume: the segment goes on watching, and
// the latch is as exact as without the hold.
TEST(Probe, HoldAndResumeKeepWatching) {
  Probing p;
  p.at = 3000;
  ASSERT_EQ(p.Push(Seg(6000, 2000, 4000, 40000, X4_PROBE_TOWARD, 4)), X4_OK);
  p.Start();
  p.Run(1000);
  ASSERT_LT(p.Now()[0], 2000);
  ASSERT_EQ(x4_path_hold(&p.e, false), X4_OK);
  p.Run();
  ASSERT_EQ(p.Status().state, X4_PATH_HELD);
  ASSERT_FALSE(p.e.path.latch.tripped);
  ASSERT_EQ(x4_path_resume(&p.e, p.r.events.back().t_ns + 1000000), X4_OK);
  p.Run();
  EXPECT_TRUE(p.e.path.latch.tripped);
  EXPECT_EQ(p.Latch()[0], 3000);
  EXPECT_EQ(p.Latch(), p.at_change);
  EXPECT_EQ(p.e.path.latch.runs, 1u) << "a resume is no new start";
  EXPECT_EQ(p.Status().state, X4_PATH_IDLE);
  EXPECT_LT(p.Now()[0], 6000);
}

struct Told {
  uint32_t type, axes, how, value;
};
std::vector<Told> told;
void Tell(x4_track *, u32 type, u32 axes, u32 how, u32 value, u32) {
  told.push_back({type, axes, how, value});
}

// The event stream: the probe's switch event (the path's axes, the input),
// then the path's end, ABORTED; also when it trips at the start.
TEST(Probe, TrackerTellsTheTripAndTheAbortedEnd) {
  for (const int32_t at : {2000, 0}) {
    told.clear();
    x4_track t{};
    t.push = Tell;
    Probing p;
    p.at = at;
    ASSERT_EQ(p.Push(Seg(4000, 0, 4000, 40000, X4_PROBE_TOWARD)), X4_OK);
    x4_track_update(&t, &p.e, -1, X4STEP_KIND_PATH);
    p.Start();
    size_t late = 0;  // ticks after the trip, braking, without its event
    record(p.e, p.r, SIZE_MAX, [&] {
      p.Sense();
      x4_track_fired(&t, &p.e, 0);
      late += p.e.path.latch.tripped && p.e.busy && told.size() < 2;
    });
    EXPECT_EQ(late, 0u) << "the switch event comes at the trip, not at the end";
    x4_track_fired(&t, &p.e, 0);
    ASSERT_EQ(told.size(), 3u) << "at " << at;
    EXPECT_EQ(told[0].type, uint32_t(X4STEP_EV_MOVE_STARTED));
    EXPECT_EQ(told[1].type, uint32_t(X4STEP_EV_SWITCH));
    EXPECT_EQ(told[1].how, uint32_t(X4STEP_SW_PROBE));
    EXPECT_EQ(told[1].value, uint32_t(kInput));
    EXPECT_EQ(told[1].axes, 0x0fu);
    EXPECT_EQ(told[2].type, uint32_t(X4STEP_EV_MOVE_ENDED));
    EXPECT_EQ(told[2].how, uint32_t(X4STEP_END_ABORTED));
    EXPECT_FALSE(t.path_aborting);
  }
}

// The probe costs a step tick nothing but a test while no probing segment
// runs: a path without one is not watched at all.
TEST(Probe, OnlyAProbingSegmentIsWatched) {
  Probing p;
  p.at = 100000;
  ASSERT_EQ(p.Push(Seg(500, 0, 2000, 20000)), X4_OK);
  size_t watched = 0;
  record(p.e, p.r, SIZE_MAX, [&] { watched += x4_engine_rise_watched(&p.e); });
  EXPECT_EQ(watched, 0u);
  ASSERT_EQ(p.Push(Seg(500, 0, 2000, 20000, X4_PROBE_TOWARD)), X4_OK);
  record(p.e, p.r, SIZE_MAX, [&] { watched += x4_engine_rise_watched(&p.e); });
  EXPECT_EQ(watched, 500u) << "every step tick of the probing segment";
}

}  // namespace
