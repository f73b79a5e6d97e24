// SPDX-License-Identifier: GPL-2.0
// Continuous paths on the simulated port (lib/sim/path.cpp): x4step::path
// and the X4Path* C functions run the module's planner with the module's
// checks and errnos; a program that streams a path finishes in virtual time.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/x4step.h>
#include <poll.h>
#include <stdlib.h>

#include <cerrno>
#include <chrono>
#include <vector>

#include "sim/port.hpp"
#include "sim/sim.hpp"
#include "sim_env.hpp"
#include "sim_writes.hpp"
#include "x4step.h"
#include "x4step.hpp"
#include "x4step_ext.h"
#include "x4step_path.hpp"

using namespace std::chrono_literals;
using x4step::axis;
using x4step::controller;
using x4step::path_state;

namespace {

class SimPath : public SimEnv {};

// n straight segments of 100 steps on axis 1 and 50 on axis 2, at 5000
// units/s: one unit is a step of axis 1, so the path takes n / 50 s.
std::vector<x4step::segment> line(int n) {
  std::vector<x4step::segment> s(n);
  for (int i = 0; i < n; i++)
    s[i].steps(axis(1), 100)
        .steps(axis(2), 50)
        .length(100)
        .top_speed(5000)
        .accel(20000)
        .tag(i + 1)
        .entry_speed(i ? 5000 : 0);
  return s;
}

std::vector<x4step::event> events(const x4step::monitor &m) {
  std::vector<x4step::event> seen;
  while (auto e = m.read_event(0ms)) seen.push_back(*e);
  return seen;
}

// Machine coordinates: a path's step counters start again at a resume.
long pos(const controller &c, int a) { return c.get_axes()[axis(a)].position; }

// line(200) for a second of virtual time, then held: it stands held.
void RunASecondAndHold(x4step::path &path) {
  auto p = x4step::sim::port::find(0);
  path.append(line(200));
  p->run_until(p->engine_now() + 1000000000u);
  path.hold();
  ASSERT_TRUE(path.wait(10s));
  ASSERT_EQ(path.status().state, path_state::held);
}

unsigned count(const std::vector<x4step::event> &ev, x4step::event_type t, unsigned how) {
  unsigned n = 0;
  for (const auto &e : ev) n += e.type == t && e.how == how;
  return n;
}

}  // namespace

// More segments than the queue holds: append() waits for room (the
// clock runs while it does) and the whole path runs, edge for edge.
TEST_F(SimPath, StreamedPathRunsToItsEnd) {
  controller c("sim");
  x4step::monitor m("sim");
  auto p = x4step::sim::port::find(0);
  p->record(true);
  x4step::path path(c);
  const auto t = std::chrono::steady_clock::now();
  path.append(line(1000));  // the queue holds 256
  ASSERT_TRUE(path.wait(60s));
  // 20 s of motion in virtual time: host time, so bounded by what a run in
  // real time cannot beat (the motion's own 20 s), not by what a loaded
  // host may stretch.
  EXPECT_LT(std::chrono::steady_clock::now() - t, 20s);
  const x4step::path_status s = path.status();
  EXPECT_EQ(s.state, path_state::idle);
  EXPECT_EQ(s.queued, 0u);
  EXPECT_EQ(s.done, 1000u);
  EXPECT_EQ(c.steps(axis(1)), 100000);
  EXPECT_EQ(c.steps(axis(2)), 50000);
  EXPECT_EQ(rises(p->writes(), 1), 100000);
  EXPECT_EQ(rises(p->writes(), 3), 50000);
  EXPECT_GE(p->engine_now(), 20000000000u);
  const auto ev = events(m);
  EXPECT_EQ(count(ev, x4step::event_type::move_started, X4STEP_KIND_PATH), 1u);
  EXPECT_EQ(count(ev, x4step::event_type::move_ended, X4STEP_END_COMPLETED), 1u);
}

