// SPDX-License-Identifier: GPL-2.0
// The simulated port (lib/sim): the library's requests on "sim" run the
// module's engine; its pin writes are the engine's, edge for edge, and
// the manual's C API works on it unchanged (X4STEP_SIM=1).
#include <gtest/gtest.h>
#include <linux/x4step.h>
#include <stdlib.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "engine_ref.h"
#include "sim/port.hpp"
#include "x4step.h"
#include "x4step.hpp"

using namespace std::chrono_literals;
using x4step::axis;
using x4step::controller;

namespace {

class Sim : public ::testing::Test {
 protected:
  void SetUp() override {
    setenv("X4STEP_SIM_TIME", "virtual", 1);
    unsetenv("X4STEP_SIM_VCD");
    unsetenv("X4STEP_SIM");
  }
  void TearDown() override {
    unsetenv("X4STEP_SIM_TIME");
    unsetenv("X4STEP_SIM_VCD");
    unsetenv("X4STEP_SIM");
  }
};

// The pin changes the engine itself makes for a move started at t0, each
// event fired at its due time: what the module's timer does when on time.
std::vector<x4step::sim::pin_write> reference(const x4_move &m, uint64_t t0) {
  x4_engine e;
  const x4_timing t{0, 0, X4_DIR_SETUP_NS, 0};
  x4_engine_init(&e);
  x4_engine_configure(&e, &t, X4_MODE_CLOCK_DIR);
  e.budget = X4_WRITE_BUDGET;
  EXPECT_EQ(x4_engine_load(&e, &m), X4_OK);
  EXPECT_EQ(x4_engine_start(&e, t0), X4_OK);
  x4test::Recording rec;
  x4test::record(e, rec);
  std::vector<x4step::sim::pin_write> out;
  uint8_t data = 0, ctl = 0;
  for (const x4_event &ev : rec.events) {
    if (ev.data == data && ev.ctl == ctl) continue;
    out.push_back({ev.t_ns, ev.data, ev.ctl});
    data = ev.data;
    ctl = ev.ctl;
  }
  return out;
}

std::vector<x4step::sim::pin_write> after(const std::vector<x4step::sim::pin_write> &w, uint64_t t0) {
  std::vector<x4step::sim::pin_write> out;
  for (const auto &p : w)
    if (p.t_ns >= t0) out.push_back(p);
  return out;
}

long rises(const std::vector<x4step::sim::pin_write> &w, int bit) {
  long n = 0;
  uint8_t last = 0;
  for (const auto &p : w) {
    n += (p.data & ~last) >> bit & 1;
    last = p.data;
  }
  return n;
}

}  // namespace

TEST_F(Sim, MoveEdgesAreTheEnginesExactly) {
  controller c("sim");
  auto p = x4step::sim::port::find(0);
  ASSERT_TRUE(p);
  p->record(true);
  c.load({{3000, -1500, 700, 1}, 20000, 100ms});
  const uint64_t t0 = p->engine_now();
  c.start();
  ASSERT_TRUE(c.wait());
  const auto sim = after(p->writes(), t0);
  const auto ref = reference(x4test::Move(3000, -1500, 700, 1, 20000, 100), t0);
  ASSERT_EQ(sim.size(), ref.size());
  for (size_t i = 0; i < ref.size(); i++) {
    ASSERT_EQ(sim[i].t_ns, ref[i].t_ns) << "write " << i;
    ASSERT_EQ(sim[i].data, ref[i].data) << "write " << i;
    ASSERT_EQ(sim[i].ctl, ref[i].ctl) << "write " << i;
  }
  EXPECT_EQ(rises(sim, 1), 3000);
  EXPECT_EQ(rises(sim, 3), 1500);
  EXPECT_EQ(rises(sim, 5), 700);
  EXPECT_EQ(rises(sim, 7), 1);
  const x4step::status s = c.get_status();
  EXPECT_EQ(s.steps[0], 3000);
  EXPECT_EQ(s.steps[1], -1500);
  EXPECT_FALSE(s.active);
}

