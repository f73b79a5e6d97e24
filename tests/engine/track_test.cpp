// SPDX-License-Identifier: GPL-2.0
// Unit tests of kmod/engine/x4_track.c: why moves end, as the event stream
// tells it. The engine runs moves on a small machine (positions counted
// from the clock edges, switches on the inputs); after every command and
// every fired event the tracker is asked, as the module's glue and the
// simulated port ask it, and the events it pushes are compared with the
// ones the move must give. Paths (held, aborted) are in path_test.cpp.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "engine_ref.h"  // x4test::Move()

extern "C" {
#include "x4_req.h"
#include "x4_track.h"
}

namespace {

using x4test::Move;

constexpr uint64_t kStart = 1000;

struct Ev {
  uint32_t type, axes, how, value, flags;
  bool operator==(const Ev &o) const {
    return type == o.type && axes == o.axes && how == o.how && value == o.value && flags == o.flags;
  }
};

std::ostream &operator<<(std::ostream &os, const Ev &e) {
  return os << "{type " << e.type << " axes " << e.axes << " how " << e.how << " value " << e.value
            << " flags " << e.flags << "}";
}

// A switch of the machine: input `input` (1..5) is active while axis
// `axis`'s position is within [lo, hi].
struct Switch {
  int axis, input;
  int64_t lo, hi;
};

struct Rig {
  x4_engine e;
  struct Tracker {
    x4_track t;  // first: the callback gets its address
    std::vector<Ev> *out;
  } tr{};
  std::vector<Ev> events;
  int64_t machine[X4_AXES] = {};
  std::vector<Switch> switches;
  uint64_t now = kStart;

  Rig() {
    x4_engine_init(&e);
    tr.out = &events;
    tr.t.push = [](x4_track *t, u32 type, u32 axes, u32 how, u32 value, u32 flags) {
      reinterpret_cast<Tracker *>(t)->out->push_back({type, axes, how, value, flags});
    };
    Sense();
  }

  void Sense() {
    uint8_t bits = 0;
    for (const Switch &s : switches)
      if (machine[s.axis] >= s.lo && machine[s.axis] <= s.hi) bits |= uint8_t(1u << (s.input - 1));
    x4_switch_sense(&e, bits);
  }

  int SetSwitches(const x4_switches &sw) {
    const int ret = x4_switch_set(&e, &sw);
    Sense();
    return ret;
  }

  // After a command: what the glue does (x4_track_update), kind of the
  // moves that start.
  void Commanded(uint32_t kind) { x4_track_update(&tr.t, &e, -1, kind); }

  // Fire the engine until idle (at most max_events), each event as the
  // glue fires it: inputs sensed, fired at its time, the tracker told.
  void Run(size_t max_events = SIZE_MAX) {
    for (size_t n = 0; n < max_events && x4_engine_busy(&e); n++) {
      const int c = int(e.cur - e.ch);
      const uint8_t before = e.data;
      Sense();
      now = x4_engine_due(&e);
      x4_engine_fire(&e, now);
      x4_engine_written(&e, now);
      const uint8_t rose = e.data & ~before & X4_CLK_MASK;
      for (int i = 0; i < X4_AXES; i++)
        if (rose & X4_CLK_BIT(i)) machine[i] += (e.data & X4_DIR_BIT(i)) ? 1 : -1;
      x4_track_fired(&tr.t, &e, c);
    }
  }