// A hold brakes along the path and a resume goes on: the path ends where
// it ends uninterrupted, with the same steps.
TEST_F(SimPath, HoldAndResumeEndWhereAnUninterruptedRunEnds) {
  long straight[2];
  {
    controller c("sim");
    x4step::path path(c);
    path.append(line(200));
    ASSERT_TRUE(path.wait(60s));
    straight[0] = pos(c, 1);
    straight[1] = pos(c, 2);
  }
  controller c("sim");
  x4step::monitor m("sim");
  auto p = x4step::sim::port::find(0);
  p->record(true);
  x4step::path path(c);
  path.append(line(200));
  p->run_until(p->engine_now() + 1500000000u);  // 1.5 s into the 4 s path
  ASSERT_EQ(path.status().state, path_state::running);
  path.hold();
  ASSERT_TRUE(path.wait(10s));
  const x4step::path_status held = path.status();
  EXPECT_EQ(held.state, path_state::held);
  EXPECT_GT(held.queued, 0u);
  EXPECT_GT(pos(c, 1), 0);
  EXPECT_LT(pos(c, 1), straight[0]);
  path.resume();
  ASSERT_TRUE(path.wait(60s));
  EXPECT_EQ(path.status().state, path_state::idle);
  EXPECT_EQ(pos(c, 1), straight[0]);
  EXPECT_EQ(pos(c, 2), straight[1]);
  EXPECT_EQ(rises(p->writes(), 1), straight[0]);
  EXPECT_EQ(rises(p->writes(), 3), straight[1]);
  const auto ev = events(m);
  EXPECT_EQ(count(ev, x4step::event_type::move_ended, X4STEP_END_HELD), 1u);
  EXPECT_EQ(count(ev, x4step::event_type::move_started, X4STEP_KIND_PATH), 2u);
  EXPECT_EQ(count(ev, x4step::event_type::move_ended, X4STEP_END_COMPLETED), 1u);
}

// An abort after a hold flushes the queue: appends fail until clear().
TEST_F(SimPath, AbortAfterHoldFlushes) {
  controller c("sim");
  x4step::monitor m("sim");
  auto p = x4step::sim::port::find(0);
  x4step::path path(c);
  ASSERT_NO_FATAL_FAILURE(RunASecondAndHold(path));
  const long at = pos(c, 1);
  path.abort();
  ASSERT_TRUE(path.wait(10s));
  const x4step::path_status s = path.status();
  EXPECT_EQ(s.state, path_state::idle);
  EXPECT_EQ(s.queued, 0u);
  EXPECT_EQ(pos(c, 1), at);  // held: the abort moves nothing
  try {
    path.append(line(1));
    FAIL() << "append after a flush";
  } catch (const x4step::error &e) {
    EXPECT_EQ(e.code(), x4step::errc::not_active);
  }
  path.clear();
  path.append(line(2));
  ASSERT_TRUE(path.wait(10s));
  EXPECT_EQ(pos(c, 1), at + 200);
  // An abort of a running path brakes along it, then flushes.
  path.append(line(50));
  p->run_until(p->engine_now() + 300000000u);
  path.abort();
  ASSERT_TRUE(path.wait(10s));
  EXPECT_EQ(path.status().queued, 0u);
  EXPECT_LT(pos(c, 1), at + 200 + 5000);
  const auto ev = events(m);
  // The held path's end said HELD; the abort of it moved nothing, and
  // said ABORTED (issue 28), as the abort of the running path did.
  EXPECT_EQ(count(ev, x4step::event_type::move_ended, X4STEP_END_HELD), 1u);
  EXPECT_EQ(count(ev, x4step::event_type::move_ended, X4STEP_END_COMPLETED), 1u);
  EXPECT_EQ(count(ev, x4step::event_type::move_ended, X4STEP_END_ABORTED), 2u);
}