// Known figures: directions 100 us before the first step, a 20 kHz clock
// without ramp is 50 us per step, 25 us high.
TEST_F(Sim, TwentyKilohertzWithoutRampKnownTimes) {
  controller c("sim");
  auto p = x4step::sim::port::find(0);
  p->record(true);
  c.load({{10, 0, 0, 0}, 20000, 0ms});
  const uint64_t t0 = p->engine_now();
  c.start();
  c.wait();
  std::vector<uint64_t> up, down;
  uint8_t last = 0;
  for (const auto &w : after(p->writes(), t0)) {
    if ((w.data & ~last) & 2) up.push_back(w.t_ns - t0);
    if ((~w.data & last) & 2) down.push_back(w.t_ns - t0);
    last = w.data;
  }
  ASSERT_EQ(up.size(), 10u);
  ASSERT_EQ(down.size(), 10u);
  for (size_t n = 0; n < 10; n++) {
    EXPECT_EQ(up[n], 100000u + 50000u * n);
    EXPECT_EQ(down[n], 125000u + 50000u * n);
  }
}

TEST_F(Sim, ChecksAndErrorsAreTheModules) {
  controller c("sim");
  c.load({{100, 0, 0, 0}, 1000, 0ms});
  EXPECT_THROW(c.load({{100, 0, 0, 0}, 1000, 0ms}), x4step::error);  // is_loaded
  try {
    c.load({{100, 0, 0, 0}, 1000, 0ms});
  } catch (const x4step::error &e) {
    EXPECT_EQ(e.code(), x4step::errc::is_loaded);
  }
  c.start();
  try {
    c.move_endless(axis(1), x4step::direction::positive, 1000, 0ms);
    FAIL();
  } catch (const x4step::error &e) {
    EXPECT_EQ(e.code(), x4step::errc::is_active);
  }
  c.stop();
  try {
    c.brake();
    FAIL();
  } catch (const x4step::error &e) {
    EXPECT_EQ(e.code(), x4step::errc::not_active);
  }
  try {
    controller second("sim");
    FAIL();
  } catch (const x4step::error &e) {
    EXPECT_EQ(e.code(), x4step::errc::lpt_not_found);
    EXPECT_NE(std::string(e.what()).find("port busy"), std::string::npos) << e.what();
  }
}

TEST_F(Sim, EventsOfMovesBrakesAndKeys) {
  controller c("sim");
  x4step::monitor m("sim");
  c.set_brake_codes({57});
  c.move_endless(axis(1), x4step::direction::negative, 5000, 200ms);
  EXPECT_FALSE(c.wait(100ms));
  ASSERT_TRUE(x4step::sim::port::find(0)->key(57));
  ASSERT_TRUE(c.wait(1s));
  EXPECT_EQ(c.get_status().last_brake_code, 57);
  EXPECT_LT(c.steps(axis(1)), 0);
  std::vector<x4step::event> seen;
  while (auto e = m.read_event(0ms)) seen.push_back(*e);
  ASSERT_EQ(seen.size(), 3u);
  EXPECT_EQ(seen[0].type, x4step::event_type::move_started);
  EXPECT_EQ(seen[1].type, x4step::event_type::brake);
  EXPECT_EQ(seen[1].value, 57u);
  EXPECT_EQ(seen[2].type, x4step::event_type::move_ended);
  EXPECT_EQ(seen[2].how, static_cast<unsigned>(X4STEP_END_BRAKED));
  EXPECT_EQ(seen[2].position[0], c.steps(axis(1)));
}

TEST_F(Sim, InputsAndOutputs) {
  controller c("sim");
  auto p = x4step::sim::port::find(0);
  EXPECT_EQ(c.inputs(), 0u);
  p->set_inputs(0x15);
  EXPECT_EQ(c.inputs(), 0x15u);
  p->record(true);
  c.set_output(x4step::signal::two, true);
  EXPECT_EQ(c.get_status().outputs & 0x3, 0x2u);
  const auto w = p->writes();  // the output is a pin write of its own
  ASSERT_EQ(w.size(), 1u);
  EXPECT_EQ(w[0].ctl, X4_CTL_SIGNAL2);
}

