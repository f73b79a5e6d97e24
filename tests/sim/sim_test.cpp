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
#include "sim_env.hpp"
#include "sim_writes.hpp"
#include "x4step.h"
#include "x4step.hpp"

using namespace std::chrono_literals;
using x4step::axis;
using x4step::controller;

namespace {

class Sim : public SimEnv {
 protected:
  void TearDown() override {
    SimEnv::TearDown();
    if (!machine_file_.empty()) ::unlink(machine_file_.c_str());
  }
  // Writes a machine file and names it in X4STEP_SIM_MACHINE.
  void Machine(const std::string &text) {
    machine_file_ = ::testing::TempDir() + "sim_test.machine";
    std::ofstream(machine_file_) << text;
    setenv("X4STEP_SIM_MACHINE", machine_file_.c_str(), 1);
  }
  std::string machine_file_;
};

// Axis 1 of a machine: REF on pin 10 (input 4) NO, active at -300 and
// below; both limits on pin 11 (input 5), NC, in parallel; it stands at 200.
const char *const kAxis1 =
    "# axis 1\n"
    "ref 1 below -300 pin10 no\n"
    "e- 1 -1000 pin11 nc   # shared input\n"
    "e+ 1 5000 11 nc\n"
    "position 1 200\n";

x4step::switches Axis1Switches() {
  x4step::switches sw;
  sw.ref[0] = 4;
  sw.plus[0] = 5;
  sw.minus[0] = 5;
  sw.nc = 1u << 4;
  return sw;
}

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

// A name that starts with "sim" is a simulated port's: a misspelt one is
// refused as such (not opened as a file here); X4STEP_SIM takes 1 or 0,
// not a port number.
TEST_F(Sim, MisspeltNamesAndOtherX4StepSimValuesAreRefused) {
  for (const char *name : {"simx", "sim0", "sim:", "sim:4", "sim:00", "sim1:0"}) {
    try {
      controller c(name);
      ADD_FAILURE() << "opened " << name;
    } catch (const x4step::error &e) {
      EXPECT_EQ(e.code(), x4step::errc::lpt_not_found);
      EXPECT_NE(std::string(e.what()).find(std::string(name) +
                                           ": no such simulated port: use sim (= sim:0) or sim:0 .. sim:3"),
                std::string::npos)
          << e.what();
    }
    EXPECT_THROW(x4step::monitor m(name), x4step::error);
  }
  for (const char *v : {"2", "yes", "true", " 1"}) {
    setenv("X4STEP_SIM", v, 1);
    try {
      controller c(1);
      ADD_FAILURE() << "X4STEP_SIM=" << v << " taken";
    } catch (const x4step::error &e) {
      EXPECT_EQ(e.code(), x4step::errc::lpt_not_found);
      EXPECT_NE(std::string(e.what()).find(std::string("X4STEP_SIM=") + v + ": use 1"), std::string::npos)
          << e.what();
    }
    EXPECT_EQ(X4Init(LPT1), X4ErrLPTNotFound);
  }
  EXPECT_FALSE(x4step::sim::port::find(0));  // nothing simulated
  setenv("X4STEP_SIM", "1", 1);
  ASSERT_EQ(X4Init(LPT2), X4NoErr);
  EXPECT_TRUE(x4step::sim::port::find(1));
  EXPECT_EQ(X4ReInit(), X4NoErr);
}

// A refused setting simulates nothing: not even the VCD file is made.
TEST_F(Sim, RefusedSettingsWriteNoVcd) {
  const std::string vcd = ::testing::TempDir() + "sim_test_refused.vcd";
  ::unlink(vcd.c_str());
  setenv("X4STEP_SIM_VCD", vcd.c_str(), 1);
  const struct {
    const char *variable, *value;
  } bad[] = {{"X4STEP_SIM_TIME", "fast"}, {"X4STEP_SIM_KEYS", "3:esc"}, {"X4STEP_SIM_INPUTS", "soon"}};
  for (const auto &b : bad) {
    setenv(b.variable, b.value, 1);
    EXPECT_THROW(controller("sim"), x4step::error) << b.variable;
    unsetenv(b.variable);
  }
  setenv("X4STEP_SIM_TIME", "virtual", 1);
  Machine("e+ 1 100 pin11 nc\ne- 1 500 pin12 nc\n");
  EXPECT_THROW(controller("sim"), x4step::error);
  EXPECT_THROW(controller("sim:4"), x4step::error);
  EXPECT_NE(::access(vcd.c_str(), F_OK), 0) << vcd << " was written";
  EXPECT_FALSE(x4step::sim::port::find(0));
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

// Virtual time: a 4-axis 20 kHz move of 10 s simulates in well under a
// second (some 30 ms). Host time, so the bound is the one a loaded host
// cannot break: the motion's own 10 s, which a run in real time cannot beat.
TEST_F(Sim, VirtualTimeIsFast) {
  controller c("sim");
  c.load({{200000, 150000, 100000, 50000}, 20000, 0ms});
  const auto t = std::chrono::steady_clock::now();
  c.start();
  c.wait();
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  EXPECT_EQ(c.steps(axis(4)), 50000);
  std::printf("4 axes, 20 kHz, 10 s of motion simulated in %.3f s\n", s);
  EXPECT_LT(s, 10.0);
}

// Real time: the move takes its time. Host time: only the lower bound,
// which no load can break (a late timer only stretches the move); 30 s
// only bounds a move that never ends.
TEST_F(Sim, RealTimeTakesTheMovesTime) {
  setenv("X4STEP_SIM_TIME", "real", 1);
  controller c("sim");
  c.load({{1000, 0, 0, 0}, 10000, 0ms});  // 100 ms
  const auto t = std::chrono::steady_clock::now();
  c.start();
  EXPECT_TRUE(c.get_status().active);
  ASSERT_TRUE(c.wait(30s));
  const auto took = std::chrono::steady_clock::now() - t;
  EXPECT_GE(took, 99ms);
  EXPECT_EQ(c.steps(axis(1)), 1000);
}

// The public clock: a simulated port in virtual time has its own, which
// sleep_for() moves at once, running the move due meanwhile; the steady
// clock otherwise (only the lower bound of host time is checked).
TEST_F(Sim, PortClockAndSleepingOnIt) {
  controller c("sim");
  EXPECT_FALSE(c.clock_runs());
  c.load({{1000, 0, 0, 0}, 1000, 0ms});  // 1 s
  c.start();
  const auto t0 = c.now();
  c.sleep_for(500ms);
  EXPECT_GE(c.now() - t0, 500ms);
  EXPECT_TRUE(c.get_status().active);
  c.sleep_for(600ms);
  EXPECT_FALSE(c.get_status().active);
  EXPECT_EQ(c.steps(axis(1)), 1000);
  EXPECT_LT(c.now() - t0, 1200ms);  // its own clock: no host time in it

  setenv("X4STEP_SIM_TIME", "real", 1);
  controller r("sim:1");
  EXPECT_TRUE(r.clock_runs());
  const auto t1 = std::chrono::steady_clock::now();
  r.sleep_for(20ms);
  EXPECT_GE(std::chrono::steady_clock::now() - t1, 20ms);
}

// Whether a name or X4STEP_SIM asks for the simulator: one rule, public.
TEST_F(Sim, PublicNamesAndEnvironment) {
  for (const char *name : {"sim", "sim:3", "sim0", "sim:7", "simx"})
    EXPECT_TRUE(x4step::is_sim_name(name)) << name;
  for (const char *name : {"/dev/x4step0", "./sim0", "x4sim", ""})
    EXPECT_FALSE(x4step::is_sim_name(name)) << name;
  EXPECT_FALSE(x4step::env_wants_sim());
  for (const char *v : {"", "0"}) {
    setenv("X4STEP_SIM", v, 1);
    EXPECT_FALSE(x4step::env_wants_sim()) << v;
  }
  setenv("X4STEP_SIM", "1", 1);
  EXPECT_TRUE(x4step::env_wants_sim());
  for (const char *v : {"2", "yes", "10"}) {
    setenv("X4STEP_SIM", v, 1);
    try {
      x4step::env_wants_sim();
      ADD_FAILURE() << v;
    } catch (const x4step::error &e) {
      EXPECT_EQ(e.code(), x4step::errc::lpt_not_found);
      EXPECT_NE(std::string(e.what()).find(std::string("X4STEP_SIM=") + v + ": use 1"), std::string::npos)
          << e.what();
    }
  }
}

// ---- the machine model (X4STEP_SIM_MACHINE, X4STEP_SIM_INPUTS) ----

// Homing: phase 1 runs onto REF (active at -300 and below) and stops on
// the step that reaches it; phase 2 leaves it and stops where it changes
// (-299), which becomes coordinate 0, synchronized (X4STEP_HOME).
TEST_F(Sim, HomingFindsRefAndEndsAtZero) {
  Machine(kAxis1);
  controller c("sim");
  auto p = x4step::sim::port::find(0);
  c.set_switches(Axis1Switches());
  x4step::monitor m("sim");
  c.home(axis(1), x4step::homing{}.phase1_speed(-2000).phase2_speed(200).max_travel(5000));
  ASSERT_TRUE(c.wait());
  EXPECT_EQ(p->machine_positions()[0], -299);
  const x4step::axis_status a = c.get_axis(axis(1));
  EXPECT_EQ(a.position, 0);
  EXPECT_TRUE(a.synced);
  EXPECT_EQ(a.error, 0u);
  bool homed = false;
  while (auto e = m.read_event(0ms))
    homed |= e->type == x4step::event_type::move_ended && e->how == static_cast<unsigned>(X4STEP_END_HOMED);
  EXPECT_TRUE(homed);
  c.move_to(axis(1), 99);  // the coordinate is the machine's, shifted
  ASSERT_TRUE(c.wait());
  EXPECT_EQ(p->machine_positions()[0], -200);
}

// A limit stops the move before the step after the one that reached it:
// the machine stands on E+ (5000), the axis reports limit_pos.
TEST_F(Sim, LimitSwitchStopsOnTheStepThatReachesIt) {
  Machine(kAxis1);
  controller c("sim");
  auto p = x4step::sim::port::find(0);
  c.set_switches(Axis1Switches());
  c.set_profile(axis(1), x4step::profile{}.top_speed(4000).accel(40000).decel(40000));
  c.move_by(axis(1), 10000);
  ASSERT_TRUE(c.wait());
  EXPECT_EQ(p->machine_positions()[0], 5000);
  const x4step::axis_status a = c.get_axis(axis(1));
  EXPECT_EQ(a.position, 4800);
  EXPECT_EQ(a.error, x4step::axis_error::limit_pos);
  EXPECT_EQ(c.get_axes().switches_active, 1u << 4);
  // Backing off the limit is allowed and releases it.
  c.move_by(axis(1), -100);
  ASSERT_TRUE(c.wait());
  EXPECT_EQ(p->machine_positions()[0], 4900);
  EXPECT_EQ(c.get_axes().switches_active, 0u);
}

// Scripted inputs: levels from their time on, read by X4GetIn.
TEST_F(Sim, ScriptedInputsChangeAtTheirTimes) {
  Machine("input 10 pin15=1 pin13=1\ninput 30 15=0\n");
  setenv("X4STEP_SIM_INPUTS", "20:pin12=1,40.5:pin12=0", 1);
  controller c("sim");
  auto p = x4step::sim::port::find(0);
  EXPECT_EQ(c.inputs(), 0u);
  p->run_until(10000000);
  EXPECT_EQ(c.inputs(), 0x3u);
  p->run_until(20000000);
  EXPECT_EQ(c.inputs(), 0x7u);
  p->run_until(30000000);
  EXPECT_EQ(c.inputs(), 0x6u);
  p->run_until(40499999);
  EXPECT_EQ(c.inputs(), 0x6u);
  p->run_until(40500000);
  EXPECT_EQ(c.inputs(), 0x2u);
}

// Every layout error names the file or variable, the line or item, and
// what to fix; nothing is simulated.
// The simulated machine's switches, public, as set_switches() takes them.
TEST_F(Sim, PublicMachineSwitches) {
  EXPECT_FALSE(x4step::sim_machine_switches());
  Machine("position 1 200\n");
  EXPECT_FALSE(x4step::sim_machine_switches());  // a machine without switches
  Machine(kAxis1);
  const auto sw = x4step::sim_machine_switches();
  ASSERT_TRUE(sw);
  const x4step::switches want = Axis1Switches();
  EXPECT_EQ(sw->ref, want.ref);
  EXPECT_EQ(sw->plus, want.plus);
  EXPECT_EQ(sw->minus, want.minus);
  EXPECT_EQ(sw->nc, want.nc);
  Machine("ref 9 below 0 pin10 no\n");
  EXPECT_THROW(x4step::sim_machine_switches(), x4step::error);
}

TEST_F(Sim, MachineLayoutErrorsSayWhereAndWhatToFix) {
  const struct {
    const char *file;
    const char *says;
  } bad[] = {
      {"ref 1 below 0 pin10 no\ne+ 1 500 pin10 nc\n", ":2: pin 10 has a no switch already (line 1)"},
      {"ref 1 below 0 pin2 no\n",
       ":1: 'pin2' is not an input pin: the inputs are pins 10, 11, 12, 13 and 15"},
      {"e- 1 -100 pin11 nc\ne+ 1 100 pin11 nc\nref 1 above 200 pin10 no\n",
       ":3: axis 1: REF at 200 lies outside E-..E+ (line 2)"},
      {"\nref 2 above -500 pin10 no\ne- 2 -400 pin11 nc\n",
       ":3: axis 2: REF at -500 lies outside E-..E+ (line 2)"},
      {"e+ 3 100 pin11 no\ne- 3 100 pin11 no\n", ":2: axis 3: E- at 100 is not below E+ at 100 (line 1)"},
      {"e+ 1 100 pin11 no\ne+ 1 200 pin12 no\n",
       ":2: axis 1 has its E+ switch already (line 1): one per axis"},
      {"ref 5 below 0 pin10 no\n", ":1: axis '5': use 1, 2, 3 or 4"},
      {"ref 1 left 0 pin10 no\n", ":1: REF side 'left': use below"},
      {"probe 3 left 0 pin12 no\n", ":1: probe side 'left': use below"},
      {"probe 3 above 0 pin12\n",
       ":1: write a probe switch as: probe AXIS below|above AT PIN no|nc [hyst STEPS]"},
      {"probe 3 above 0 pin12 no\nprobe 3 below -9 pin13 no\n",
       ":2: axis 3 has its probe switch already (line 1)"},
      {"e+ 1 100 pin11 open\n", ":1: polarity 'open': use no"},
      {"e+ 1 1e3 pin11 no\n", ":1: position '1e3' is not a whole number of steps"},
      {"e+ 1 100 pin11 no hyst -1\n", ":1: hysteresis -1: use 0 or more steps"},
      {"e+ 1 100 pin11\n", ":1: write a limit switch as: e+ AXIS AT PIN no|nc [hyst STEPS]"},
      {"limit 1 100\n", ":1: 'limit' is not a machine line"},
      {"e+ 1 100 pin11 no\ninput 5 pin11=1\n", ":2: pin 11 is driven by a switch"},
      {"input 5 pin15=1\ne+ 1 100 pin15 no\n", ":2: pin 15 is set by the input script"},
      {"input -5 pin15=1\n", ":1: time '-5' is not a time in ms"},
      {"input 5 pin15=2\n", ":1: 'pin15=2': set an input as PIN=0 or PIN=1"},
  };
  for (const auto &b : bad) {
    Machine(b.file);
    try {
      controller c("sim");
      ADD_FAILURE() << "accepted: " << b.file;
    } catch (const x4step::error &e) {
      EXPECT_EQ(e.code(), x4step::errc::lpt_not_found);
      EXPECT_NE(std::string(e.what()).find(machine_file_ + b.says), std::string::npos)
          << "wanted \"" << b.says << "\" in: " << e.what();
    }
    EXPECT_FALSE(x4step::sim::port::find(0));
  }
  setenv("X4STEP_SIM_MACHINE", "/nonexistent/machine", 1);
  EXPECT_THROW(controller("sim"), x4step::error);
  unsetenv("X4STEP_SIM_MACHINE");
  for (const char *spec : {"20pin12=1", "20:pin12", "x:pin12=1", "20:pin9=1"}) {
    setenv("X4STEP_SIM_INPUTS", spec, 1);
    try {
      controller c("sim");
      ADD_FAILURE() << "accepted: " << spec;
    } catch (const x4step::error &e) {
      EXPECT_NE(std::string(e.what()).find(std::string("X4STEP_SIM_INPUTS item 1 '") + spec + "': "),
                std::string::npos)
          << e.what();
    }
  }
  EXPECT_FALSE(x4step::sim::port::find(0));
}
