// SPDX-License-Identifier: GPL-2.0
// Probing on the simulated port (issue 31, G38.2..G38.5): a probe switch
// on the machine (X4STEP_SIM_MACHINE, "probe AXIS above AT PIN no|nc") at
// a known position; x4step::path's probing segments latch the step at
// which its input changed, at several feeds, toward and away; a start
// with the probe tripped already moves nothing; a probing segment that
// ends without a trip lets the path go on; without a probe input it is
// refused. Also the C API's X4PathProbe*.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/x4step.h>
#include <stdlib.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <string>
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
using x4step::probe_mode;

namespace {

// The probe on axis 3 (Z), active at 1000 and above, on pin 12: input 3.
constexpr int kProbeInput = 3;
constexpr long kAt = 1000;

class SimProbe : public SimEnv {
 protected:
  void SetUp() override {
    SimEnv::SetUp();
    machine_file_ = ::testing::TempDir() + "sim_probe_test.machine";
    std::ofstream(machine_file_) << "probe 3 above " << kAt << " pin12 " << (nc_ ? "nc" : "no") << "\n";
    setenv("X4STEP_SIM_MACHINE", machine_file_.c_str(), 1);
  }
  void TearDown() override {
    SimEnv::TearDown();
    ::unlink(machine_file_.c_str());
  }
  std::string machine_file_;
  bool nc_ = false;
};

// Z (the leader) by z steps, X by x, one unit a Z step, at feed steps/s.
x4step::segment Seg(long z, long x, std::uint32_t feed, probe_mode m = probe_mode::none,
                    std::uint64_t tag = 0) {
  return x4step::segment{}
      .steps(axis(3), z)
      .steps(axis(1), x)
      .length(static_cast<std::uint32_t>(std::labs(z)))
      .top_speed(feed)
      .accel(100000)
      .tag(tag)
      .probe(m);
}

std::vector<x4step::event> events(const x4step::monitor &m) {
  std::vector<x4step::event> seen;
  while (auto e = m.read_event(0ms)) seen.push_back(*e);
  return seen;
}

unsigned count(const std::vector<x4step::event> &ev, x4step::event_type t, unsigned how) {
  unsigned n = 0;
  for (const auto &e : ev) n += e.type == t && e.how == how;
  return n;
}

// Run a probing segment from where Z stands; the path ends tripped,
// flushed (append throws not_active until clear()). The latch.
x4step::probe_latch ProbeAndClear(x4step::path &path, const x4step::segment &s) {
  path.append(s);
  EXPECT_TRUE(path.wait(60s));
  const x4step::probe_latch l = path.probe();
  EXPECT_TRUE(l.tripped);
  EXPECT_EQ(path.status().state, path_state::idle);
  EXPECT_THROW(path.append(Seg(10, 0, 1000)), x4step::error) << "flushed: clear() first";
  path.clear();
  return l;
}

// Toward the probe from 0 and away from it back down, at feeds from
// 200 to 40000 steps/s: the latch is the step at which the input
// changed (1000 going up, 999 going down), X on the line with it; the
// machine stopped within the brake from that speed.
TEST_F(SimProbe, LatchIsTheStepAtWhichTheInputChangedAtAnyFeed) {
  controller c("sim");
  x4step::monitor m("sim");
  auto p = x4step::sim::port::find(0);
  x4step::path path(c);
  path.configure(x4step::path_config{}.probe_input(kProbeInput, false));
  EXPECT_EQ(path.config().probe_input(), 3u);
  EXPECT_FALSE(path.config().probe_active_low());
  for (const std::uint32_t feed : {200u, 3000u, 40000u}) {
    const long z0 = p->machine_positions()[2], x0 = p->machine_positions()[0];
    ASSERT_LT(z0, kAt);
    const x4step::probe_latch up = ProbeAndClear(path, Seg(4000, 1200, feed, probe_mode::toward, feed));
    EXPECT_EQ(up.tag, feed);
    EXPECT_EQ(up.steps[2], kAt) << "toward at " << feed << " steps/s";
    EXPECT_EQ(up.steps[0], x0 + std::lround((kAt - z0) * 1200.0 / 4000)) << "X on the line";
    const long z1 = p->machine_positions()[2];
    EXPECT_GE(z1, kAt);
    EXPECT_LE(z1 - kAt, feed * feed / (2 * 100000) + 2) << "it braked from " << feed << " steps/s";
    const x4step::probe_latch down = ProbeAndClear(path, Seg(-4000, -1200, feed, probe_mode::away, feed + 1));
    EXPECT_EQ(down.steps[2], kAt - 1) << "away at " << feed << " steps/s";
    EXPECT_LT(p->machine_positions()[2], kAt);
    const long z2 = p->machine_positions()[2];
    EXPECT_LE(kAt - 1 - z2, feed * feed / (2 * 100000) + 2);
    // Back to 2000 below the probe: within the next probing segment's reach.
    if (z2 != kAt - 2000) path.append(Seg(-(z2 - (kAt - 2000)), 0, 20000));
    ASSERT_TRUE(path.wait(60s));
  }
  const auto ev = events(m);
  EXPECT_EQ(count(ev, x4step::event_type::switch_hit, X4STEP_SW_PROBE), 6u);
  EXPECT_EQ(count(ev, x4step::event_type::move_ended, X4STEP_END_ABORTED), 6u);
  for (const auto &e : ev) {
    if (e.type == x4step::event_type::switch_hit) {
      EXPECT_EQ(e.value, unsigned(kProbeInput));
    }
  }
}

// The probe tripped already when the probing segment starts: no step, the
// latch where the axes stand.
TEST_F(SimProbe, TrippedAtTheStartMovesNothing) {
  controller c("sim");
  auto p = x4step::sim::port::find(0);
  p->record(true);
  x4step::path path(c);
  path.configure(x4step::path_config{}.probe_input(kProbeInput, false));
  path.append(Seg(1500, 300, 5000));  // onto the probe, not probing
  ASSERT_TRUE(path.wait(60s));
  const auto writes = p->writes().size();
  const x4step::probe_latch l = ProbeAndClear(path, Seg(500, 100, 5000, probe_mode::toward, 7));
  EXPECT_EQ(l.steps[2], 1500);
  EXPECT_EQ(l.steps[0], 300);
  EXPECT_EQ(p->machine_positions()[2], 1500);
  EXPECT_EQ(p->machine_positions()[0], 300);
  long clocks = 0;
  for (std::size_t i = writes; i < p->writes().size(); i++) clocks += p->writes()[i].data & 0xaa;
  EXPECT_EQ(clocks, 0) << "no clock edge";
}

// No trip: the probing segment ends, and the path goes on after it.
TEST_F(SimProbe, NoTripEndLetsThePathGoOn) {
  controller c("sim");
  auto p = x4step::sim::port::find(0);
  x4step::path path(c);
  path.configure(x4step::path_config{}.probe_input(kProbeInput, false));
  path.append({Seg(800, 0, 5000, probe_mode::toward, 3), Seg(0, 0, 5000).steps(axis(1), 500).length(500)});
  ASSERT_TRUE(path.wait(60s));
  const x4step::probe_latch l = path.probe();
  EXPECT_FALSE(l.tripped);
  EXPECT_EQ(l.tag, 3u);
  EXPECT_EQ(l.steps, (std::array<long, x4step::axes>{}));
  EXPECT_EQ(p->machine_positions()[2], 800);
  EXPECT_EQ(p->machine_positions()[0], 500);
  EXPECT_EQ(path.status().done, 2u);
  path.append(Seg(-800, 0, 5000));  // not flushed: no clear() needed
  ASSERT_TRUE(path.wait(60s));
}

// A normally closed probe (the machine's switch nc, the path's probe
// active low): the same latch.
class SimProbeNc : public SimProbe {
 protected:
  void SetUp() override {
    nc_ = true;
    SimProbe::SetUp();
  }
};

TEST_F(SimProbeNc, NormallyClosedProbeLatchesAlike) {
  controller c("sim");
  x4step::path path(c);
  path.configure(x4step::path_config{}.probe_input(kProbeInput, true));
  EXPECT_TRUE(path.config().probe_active_low());
  EXPECT_EQ(ProbeAndClear(path, Seg(3000, 0, 2000, probe_mode::toward)).steps[2], kAt);
}

// Without a probe input a probing segment is refused (param_fail), and
// the input changes only while no path is active.
TEST_F(SimProbe, RefusedWithoutAProbeInput) {
  controller c("sim");
  x4step::path path(c);
  try {
    path.append(Seg(100, 0, 1000, probe_mode::toward));
    ADD_FAILURE() << "a probing segment without a probe input was queued";
  } catch (const x4step::error &e) {
    EXPECT_EQ(e.code(), x4step::make_error_code(x4step::errc::param_fail));
  }
  EXPECT_EQ(x4step::check(Seg(100, 0, 1000, probe_mode::away)), x4step::errc::ok)
      << "the port's input decides";
  EXPECT_EQ(x4step::check(Seg(100, 0, 1000, static_cast<probe_mode>(7))), x4step::errc::param_fail);
  try {
    path.configure(x4step::path_config{}.probe_input(6, false));
    ADD_FAILURE() << "probe input 6 accepted";
  } catch (const x4step::error &e) {
    EXPECT_EQ(e.code(), x4step::make_error_code(x4step::errc::param_fail));
  }
  path.configure(x4step::path_config{}.probe_input(kProbeInput, false));
  path.append(Seg(3000, 0, 1000));
  ASSERT_EQ(path.status().state, path_state::running);
  try {
    path.configure(x4step::path_config{}.probe_input(2, false));
    ADD_FAILURE() << "the probe input changed under a running path";
  } catch (const x4step::error &e) {
    EXPECT_EQ(e.code(), x4step::make_error_code(x4step::errc::is_active));
  }
  path.configure(x4step::path_config{}.probe_input(kProbeInput, false).keys_abort(true));  // as it is
  EXPECT_TRUE(path.config().keys_abort());
  path.abort();
}

// The module's errno for a record with both probe flags, or none and no input.
TEST_F(SimProbe, RecordsGetTheModulesErrno) {
  auto io = x4step::sim::open("sim", O_RDWR);
  x4step_segment r{};
  r.steps[2] = 100;
  r.length = 100;
  r.v_max = 1000;
  r.accel = 10000;
  r.flags = X4STEP_SEG_PROBE_TOWARD;
  errno = 0;
  EXPECT_EQ(io->write(&r, sizeof r), -1);
  EXPECT_EQ(errno, EINVAL) << "no probe input";
  x4step_path_config cfg{};
  cfg.probe = kProbeInput;
  cfg.reserved = 1;
  EXPECT_EQ(io->ioctl(X4STEP_SET_PATH_CONFIG, &cfg), -1);
  EXPECT_EQ(errno, EINVAL);
  cfg.reserved = 0;
  ASSERT_EQ(io->ioctl(X4STEP_SET_PATH_CONFIG, &cfg), 0);
  r.flags = X4STEP_SEG_PROBE_TOWARD | X4STEP_SEG_PROBE_AWAY;
  EXPECT_EQ(io->write(&r, sizeof r), -1);
  EXPECT_EQ(errno, EINVAL) << "both";
  x4step_probe pr{};
  ASSERT_EQ(io->ioctl(X4STEP_GET_PROBE, &pr), 0);
  EXPECT_EQ(pr.input, unsigned(kProbeInput));
  EXPECT_EQ(pr.runs, 0u);
}

// The C API: X4PathProbeInput, X4PathAppendProbe, X4PathProbe.
TEST_F(SimProbe, CApiProbes) {
  setenv("X4STEP_SIM", "1", 1);
  ASSERT_EQ(X4Init(LPT1), X4NoErr);
  const X4Segment s{{0, 0, 3000, 0}, 3000, 2000, 0, 100000, 5};
  EXPECT_EQ(X4PathAppendProbe(&s, X4PROBE_TOWARD), X4ErrParamFail) << "no probe input";
  EXPECT_EQ(X4PathProbeInput(6, 0), X4ErrParamFail);
  ASSERT_EQ(X4PathProbeInput(kProbeInput, 0), X4NoErr);
  EXPECT_EQ(X4PathAppendProbe(&s, 3), X4ErrParamFail);
  ASSERT_EQ(X4PathAppendProbe(&s, X4PROBE_TOWARD), X4NoErr);
  int state = X4PATH_RUN;
  long queued = 1;
  while (state != X4PATH_IDLE || queued) ASSERT_EQ(X4PathState(&state, &queued, nullptr), X4NoErr);
  int tripped = 0;
  long pos[4] = {-1, -1, -1, -1};
  unsigned long long tag = 0;
  ASSERT_EQ(X4PathProbe(&tripped, pos, &tag), X4NoErr);
  EXPECT_EQ(tripped, 1);
  EXPECT_EQ(pos[2], kAt);
  EXPECT_EQ(pos[0], 0);
  EXPECT_EQ(tag, 5u);
  EXPECT_EQ(X4PathAppend(&s, 1), X4ErrNotActive) << "flushed";
  EXPECT_EQ(X4PathClear(), X4NoErr);
  EXPECT_EQ(X4PathProbe(nullptr, nullptr, nullptr), X4NoErr);
  EXPECT_EQ(X4ReInit(), X4NoErr);
}

}  // namespace