// The manual's C API, unchanged, on the simulator: X4STEP_SIM=1.
TEST_F(Sim, ManualProgramRunsWithTheEnvironmentVariable) {
  setenv("X4STEP_SIM", "1", 1);
  ASSERT_EQ(X4Init(LPT1), X4NoErr);
  ASSERT_EQ(X4Load(2000, 1000, 0, 0, 2000, 100), X4NoErr);
  ASSERT_EQ(X4Start(), X4NoErr);
  while (X4GetState()) {
  }
  EXPECT_EQ(X4GetSteps(1), 2000);
  EXPECT_EQ(X4GetSteps(2), 1000);
  EXPECT_GE(X4GetTimer(), 1000);  // 2000 steps at 2 kHz: more than 1 s, virtual
  EXPECT_EQ(X4ReInit(), X4NoErr);
}

TEST_F(Sim, BadNamesAndSettingsSayWhatToFix) {
  try {
    controller c("sim:7");
    FAIL();
  } catch (const x4step::error &e) {
    EXPECT_NE(std::string(e.what()).find("sim:0 .. sim:3"), std::string::npos) << e.what();
  }
  setenv("X4STEP_SIM_TIME", "fast", 1);
  try {
    controller c("sim");
    FAIL();
  } catch (const x4step::error &e) {
    EXPECT_NE(std::string(e.what()).find("X4STEP_SIM_TIME=fast"), std::string::npos) << e.what();
  }
  setenv("X4STEP_SIM_TIME", "virtual", 1);
  setenv("X4STEP_SIM_VCD", "/nonexistent/dir/x.vcd", 1);
  try {
    controller c("sim");
    FAIL();
  } catch (const x4step::error &e) {
    EXPECT_NE(std::string(e.what()).find("X4STEP_SIM_VCD=/nonexistent/dir/x.vcd"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(x4step::sim::port::find(0));  // nothing simulated
  setenv("X4STEP_SIM", "1", 1);
  EXPECT_EQ(X4Init(LPT1), X4ErrLPTNotFound);
}

TEST_F(Sim, VcdHasTheTraceSignalNamesAndEveryEdge) {
  const std::string path = ::testing::TempDir() + "sim_test.vcd";
  setenv("X4STEP_SIM_VCD", path.c_str(), 1);
  {
    controller c("sim");
    c.load({{500, 250, 0, 0}, 10000, 20ms});
    c.start();
    c.wait();
  }
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  const std::string vcd = s.str();
  for (const char *name : {"pin01_signal1", "pin02_dir1", "pin03_clk1", "pin05_clk2", "pin09_clk4",
                           "pin14_signal2", "pin16_boost", "pin17_aktiv"})
    EXPECT_NE(vcd.find(std::string(" ") + name + " $end"), std::string::npos) << name;
  // pin03_clk1 is the third signal: '#'.
  std::istringstream lines(vcd.substr(vcd.find("$enddefinitions")));
  long clk1 = 0, clk2 = 0;
  for (std::string l; std::getline(lines, l);) {
    clk1 += l == "1#";
    clk2 += l == "1%";
  }
  EXPECT_EQ(clk1, 500);
  EXPECT_EQ(clk2, 250);
  ::unlink(path.c_str());
}

// Virtual time: a 4-axis 20 kHz move of 10 s simulates in well under a second.
TEST_F(Sim, VirtualTimeIsFast) {
  controller c("sim");
  c.load({{200000, 150000, 100000, 50000}, 20000, 0ms});
  const auto t = std::chrono::steady_clock::now();
  c.start();
  c.wait();
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  EXPECT_EQ(c.steps(axis(4)), 50000);
  std::printf("4 axes, 20 kHz, 10 s of motion simulated in %.3f s\n", s);
  EXPECT_LT(s, 1.0);
}

// Real time: the move takes its time.
TEST_F(Sim, RealTimeTakesTheMovesTime) {
  setenv("X4STEP_SIM_TIME", "real", 1);
  controller c("sim");
  c.load({{1000, 0, 0, 0}, 10000, 0ms});  // 100 ms
  const auto t = std::chrono::steady_clock::now();
  c.start();
  EXPECT_TRUE(c.get_status().active);
  ASSERT_TRUE(c.wait(2s));
  const auto took = std::chrono::steady_clock::now() - t;
  EXPECT_GE(took, 99ms);
  EXPECT_LT(took, 1s);
  EXPECT_EQ(c.steps(axis(1)), 1000);
}