// The requests themselves, as the module answers them: a bad record or
// request gets the module's errno and changes nothing.
TEST_F(SimPath, BadSegmentsAndRequestsGetTheModulesErrno) {
  auto io = x4step::sim::open("sim", O_RDWR);
  auto mon = x4step::sim::open("sim", O_RDONLY);
  auto p = x4step::sim::port::find(0);
  p->record(true);
  x4step_segment r{};
  r.steps[0] = 100;
  r.length = 100;
  r.v_max = 1000;
  r.accel = 10000;
  const auto write_err = [&](const x4step_segment &rec, size_t n) {
    errno = 0;
    EXPECT_EQ(io->write(&rec, n), -1);
    return errno;
  };
  EXPECT_EQ(write_err(r, sizeof r - 1), EINVAL);  // not whole records
  x4step_segment bad = r;
  bad.flags = 1;
  EXPECT_EQ(write_err(bad, sizeof bad), EINVAL);
  bad = r;
  bad.steps[0] = 0;
  EXPECT_EQ(write_err(bad, sizeof bad), EINVAL);  // no steps
  bad = r;
  bad.v_max = 150000;  // 150 kHz on axis 1: beyond any port's rate
  EXPECT_EQ(write_err(bad, sizeof bad), ERANGE);
  errno = 0;
  EXPECT_EQ(mon->write(&r, sizeof r), -1);  // only the controller writes
  EXPECT_EQ(errno, EBADF);
  x4step_path_ctl ctl{};
  ctl.cmd = X4STEP_PATH_HOLD;
  EXPECT_EQ(io->ioctl(X4STEP_PATH_CTL, &ctl), -1);
  EXPECT_EQ(errno, ESRCH);  // no path
  ctl.value = 50;           // a value for anything but the override
  EXPECT_EQ(io->ioctl(X4STEP_PATH_CTL, &ctl), -1);
  EXPECT_EQ(errno, EINVAL);
  ctl = {};
  ctl.cmd = X4STEP_PATH_OVERRIDE;
  ctl.value = 201;
  EXPECT_EQ(io->ioctl(X4STEP_PATH_CTL, &ctl), -1);
  EXPECT_EQ(errno, EINVAL);
  x4step_path_config cfg{};
  cfg.depth = 300;  // not a power of 2
  EXPECT_EQ(io->ioctl(X4STEP_SET_PATH_CONFIG, &cfg), -1);
  EXPECT_EQ(errno, EINVAL);
  cfg.depth = 1024;
  EXPECT_EQ(mon->ioctl(X4STEP_SET_PATH_CONFIG, &cfg), -1);
  EXPECT_EQ(errno, EBADF);
  EXPECT_EQ(io->ioctl(X4STEP_SET_PATH_CONFIG, &cfg), 0);

  // Nothing of that changed the port: no steps, no pin writes, nothing queued.
  x4step_path_status st{};
  ASSERT_EQ(mon->ioctl(X4STEP_GET_PATH, &st), 0);
  EXPECT_EQ(st.state, static_cast<unsigned>(X4STEP_PATH_IDLE));
  EXPECT_EQ(st.queued, 0u);
  EXPECT_EQ(st.depth, 1024u);
  EXPECT_EQ(st.override, 100u);
  EXPECT_TRUE(p->writes().empty());

  // A path owns every axis: a move is EBUSY while it runs, and a record
  // is EBUSY while a move runs.
  EXPECT_EQ(io->write(&r, sizeof r), static_cast<ssize_t>(sizeof r));
  x4step_endless e{};
  e.axis = 2;
  e.direction = 1;
  e.freq_hz = 1000;
  EXPECT_EQ(io->ioctl(X4STEP_MOVE_ENDLESS, &e), -1);
  EXPECT_EQ(errno, EBUSY);
  short rev = 0;
  ASSERT_EQ(io->poll(POLLIN, -1, &rev), 1);  // virtual time: runs to its end
  EXPECT_EQ(io->ioctl(X4STEP_MOVE_ENDLESS, &e), 0);
  EXPECT_EQ(write_err(r, sizeof r), EBUSY);
  ASSERT_EQ(io->ioctl(X4STEP_STOP, nullptr), 0);
}

// Non-blocking: try_append() queues what fits now; room comes as the
// path runs.
TEST_F(SimPath, TryAppendQueuesWhatFits) {
  controller c("sim");
  x4step::path path(c);
  const auto s = line(300);
  EXPECT_EQ(path.try_append(s.data(), s.size()), 256u);
  EXPECT_EQ(path.try_append(s.data() + 256, 44), 0u);
  auto p = x4step::sim::port::find(0);
  p->run_until(p->engine_now() + 500000000u);  // 25 segments done
  const std::size_t more = path.try_append(s.data() + 256, 44);
  EXPECT_GE(more, 10u);
  EXPECT_LT(more, 44u);
  path.append(std::vector<x4step::segment>(s.begin() + 256 + static_cast<long>(more), s.end()));
  ASSERT_TRUE(path.wait(60s));
  EXPECT_EQ(path.status().done, 300u);
}

