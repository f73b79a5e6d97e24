// SPDX-License-Identifier: GPL-2.0
// Unit tests of kmod/engine/x4_req.c: the module's request records as the
// engine takes them. Which fields make a request invalid (every reserved
// word, every bound on both sides), the records copied into the engine's
// arguments and back, the X4Step results as errnos. The module and the
// simulated port both answer through these functions; here each is called
// alone, with the bound and the first value past it.
#include <gtest/gtest.h>

#include <cerrno>
#include <cstring>

extern "C" {
#include "x4_req.h"
}

namespace {

// A record of bytes `fill` (0xff: fields the function must write show it).
template <class T>
T Filled(unsigned char fill) {
  T r;
  std::memset(&r, fill, sizeof r);
  return r;
}

TEST(Req, ErrnoOfEachResult) {
  EXPECT_EQ(x4_req_errno(X4_OK), 0);
  EXPECT_EQ(x4_req_errno(X4_ERR_IS_ACTIVE), -EBUSY);
  EXPECT_EQ(x4_req_errno(X4_ERR_IS_LOADED), -EEXIST);
  EXPECT_EQ(x4_req_errno(X4_ERR_NOT_LOADED), -ENODATA);
  EXPECT_EQ(x4_req_errno(X4_ERR_NOT_ACTIVE), -ESRCH);
  EXPECT_EQ(x4_req_errno(X4_ERR_RATE_BUDGET), -ERANGE);
  for (int r : {X4_ERR_NO_STEPS, X4_ERR_FREQ_TOO_HIGH, X4_ERR_FREQ_TOO_LOW, X4_ERR_RAMP_TOO_HIGH,
                X4_ERR_RAMP_FREQ, X4_ERR_PARAM_FAIL, X4_ERR_STEPS_TOO_HIGH})
    EXPECT_EQ(x4_req_errno(r), -EINVAL) << r;
}

TEST(Req, ResultOverTheBudgetIsFreqTooHigh) {
  EXPECT_EQ(x4_req_result(X4_ERR_RATE_BUDGET), X4_ERR_FREQ_TOO_HIGH);
  for (int r = X4_OK; r <= X4_ERR_STEPS_TOO_HIGH; r++) EXPECT_EQ(x4_req_result(r), r);
}

TEST(Req, BadEndless) {
  x4step_endless u{};
  u.axis = 1;
  u.direction = 1;
  EXPECT_FALSE(x4_req_bad_endless(&u));
  u.direction = -1;
  EXPECT_FALSE(x4_req_bad_endless(&u));
  for (int d : {0, 2, -2}) {
    u.direction = d;
    EXPECT_TRUE(x4_req_bad_endless(&u)) << d;
  }
  u.direction = 1;
  u.flags = 1;
  EXPECT_TRUE(x4_req_bad_endless(&u));
  u.flags = 0;
  for (auto &w : u.reserved) {
    w = 1;
    EXPECT_TRUE(x4_req_bad_endless(&u));
    w = 0;
  }
}

TEST(Req, BadGoto) {
  x4step_goto u{};
  u.axes = 0x0f;
  u.flags = X4STEP_GOTO_RELATIVE;
  EXPECT_FALSE(x4_req_bad_goto(&u));
  u.axes = 0x10;
  EXPECT_TRUE(x4_req_bad_goto(&u));
  u.axes = 1;
  u.flags = X4STEP_GOTO_RELATIVE << 1;
  EXPECT_TRUE(x4_req_bad_goto(&u));
  u.flags = 0;
  for (auto &w : u.reserved) {
    w = 1;
    EXPECT_TRUE(x4_req_bad_goto(&u));
    w = 0;
  }
  EXPECT_FALSE(x4_req_bad_goto(&u));
}

TEST(Req, BadHome) {
  x4step_home u{};
  u.phases = X4STEP_HOME_AUTO | X4STEP_HOME_BRAKE;
  EXPECT_FALSE(x4_req_bad_home(&u));
  u.phases++;
  EXPECT_TRUE(x4_req_bad_home(&u));
  u.phases = X4STEP_HOME_PHASE1;
  for (auto &w : u.reserved) {
    w = 1;
    EXPECT_TRUE(x4_req_bad_home(&u));
    w = 0;
  }
  EXPECT_FALSE(x4_req_bad_home(&u));
}

TEST(Req, BadHalt) {
  x4step_halt u{};
  u.axes = 0x0f;
  u.how = X4STEP_HALT_STOP;
  EXPECT_FALSE(x4_req_bad_halt(&u));
  u.how = X4STEP_HALT_STOP + 1;
  EXPECT_TRUE(x4_req_bad_halt(&u));
  u.how = X4STEP_HALT_BRAKE;
  u.axes = 0;
  EXPECT_TRUE(x4_req_bad_halt(&u));
  u.axes = 0x10;
  EXPECT_TRUE(x4_req_bad_halt(&u));
  u.axes = 1;
  for (auto &w : u.reserved) {
    w = 1;
    EXPECT_TRUE(x4_req_bad_halt(&u));
    w = 0;
  }
  EXPECT_FALSE(x4_req_bad_halt(&u));
}

TEST(Req, BadEstop) {
  x4step_estop u{};
  u.how = X4STEP_HALT_STOP;
  EXPECT_FALSE(x4_req_bad_estop(&u));
  u.how = X4STEP_HALT_STOP + 1;
  EXPECT_TRUE(x4_req_bad_estop(&u));
  u.how = X4STEP_HALT_BRAKE;
  u.flags = 1;
  EXPECT_TRUE(x4_req_bad_estop(&u));
  u.flags = 0;
  for (auto &w : u.reserved) {
    w = 1;
    EXPECT_TRUE(x4_req_bad_estop(&u));
    w = 0;
  }
  EXPECT_FALSE(x4_req_bad_estop(&u));
}

TEST(Req, BadPosition) {
  x4step_position u{};
  u.axes = 0x0f;
  EXPECT_FALSE(x4_req_bad_position(&u));
  u.axes = 0;
  EXPECT_TRUE(x4_req_bad_position(&u));
  u.axes = 0x10;
  EXPECT_TRUE(x4_req_bad_position(&u));
  u.axes = 1;
  u.reserved = 1;
  EXPECT_TRUE(x4_req_bad_position(&u));
}

TEST(Req, BadOutput) {
  for (uint32_t s : {X4STEP_OUT_SIGNAL1, X4STEP_OUT_SIGNAL2})
    for (uint32_t level : {0u, 1u}) {
      const x4step_output o{s, level};
      EXPECT_FALSE(x4_req_bad_output(&o)) << s << " " << level;
    }
  for (uint32_t s : {0u, X4STEP_OUT_SIGNAL1 | X4STEP_OUT_SIGNAL2, X4STEP_OUT_SIGNAL2 << 1}) {
    const x4step_output o{s, 0};
    EXPECT_TRUE(x4_req_bad_output(&o)) << s;
  }
  const x4step_output o{X4STEP_OUT_SIGNAL1, 2};
  EXPECT_TRUE(x4_req_bad_output(&o));
}

TEST(Req, BadOutputs) {
  x4step_outputs u{};
  u.mask = X4STEP_OUT_SIGNAL1 | X4STEP_OUT_SIGNAL2;
  u.levels = X4STEP_OUT_SIGNAL2;
  EXPECT_FALSE(x4_req_bad_outputs(&u));
  u.mask = X4STEP_OUT_SIGNAL1;
  EXPECT_TRUE(x4_req_bad_outputs(&u)) << "a level outside the mask";
  u.levels = X4STEP_OUT_SIGNAL1;
  EXPECT_FALSE(x4_req_bad_outputs(&u));
  u.mask = 0;
  u.levels = 0;
  EXPECT_TRUE(x4_req_bad_outputs(&u)) << "no signal";
  u.mask = X4STEP_OUT_SIGNAL1 | (X4STEP_OUT_SIGNAL2 << 1);
  EXPECT_TRUE(x4_req_bad_outputs(&u)) << "a signal that is none";
  u.mask = X4STEP_OUT_SIGNAL1;
  u.flags = 1;
  EXPECT_TRUE(x4_req_bad_outputs(&u));
  u.flags = 0;
  for (auto &w : u.reserved) {
    w = 1;
    EXPECT_TRUE(x4_req_bad_outputs(&u));
    w = 0;
  }
  EXPECT_FALSE(x4_req_bad_outputs(&u));
}

TEST(Req, BadBrakeCodes) {
  x4step_brake_codes u{};
  EXPECT_FALSE(x4_req_bad_brake_codes(&u)) << "no codes";
  u.count = X4STEP_MAX_BRAKE_CODES;
  for (auto &c : u.codes) c = 255;
  EXPECT_FALSE(x4_req_bad_brake_codes(&u));
  u.count = X4STEP_MAX_BRAKE_CODES + 1;
  EXPECT_TRUE(x4_req_bad_brake_codes(&u));
  u.count = 2;
  u.codes[1] = 256;
  EXPECT_TRUE(x4_req_bad_brake_codes(&u));
  u.codes[1] = 0;
  EXPECT_TRUE(x4_req_bad_brake_codes(&u));
  u.codes[1] = 1;
  u.codes[2] = 0;  // past count: not looked at
  EXPECT_FALSE(x4_req_bad_brake_codes(&u));
  u.reserved = 1;
  EXPECT_TRUE(x4_req_bad_brake_codes(&u));
}

TEST(Req, BadConfig) {
  x4step_config u{};
  u.clock_invert = 0xf;
  u.dir_invert = 0xf;
  u.flags = X4STEP_CFG_KEYS_SWALLOW;
  u.output_mode = X4STEP_MODE_SMC_PHASE_HOLD;
  EXPECT_FALSE(x4_req_bad_config(&u));
  u.clock_invert = 0x10;
  EXPECT_TRUE(x4_req_bad_config(&u));
  u.clock_invert = 0;
  u.dir_invert = 0x10;
  EXPECT_TRUE(x4_req_bad_config(&u));
  u.dir_invert = 0;
  u.flags = X4STEP_CFG_KEYS_SWALLOW << 1;
  EXPECT_TRUE(x4_req_bad_config(&u));
  u.flags = 0;
  u.output_mode = X4STEP_MODE_SMC_PHASE_HOLD + 1;
  EXPECT_TRUE(x4_req_bad_config(&u));
  u.output_mode = X4STEP_MODE_CLOCK_DIR;
  for (auto &w : u.reserved) {
    w = 1;
    EXPECT_TRUE(x4_req_bad_config(&u));
    w = 0;
  }
  EXPECT_FALSE(x4_req_bad_config(&u));
}

TEST(Req, BadStepTimingAndSwitchesOnlyByReservedFields) {
  x4step_step_timing t = Filled<x4step_step_timing>(0xff);
  std::memset(t.reserved, 0, sizeof t.reserved);
  EXPECT_FALSE(x4_req_bad_step_timing(&t)) << "the values are the engine's to check";
  for (auto &w : t.reserved) {
    w = 1;
    EXPECT_TRUE(x4_req_bad_step_timing(&t));
    w = 0;
  }
  x4step_switches s = Filled<x4step_switches>(0xff);
  std::memset(s.reserved, 0, sizeof s.reserved);
  EXPECT_FALSE(x4_req_bad_switches(&s)) << "the values are the engine's to check";
  for (auto &b : s.reserved) {
    b = 1;
    EXPECT_TRUE(x4_req_bad_switches(&s));
    b = 0;
  }
}

TEST(Req, ProfileAxisAndCopy) {
  x4step_profile u{};
  u.v0 = 1;
  u.ve = 2;
  u.vm = 3;
  u.a0 = 4;
  u.ae = 5;
  for (uint32_t axis : {0u, uint32_t(X4_AXES + 1)}) {
    u.axis = axis;
    x4_profile p{};
    EXPECT_EQ(x4_req_profile(&u, &p), -EINVAL) << axis;
  }
  for (uint32_t axis = 1; axis <= X4_AXES; axis++) {
    u.axis = axis;
    x4_profile p{};
    ASSERT_EQ(x4_req_profile(&u, &p), 0) << axis;
    EXPECT_EQ(p.v0, 1u);
    EXPECT_EQ(p.ve, 2u);
    EXPECT_EQ(p.vm, 3u);
    EXPECT_EQ(p.a0, 4u);
    EXPECT_EQ(p.ae, 5u);
  }
  u.axis = 1;
  for (auto &w : u.reserved) {
    w = 1;
    x4_profile p{};
    EXPECT_EQ(x4_req_profile(&u, &p), -EINVAL);
    w = 0;
  }
}

// Set through the request, read back through the answer: the same values,
// and the answer's other fields zero (not what the caller's record held).
TEST(Req, SwitchesProfileAndTimingRoundTrip) {
  x4_engine e;
  x4_engine_init(&e);

  x4step_switches us{};
  us.ref[0] = 1;
  us.plus[1] = 2;
  us.minus[1] = 3;
  us.ref[3] = 5;
  us.nc = 0x14;
  x4_switches sw;
  std::memset(&sw, 0xff, sizeof sw);
  x4_req_switches(&us, &sw);
  EXPECT_EQ(std::memcmp(sw.ref, us.ref, sizeof sw.ref), 0);
  EXPECT_EQ(std::memcmp(sw.plus, us.plus, sizeof sw.plus), 0);
  EXPECT_EQ(std::memcmp(sw.minus, us.minus, sizeof sw.minus), 0);
  EXPECT_EQ(sw.nc, 0x14);
  ASSERT_EQ(x4_switch_set(&e, &sw), X4_OK);
  x4step_switches got = Filled<x4step_switches>(0xff);
  x4_req_get_switches(&e, &got);
  EXPECT_EQ(std::memcmp(&got, &us, sizeof us), 0);

  x4step_profile up{};
  up.axis = 3;
  up.v0 = 100;
  up.ve = 200;
  up.vm = 3000;
  up.a0 = 40000;
  up.ae = 50000;
  x4_profile p{};
  ASSERT_EQ(x4_req_profile(&up, &p), 0);
  ASSERT_EQ(x4_engine_set_profile(&e, 3, &p), X4_OK);
  x4step_profile gp = Filled<x4step_profile>(0xff);
  x4_req_get_profile(&e, 3, &gp);
  EXPECT_EQ(std::memcmp(&gp, &up, sizeof up), 0);

  x4step_step_timing ut{};
  ut.pulse_ns = 5000;
  ut.space_ns = 6000;
  ut.dir_setup_ns = 7000;
  ut.dir_hold_ns = 8000;
  x4_timing t;
  std::memset(&t, 0, sizeof t);
  x4_req_step_timing(&ut, &t);
  EXPECT_EQ(t.pulse_ns, 5000u);
  EXPECT_EQ(t.space_ns, 6000u);
  EXPECT_EQ(t.dir_setup_ns, 7000u);
  EXPECT_EQ(t.dir_hold_ns, 8000u);
  e.timing = t;  // the engine's own checks are x4_engine_configure's
  x4step_step_timing gt = Filled<x4step_step_timing>(0xff);
  x4_req_get_step_timing(&e, &gt);
  EXPECT_EQ(std::memcmp(&gt, &ut, sizeof ut), 0);
}

TEST(Req, AxesFromTheEngine) {
  x4_engine e;
  x4_engine_init(&e);
  x4_switches sw{};
  sw.plus[0] = 2;  // input 2: axis 1's E+
  ASSERT_EQ(x4_switch_set(&e, &sw), X4_OK);
  const int32_t pos[X4_AXES] = {10, -20, 30, -40};
  ASSERT_EQ(x4_engine_set_position(&e, 0x0f, pos), X4_OK);

  x4step_axes ua{};
  x4_req_get_axes(&e, 0x02, 1, &ua);
  EXPECT_EQ(ua.inputs, 0x02u);
  EXPECT_EQ(ua.switches, uint32_t(x4_switch_active(&e, 0x02)));
  EXPECT_NE(ua.switches, 0u);
  for (int i = 0; i < X4_AXES; i++) {
    x4_axis_state st;
    x4_status_axis(&e, i, &st);
    EXPECT_EQ(ua.axis[i].position, pos[i]) << i;
    EXPECT_EQ(ua.axis[i].state, st.state) << i;
    EXPECT_EQ(ua.axis[i].error, st.error) << i;
    EXPECT_EQ(ua.axis[i].velocity, st.velocity) << i;
  }
  // Inputs never read (their time 0): no switch is shown active.
  x4step_axes never{};
  x4_req_get_axes(&e, 0x02, 0, &never);
  EXPECT_EQ(never.inputs, 0x02u);
  EXPECT_EQ(never.switches, 0u);
}

TEST(Req, SegmentCopiedAndChecked) {
  x4step_segment r{};
  r.steps[0] = 100;
  r.steps[1] = -50;
  r.steps[3] = 7;
  r.length = 1000;
  r.v_max = 2000;
  r.v_entry = 500;
  r.accel = 10000;
  r.tag = 0x123456789abcull;
  x4_segment seg;
  std::memset(&seg, 0xff, sizeof seg);
  ASSERT_EQ(x4_req_segment(&r, &seg), X4_OK);
  for (int i = 0; i < X4_AXES; i++) EXPECT_EQ(seg.steps[i], r.steps[i]) << i;
  EXPECT_EQ(seg.length, 1000u);
  EXPECT_EQ(seg.v_max, 2000u);
  EXPECT_EQ(seg.v_entry, 500u);
  EXPECT_EQ(seg.accel, 10000u);
  EXPECT_EQ(seg.tag, 0x123456789abcull);
  EXPECT_EQ(x4_req_segment(&r, &seg), x4_segment_check(&seg, 0));
  r.flags = 4;  // 1 and 2: probing (Req.SegmentProbeFlags)
  EXPECT_EQ(x4_req_segment(&r, &seg), X4_ERR_PARAM_FAIL);
  r.flags = 0;
  r.reserved = 1;
  EXPECT_EQ(x4_req_segment(&r, &seg), X4_ERR_PARAM_FAIL);
  r.reserved = 0;
  r.steps[0] = r.steps[1] = r.steps[3] = 0;
  EXPECT_EQ(x4_req_segment(&r, &seg), X4_ERR_NO_STEPS);
}

TEST(Req, BadPathCtl) {
  x4step_path_ctl c{};
  for (uint32_t cmd : {uint32_t(X4STEP_PATH_HOLD), uint32_t(X4STEP_PATH_RESUME), uint32_t(X4STEP_PATH_ABORT),
                       uint32_t(X4STEP_PATH_OVERRIDE)}) {
    c.cmd = cmd;
    c.value = 0;
    EXPECT_FALSE(x4_req_bad_path_ctl(&c)) << cmd;
    c.value = 50;
    EXPECT_EQ(x4_req_bad_path_ctl(&c), cmd != X4STEP_PATH_OVERRIDE) << cmd << ": a value is OVERRIDE's only";
  }
  c.value = 0;
  for (auto &w : c.reserved) {
    w = 1;
    EXPECT_TRUE(x4_req_bad_path_ctl(&c));
    w = 0;
  }
}

TEST(Req, BadPathConfig) {
  x4step_path_config c{};
  EXPECT_FALSE(x4_req_bad_path_config(&c)) << "depth 0 keeps it";
  for (uint32_t d = X4STEP_PATH_DEPTH_MIN; d <= X4STEP_PATH_DEPTH_MAX; d *= 2) {
    c.depth = d;
    EXPECT_FALSE(x4_req_bad_path_config(&c)) << d;
    c.depth = d + 1;
    EXPECT_TRUE(x4_req_bad_path_config(&c)) << d + 1 << ": not a power of 2";
  }
  for (uint32_t d : {1u, uint32_t(X4STEP_PATH_DEPTH_MIN / 2), uint32_t(X4STEP_PATH_DEPTH_MAX * 2)}) {
    c.depth = d;
    EXPECT_TRUE(x4_req_bad_path_config(&c)) << d;
  }
  c.depth = 0;
  c.flags = X4STEP_PATH_KEYS_ABORT;
  EXPECT_FALSE(x4_req_bad_path_config(&c));
  c.flags = X4STEP_PATH_KEYS_ABORT | X4STEP_PATH_PROBE_NC;
  EXPECT_FALSE(x4_req_bad_path_config(&c));
  c.flags = X4STEP_PATH_PROBE_NC << 1;
  EXPECT_TRUE(x4_req_bad_path_config(&c));
  c.flags = 0;
  for (uint32_t in = 0; in <= 5; in++) {
    c.probe = in;
    EXPECT_FALSE(x4_req_bad_path_config(&c)) << "probe input " << in;
  }
  for (uint32_t in : {6u, 0xffffffffu}) {
    c.probe = in;
    EXPECT_TRUE(x4_req_bad_path_config(&c)) << "probe input " << in;
  }
  c.probe = 0;
  c.reserved = 1;
  EXPECT_TRUE(x4_req_bad_path_config(&c));
  c.reserved = 0;
}

TEST(Req, PathConfigAnswer) {
  x4_engine e;
  x4_engine_init(&e);
  e.path.depth = 0;
  x4step_path_config c = Filled<x4step_path_config>(0xff);
  x4_req_path_config(&e, X4STEP_PATH_KEYS_ABORT, &c);
  EXPECT_EQ(c.depth, uint32_t(X4STEP_PATH_DEPTH_MIN)) << "no queue yet: the default";
  EXPECT_EQ(c.flags, uint32_t(X4STEP_PATH_KEYS_ABORT));
  EXPECT_EQ(c.probe | c.reserved, 0u);
  e.path.depth = 1024;
  x4_req_path_config(&e, 0, &c);
  EXPECT_EQ(c.depth, 1024u);
  EXPECT_EQ(c.flags, 0u);
  // The probe input and its polarity: the engine's.
  ASSERT_EQ(x4_path_set_probe(&e, 4, true), X4_OK);
  x4_req_path_config(&e, 0, &c);
  EXPECT_EQ(c.probe, 4u);
  EXPECT_EQ(c.flags, uint32_t(X4STEP_PATH_PROBE_NC));
  x4step_path_config set{};
  set.probe = 2;
  ASSERT_EQ(x4_req_set_probe(&e, &set), X4_OK);
  EXPECT_EQ(e.path.probe_input, 2);
  EXPECT_FALSE(e.path.probe_nc);
}

TEST(Req, ProbeAnswer) {
  x4_engine e;
  x4_engine_init(&e);
  e.path.probe_input = 3;
  e.path.latch.tripped = true;
  for (int i = 0; i < X4_AXES; i++) e.path.latch.position[i] = -1000 * (i + 1);
  e.path.latch.tag = 42;
  e.path.latch.runs = 5;
  e.path.latch.trips = 4;
  x4step_probe p = Filled<x4step_probe>(0xff);
  x4_req_probe(&e, &p);
  EXPECT_EQ(p.flags, uint32_t(X4STEP_PROBE_TRIPPED));
  EXPECT_EQ(p.input, 3u);
  EXPECT_EQ(p.tag, 42u);
  for (int i = 0; i < X4_AXES; i++) EXPECT_EQ(p.position[i], -1000 * (i + 1));
  EXPECT_EQ(p.runs, 5u);
  EXPECT_EQ(p.trips, 4u);
  for (uint32_t w : p.reserved) EXPECT_EQ(w, 0u);
  e.path.latch.tripped = false;
  x4_req_probe(&e, &p);
  EXPECT_EQ(p.flags, 0u);
}

// A record's probe flags: one of them, or none; both, or another flag, EINVAL.
TEST(Req, SegmentProbeFlags) {
  x4step_segment r{};
  r.steps[0] = 100;
  r.length = 100;
  r.v_max = 1000;
  r.accel = 10000;
  x4_segment s;
  ASSERT_EQ(x4_req_segment(&r, &s), X4_OK);
  EXPECT_EQ(s.probe, X4_PROBE_NONE);
  r.flags = X4STEP_SEG_PROBE_TOWARD;
  ASSERT_EQ(x4_req_segment(&r, &s), X4_OK);
  EXPECT_EQ(s.probe, X4_PROBE_TOWARD);
  r.flags = X4STEP_SEG_PROBE_AWAY;
  ASSERT_EQ(x4_req_segment(&r, &s), X4_OK);
  EXPECT_EQ(s.probe, X4_PROBE_AWAY);
  for (uint32_t f : {uint32_t(X4STEP_SEG_PROBE_TOWARD | X4STEP_SEG_PROBE_AWAY),
                     uint32_t(X4STEP_SEG_PROBE_AWAY << 1), uint32_t(X4STEP_SEG_PROBE_TOWARD | 0x80000000u)}) {
    r.flags = f;
    EXPECT_EQ(x4_req_segment(&r, &s), X4_ERR_PARAM_FAIL) << std::hex << f;
  }
  r.flags = X4STEP_SEG_PROBE_TOWARD;
  r.reserved = 1;
  EXPECT_EQ(x4_req_segment(&r, &s), X4_ERR_PARAM_FAIL);
}

TEST(Req, PathStatusAnswer) {
  x4_path_status s{};
  s.state = 2;
  s.queued = 3;
  s.depth = 512;
  s.override = 150;
  s.speed = 1234;
  s.tag = 77;
  s.done = 88;
  s.starved = 9;
  x4step_path_status st = Filled<x4step_path_status>(0xff);
  x4_req_path_status(&s, X4STEP_PATH_KEYS_ABORT, &st);
  EXPECT_EQ(st.state, 2u);
  EXPECT_EQ(st.queued, 3u);
  EXPECT_EQ(st.depth, 512u);
  EXPECT_EQ(st.override, 150u);
  EXPECT_EQ(st.speed, 1234u);
  EXPECT_EQ(st.flags, uint32_t(X4STEP_PATH_KEYS_ABORT));
  EXPECT_EQ(st.tag, 77u);
  EXPECT_EQ(st.done, 88u);
  EXPECT_EQ(st.starved, 9u);
  for (auto w : st.reserved) EXPECT_EQ(w, 0u);
  // Before any path: the default depth and 100 %.
  s.depth = 0;
  s.override = 0;
  x4_req_path_status(&s, 0, &st);
  EXPECT_EQ(st.depth, uint32_t(X4STEP_PATH_DEPTH_MIN));
  EXPECT_EQ(st.override, 100u);
}

}  // namespace