  std::vector<Ev> Take() {
    std::vector<Ev> out;
    out.swap(events);
    return out;
  }
};

Ev Started(uint32_t axes, uint32_t kind) { return {X4STEP_EV_MOVE_STARTED, axes, kind, 0, 0}; }
Ev Ended(uint32_t axes, uint32_t how) { return {X4STEP_EV_MOVE_ENDED, axes, how, 0, 0}; }

TEST(Track, LoadedMoveStartsAndCompletes) {
  Rig rig;
  const x4_move m = Move(100, 0, -50, 0, 2000, 0);
  ASSERT_EQ(x4_engine_load(&rig.e, &m), X4_OK);
  rig.Commanded(0);
  EXPECT_TRUE(rig.Take().empty()) << "loaded, not started";
  ASSERT_EQ(x4_engine_start(&rig.e, rig.now), X4_OK);
  rig.Commanded(X4STEP_KIND_LOADED);
  EXPECT_EQ(rig.Take(), std::vector<Ev>{Started(0x5, X4STEP_KIND_LOADED)});
  rig.Run(3);
  EXPECT_TRUE(rig.Take().empty()) << "nothing while it runs";
  rig.Run();
  EXPECT_EQ(rig.machine[0], 100);
  EXPECT_EQ(rig.machine[2], -50);
  EXPECT_EQ(rig.Take(), std::vector<Ev>{Ended(0x5, X4STEP_END_COMPLETED)});
  rig.Commanded(0);
  EXPECT_TRUE(rig.Take().empty()) << "an end is told once";
}

TEST(Track, ChannelsOfAxes) {
  Rig rig;
  x4_profile p{};
  p.vm = 1000;
  for (int a = 1; a <= X4_AXES; a++) ASSERT_EQ(x4_engine_set_profile(&rig.e, a, &p), X4_OK);
  EXPECT_EQ(x4_track_chans(&rig.e, 0x0f), 0) << "nothing runs";
  const int32_t target[X4_AXES] = {100, 0, 100, 0};
  ASSERT_EQ(x4_engine_goto(&rig.e, 0x5, target, false, rig.now), X4_OK);
  rig.Commanded(X4STEP_KIND_GOTO);
  const std::vector<Ev> started = rig.Take();
  ASSERT_EQ(started.size(), 2u) << "a goto is one move per axis";
  EXPECT_EQ(started[0], Started(0x1, X4STEP_KIND_GOTO));
  EXPECT_EQ(started[1], Started(0x4, X4STEP_KIND_GOTO));
  const uint8_t c1 = x4_track_chans(&rig.e, 0x1), c3 = x4_track_chans(&rig.e, 0x4);
  EXPECT_NE(c1, 0);
  EXPECT_NE(c3, 0);
  EXPECT_EQ(c1 & c3, 0) << "independent axes, channels of their own";
  EXPECT_EQ(x4_track_chans(&rig.e, 0x5), c1 | c3);
  EXPECT_EQ(x4_track_chans(&rig.e, 0x2), 0) << "axis 2 does not move";
  EXPECT_EQ(x4_track_chans(&rig.e, 0xa), 0);
  rig.Run();
  EXPECT_EQ(rig.Take(),
            (std::vector<Ev>{Ended(0x1, X4STEP_END_COMPLETED), Ended(0x4, X4STEP_END_COMPLETED)}));
  EXPECT_EQ(x4_track_chans(&rig.e, 0x0f), 0);
}

TEST(Track, BrakeIsToldAndEndsBraked) {
  Rig rig;
  ASSERT_EQ(x4_engine_endless(&rig.e, 2, false, 2000, 20, rig.now), X4_OK);
  rig.Commanded(X4STEP_KIND_ENDLESS);
  EXPECT_EQ(rig.Take(), std::vector<Ev>{Started(0x2, X4STEP_KIND_ENDLESS)});
  rig.Run(200);
  x4_track_brake(&rig.tr.t, &rig.e, 0, X4STEP_SRC_IOCTL, 0);
  EXPECT_TRUE(rig.Take().empty()) << "no channel: no brake to tell";
  const uint8_t chans = x4_track_chans(&rig.e, 0x2);
  x4_track_brake(&rig.tr.t, &rig.e, chans, X4STEP_SRC_KEY, 0x39);
  const Ev brake{X4STEP_EV_BRAKE, 0x2, X4STEP_SRC_KEY, 0x39, 0};
  EXPECT_EQ(rig.Take(), std::vector<Ev>{brake});
  ASSERT_EQ(x4_engine_brake(&rig.e), X4_OK);
  rig.Commanded(0);
  rig.Run();
  EXPECT_EQ(rig.Take(), std::vector<Ev>{Ended(0x2, X4STEP_END_BRAKED)});
  // The next move's end is its own, not the brake's.
  const x4_move m = Move(0, 20, 0, 0, 1000, 0);
  ASSERT_EQ(x4_engine_load(&rig.e, &m), X4_OK);
  ASSERT_EQ(x4_engine_start(&rig.e, rig.now), X4_OK);
  rig.Commanded(X4STEP_KIND_LOADED);
  rig.Run();
  EXPECT_EQ(rig.Take(),
            (std::vector<Ev>{Started(0x2, X4STEP_KIND_LOADED), Ended(0x2, X4STEP_END_COMPLETED)}));
}

TEST(Track, StopEndsStoppedEvenAfterABrake) {
  for (bool braked_first : {false, true}) {
    Rig rig;
    ASSERT_EQ(x4_engine_endless(&rig.e, 4, true, 2000, 50, rig.now), X4_OK);
    rig.Commanded(X4STEP_KIND_ENDLESS);
    rig.Run(100);
    rig.Take();
    const uint8_t chans = x4_track_chans(&rig.e, 0x8);
    ASSERT_NE(chans, 0);
    if (braked_first) {
      x4_track_brake(&rig.tr.t, &rig.e, chans, X4STEP_SRC_IOCTL, X4STEP_HALT_BRAKE);
      ASSERT_EQ(x4_engine_brake(&rig.e), X4_OK);
      rig.Run(5);
      ASSERT_TRUE(x4_engine_busy(&rig.e)) << "still braking";
    }
    x4_track_stop(&rig.tr.t, chans);
    ASSERT_EQ(x4_engine_stop(&rig.e), X4_OK);
    rig.Commanded(0);
    rig.Run();
    std::vector<Ev> want;
    if (braked_first) want.push_back({X4STEP_EV_BRAKE, 0x8, X4STEP_SRC_IOCTL, X4STEP_HALT_BRAKE, 0});
    want.push_back(Ended(0x8, X4STEP_END_STOPPED));
    EXPECT_EQ(rig.Take(), want) << braked_first;
  }
}

// Axis 1 runs into E+ on input 3 at position 30 (or E- at -30). Shared:
// axis 3 moves too and watches the same input as its E+, so a hit cannot
// tell whose switch it was: both axes get it, flagged ambiguous.
TEST(Track, LimitSwitchEndsTheMove) {
  struct Case {
    bool positive, shared;
  };
  for (const Case c : {Case{true, false}, Case{false, false}, Case{true, true}}) {
    Rig rig;
    x4_switches sw{};
    const int s = c.positive ? 1 : -1;
    if (c.positive) {
      sw.plus[0] = 3;
      rig.switches = {{0, 3, 30, 1000}};
    } else {
      sw.minus[0] = 3;
      rig.switches = {{0, 3, -1000, -30}};
    }
    if (c.shared) sw.plus[2] = 3;
    ASSERT_EQ(rig.SetSwitches(sw), X4_OK);
    const uint32_t axes = c.shared ? 0x5 : 0x1;
    const x4_move m = Move(s * 100, 0, c.shared ? 100 : 0, 0, 1000, 0);
    ASSERT_EQ(x4_engine_load(&rig.e, &m), X4_OK);
    ASSERT_EQ(x4_engine_start(&rig.e, rig.now), X4_OK);
    rig.Commanded(X4STEP_KIND_LOADED);
    rig.Run();
    EXPECT_LT(std::abs(rig.machine[0]), 100) << "stopped on the switch";
    const uint32_t how = c.positive ? X4STEP_SW_LIMIT_POS : X4STEP_SW_LIMIT_NEG;
    const uint32_t flags = c.shared ? X4STEP_EVF_AMBIGUOUS : 0;
    std::vector<Ev> want{Started(axes, X4STEP_KIND_LOADED), {X4STEP_EV_SWITCH, 0x1, how, 3, flags}};
    if (c.shared) want.push_back({X4STEP_EV_SWITCH, 0x4, X4STEP_SW_LIMIT_POS, 3, flags});
    want.push_back(Ended(axes, X4STEP_END_LIMIT));
    EXPECT_EQ(rig.Take(), want) << c.positive << c.shared;
    // The error bit stays: no second switch event for it.
    rig.Commanded(0);
    EXPECT_TRUE(rig.Take().empty());
  }
}

// Axis 2's REF on input 1, active from position 40 on; homing from 0.
struct Homing : Rig {
  Homing() {
    x4_switches sw{};
    sw.ref[1] = 1;
    switches = {{1, 1, 40, 100000}};
    EXPECT_EQ(SetSwitches(sw), X4_OK);
  }
};

TEST(Track, ReferenceRunHomed) {
  Homing rig;
  ASSERT_EQ(x4_switch_home(&rig.e, 2, X4_HOME_AUTO, 2000, -500, 10000, rig.now), X4_OK);
  rig.Commanded(X4STEP_KIND_HOME);
  rig.Run();
  const Ev ref{X4STEP_EV_SWITCH, 0x2, X4STEP_SW_REF, 1, 0};
  EXPECT_EQ(rig.Take(),
            (std::vector<Ev>{Started(0x2, X4STEP_KIND_HOME), ref, ref, Ended(0x2, X4STEP_END_HOMED)}))
      << "REF seen in phase 1, REF left in phase 2";
  EXPECT_EQ(rig.machine[1], 39);
}

TEST(Track, ReferenceRunPhase1Only) {
  Homing rig;
  ASSERT_EQ(x4_switch_home(&rig.e, 2, X4_HOME_PHASE1, 2000, 0, 10000, rig.now), X4_OK);
  rig.Commanded(X4STEP_KIND_HOME);
  rig.Run();
  const Ev ref{X4STEP_EV_SWITCH, 0x2, X4STEP_SW_REF, 1, 0};
  EXPECT_EQ(rig.Take(),
            (std::vector<Ev>{Started(0x2, X4STEP_KIND_HOME), ref, Ended(0x2, X4STEP_END_REF_FOUND)}));
  EXPECT_EQ(rig.machine[1], 40);
}

TEST(Track, ReferenceRunTooLong) {
  Homing rig;
  ASSERT_EQ(x4_switch_home(&rig.e, 2, X4_HOME_AUTO, 2000, -500, 20, rig.now), X4_OK);
  rig.Commanded(X4STEP_KIND_HOME);
  rig.Run();
  EXPECT_EQ(rig.Take(), (std::vector<Ev>{Started(0x2, X4STEP_KIND_HOME), Ended(0x2, X4STEP_END_REF_TRAVEL)}))
      << "no REF within sref";
}

TEST(Track, ReferenceRunBrakedBeforeRef) {
  Homing rig;
  ASSERT_EQ(x4_switch_home(&rig.e, 2, X4_HOME_AUTO, 2000, -500, 10000, rig.now), X4_OK);
  rig.Commanded(X4STEP_KIND_HOME);
  rig.Run(10);
  const uint8_t chans = x4_track_chans(&rig.e, 0x2);
  x4_track_stop(&rig.tr.t, chans);
  ASSERT_EQ(x4_engine_stop(&rig.e), X4_OK);
  rig.Commanded(0);
  rig.Run();
  EXPECT_LT(rig.machine[1], 40);
  EXPECT_EQ(rig.Take(), (std::vector<Ev>{Started(0x2, X4STEP_KIND_HOME), Ended(0x2, X4STEP_END_STOPPED)}))
      << "stopped before REF: no switch event, no REF_FOUND";
}

}  // namespace