// The X4Path* C functions under X4STEP_SIM=1: a program that streams a
// path and polls its state to the end finishes.
TEST_F(SimPath, CApiStreamsAPathToItsEnd) {
  setenv("X4STEP_SIM", "1", 1);
  ASSERT_EQ(X4Init(LPT1), X4NoErr);
  std::vector<X4Segment> s(400);
  for (size_t i = 0; i < s.size(); i++)
    s[i] = X4Segment{{100, -100, 0, 0}, 100, 5000, i ? 5000ul : 0, 20000, i + 1};
  ASSERT_EQ(X4PathAppend(s.data(), static_cast<int>(s.size())), X4NoErr);
  int state = X4PATH_RUN;
  long queued = 1;
  while (state != X4PATH_IDLE || queued) ASSERT_EQ(X4PathState(&state, &queued, nullptr), X4NoErr);
  EXPECT_EQ(X4GetSteps(1), 40000);
  EXPECT_EQ(X4GetSteps(2), -40000);
  EXPECT_EQ(X4PathHold(), X4ErrNotActive);
  X4Segment bad = s[0];
  bad.length = 0;
  EXPECT_EQ(X4PathAppend(&bad, 1), X4ErrParamFail);
  EXPECT_EQ(X4ReInit(), X4NoErr);
}

// Issue 28, item 8: an emergency brake aborts a path (hold, then flush):
// the controller cannot resume it, and the streamer learns of it.
TEST_F(SimPath, EmergencyBrakeAbortsThePath) {
  controller c("sim");
  x4step::monitor m("sim");
  auto p = x4step::sim::port::find(0);
  x4step::path path(c);
  path.append(line(200));
  p->run_until(p->engine_now() + 1000000000u);
  ASSERT_EQ(path.status().state, path_state::running);
  m.emergency_halt(x4step::halt_mode::brake);
  ASSERT_TRUE(path.wait(10s));
  const x4step::path_status s = path.status();
  EXPECT_EQ(s.state, path_state::idle);
  EXPECT_EQ(s.queued, 0u);
  EXPECT_THROW(path.resume(), x4step::error);
  EXPECT_THROW(path.append(line(1)), x4step::error);  // flushed: clear() first
  const auto ev = events(m);
  EXPECT_EQ(count(ev, x4step::event_type::move_ended, X4STEP_END_ABORTED), 1u);
  EXPECT_EQ(count(ev, x4step::event_type::move_ended, X4STEP_END_HELD), 0u);
  EXPECT_EQ(count(ev, x4step::event_type::brake, X4STEP_SRC_ESTOP), 1u);
}

// ... and of a held path too: at once, with its end in the event stream.
TEST_F(SimPath, EmergencyBrakeAbortsAHeldPath) {
  controller c("sim");
  x4step::monitor m("sim");
  x4step::path path(c);
  ASSERT_NO_FATAL_FAILURE(RunASecondAndHold(path));
  events(m);
  m.emergency_halt(x4step::halt_mode::brake);
  const x4step::path_status s = path.status();
  EXPECT_EQ(s.state, path_state::idle);
  EXPECT_EQ(s.queued, 0u);
  EXPECT_THROW(path.append(line(1)), x4step::error);
  EXPECT_EQ(count(events(m), x4step::event_type::move_ended, X4STEP_END_ABORTED), 1u);
}

// Issue 28, item 9: PATH_CTL ABORT of a held path tells its end.
TEST_F(SimPath, AbortOfAHeldPathIsAnEvent) {
  controller c("sim");
  x4step::monitor m("sim");
  x4step::path path(c);
  ASSERT_NO_FATAL_FAILURE(RunASecondAndHold(path));
  const auto held = events(m);
  ASSERT_EQ(count(held, x4step::event_type::move_ended, X4STEP_END_HELD), 1u);
  path.abort();
  const auto ev = events(m);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].type, x4step::event_type::move_ended);
  EXPECT_EQ(ev[0].how, unsigned(X4STEP_END_ABORTED));
  // The path's axes (every axis: it owns them), not the segments' (1, 2).
  EXPECT_EQ(ev[0].axes.mask(), 0x0fu);
  for (const auto &e : held)
    if (e.type == x4step::event_type::move_started || e.type == x4step::event_type::move_ended) {
      EXPECT_EQ(e.axes.mask(), 0x0fu) << "event " << e.seq;
    }
}
