// SPDX-License-Identifier: GPL-2.0
// Brake keys on the simulated port: scripted (X4STEP_SIM_KEYS) at their
// times, in virtual and real time, braking moves and holding or aborting
// paths as the module's key handler does; the terminal's bytes as the
// module's default key map codes them.
#include <gtest/gtest.h>
#include <linux/x4step.h>
#include <stdlib.h>

#include <chrono>
#include <string>
#include <vector>

#include "sim/options.hpp"
#include "sim/port.hpp"
#include "sim/terminal.hpp"
#include "sim_env.hpp"
#include "x4_keys.h"
#include "x4step.hpp"
#include "x4step_path.hpp"

using namespace std::chrono_literals;
using x4step::axis;
using x4step::controller;

namespace {

class SimKeys : public SimEnv {};

std::vector<x4step::segment> line(int n) {
  std::vector<x4step::segment> s(n);
  for (int i = 0; i < n; i++)
    s[i].steps(axis(1), 100).length(100).top_speed(5000).accel(20000).entry_speed(i ? 5000 : 0);
  return s;
}

}  // namespace

TEST_F(SimKeys, ScriptedEscBrakesAMoveAtItsTime) {
  setenv("X4STEP_SIM_KEYS", "300ms:esc", 1);
  controller c("sim");
  x4step::monitor m("sim");
  c.move_endless(axis(1), x4step::direction::positive, 5000, 0ms);
  ASSERT_TRUE(c.wait(5s));
  const x4step::status s = c.get_status();
  EXPECT_EQ(s.last_brake_code, 1);
  // 5 kHz from about 0 to 300 ms, then its brake (no ramp: at once).
  EXPECT_GT(c.steps(axis(1)), 1400);
  EXPECT_LT(c.steps(axis(1)), 1600);
  std::vector<x4step::event> ev;
  while (auto e = m.read_event(0ms)) ev.push_back(*e);
  ASSERT_EQ(ev.size(), 3u);
  EXPECT_EQ(ev[1].type, x4step::event_type::brake);
  EXPECT_EQ(ev[1].how, static_cast<unsigned>(X4STEP_SRC_KEY));
  EXPECT_EQ(ev[1].value, 1u);
  EXPECT_EQ(ev[2].how, static_cast<unsigned>(X4STEP_END_BRAKED));
}

// A key that is no brake key, or one while nothing runs, brakes nothing.
TEST_F(SimKeys, OnlyBrakeKeysWhileAMoveRuns) {
  setenv("X4STEP_SIM_KEYS", "100ms:esc,300ms:a,400ms:space", 1);
  controller c("sim");
  c.set_brake_codes({57});
  auto p = x4step::sim::port::find(0);
  p->run_until(200000000);  // the ESC at 100 ms: nothing ran
  c.move_endless(axis(1), x4step::direction::positive, 1000, 0ms);
  ASSERT_TRUE(c.wait(5s));
  EXPECT_EQ(c.get_status().last_brake_code, 57);  // not 'a' (30)
  EXPECT_EQ(c.steps(axis(1)), 200);               // 200 ms at 1 kHz
}

TEST_F(SimKeys, ScriptedKeyHoldsAPathOrAbortsIt) {
  setenv("X4STEP_SIM_KEYS", "1s:space", 1);
  {
    controller c("sim");
    c.set_brake_codes({57});
    x4step::path path(c);
    path.append(line(100));
    ASSERT_TRUE(path.wait(10s));
    const x4step::path_status s = path.status();
    EXPECT_EQ(s.state, x4step::path_state::held);
    EXPECT_GT(s.queued, 0u);
    EXPECT_EQ(c.get_status().last_brake_code, 57);
    path.resume();
    ASSERT_TRUE(path.wait(10s));
    EXPECT_EQ(path.status().done, 100u);
  }
  controller c("sim");
  c.set_brake_codes({57});
  x4step::path path(c);
  path.configure(x4step::path_config().keys_abort(true));
  path.append(line(100));
  ASSERT_TRUE(path.wait(10s));
  const x4step::path_status s = path.status();
  EXPECT_EQ(s.state, x4step::path_state::idle);
  EXPECT_EQ(s.queued, 0u);
  EXPECT_LT(s.done, 100u);
  EXPECT_THROW(path.append(line(1)), x4step::error);  // flushed: clear() first
}

// Issue 28, item 9: with X4STEP_PATH_KEYS_ABORT a brake key aborts a
// path that stands held too (held by PATH_CTL HOLD), and the event stream
// tells its end.
TEST_F(SimKeys, KeyAbortsAHeldPath) {
  controller c("sim");
  x4step::monitor m("sim");
  c.set_brake_codes({57});
  auto p = x4step::sim::port::find(0);
  x4step::path path(c);
  path.configure(x4step::path_config().keys_abort(true));
  path.append(line(100));
  p->run_until(p->engine_now() + 500000000u);
  path.hold();
  ASSERT_TRUE(path.wait(10s));
  ASSERT_EQ(path.status().state, x4step::path_state::held);
  while (m.read_event(0ms)) {
  }
  EXPECT_TRUE(p->key(57));
  const x4step::path_status s = path.status();
  EXPECT_EQ(s.state, x4step::path_state::idle);
  EXPECT_EQ(s.queued, 0u);
  EXPECT_EQ(c.get_status().last_brake_code, 57);
  EXPECT_THROW(path.append(line(1)), x4step::error);  // flushed: clear() first
  std::vector<x4step::event> ev;
  while (auto e = m.read_event(0ms)) ev.push_back(*e);
  ASSERT_EQ(ev.size(), 1u);
  EXPECT_EQ(ev[0].type, x4step::event_type::move_ended);
  EXPECT_EQ(ev[0].how, unsigned(X4STEP_END_ABORTED));
}

// Without X4STEP_PATH_KEYS_ABORT a key leaves a held path held.
TEST_F(SimKeys, KeyLeavesAHeldPathHeld) {
  controller c("sim");
  c.set_brake_codes({57});
  auto p = x4step::sim::port::find(0);
  x4step::path path(c);
  path.append(line(100));
  p->run_until(p->engine_now() + 500000000u);
  path.hold();
  ASSERT_TRUE(path.wait(10s));
  EXPECT_FALSE(p->key(57));
  EXPECT_EQ(path.status().state, x4step::path_state::held);
}

// Issue 28, item 9: a write() to a held path kicks it after its chunk;
// the kick starts nothing, so the key's code stays the last brake code.
TEST_F(SimKeys, AppendToAHeldPathKeepsTheBrakeCode) {
  controller c("sim");
  c.set_brake_codes({57});
  auto p = x4step::sim::port::find(0);
  x4step::path path(c);
  path.append(line(100));
  p->run_until(p->engine_now() + 500000000u);
  EXPECT_TRUE(p->key(57));
  ASSERT_TRUE(path.wait(10s));
  ASSERT_EQ(path.status().state, x4step::path_state::held);
  ASSERT_EQ(c.get_status().last_brake_code, 57);
  path.append(line(20));
  EXPECT_EQ(path.status().state, x4step::path_state::held);
  EXPECT_EQ(c.get_status().last_brake_code, 57);
  path.resume();  // a start: it clears the code
  EXPECT_EQ(c.get_status().last_brake_code, 0);
}

TEST_F(SimKeys, RealTimeKeyComesAtItsTime) {
  setenv("X4STEP_SIM_TIME", "real", 1);
  setenv("X4STEP_SIM_KEYS", "150ms:esc", 1);
  controller c("sim");
  const auto t = std::chrono::steady_clock::now();
  c.move_endless(axis(1), x4step::direction::negative, 2000, 0ms);
  // Host time: not before the key's time; how much later a loaded host
  // makes it is not bounded (30 s: an endless move the key never ends).
  ASSERT_TRUE(c.wait(30s));
  const auto took = std::chrono::steady_clock::now() - t;
  EXPECT_GE(took, 140ms);
  EXPECT_EQ(c.get_status().last_brake_code, 1);
}

TEST_F(SimKeys, BadScriptsSayWhatToFix) {
  for (const char *bad : {"300:esc", "1s:nokey", "1s:256", "esc", "-1s:esc"}) {
    setenv("X4STEP_SIM_KEYS", bad, 1);
    try {
      controller c("sim");
      FAIL() << bad;
    } catch (const x4step::error &e) {
      EXPECT_NE(std::string(e.what()).find(std::string("X4STEP_SIM_KEYS: '") + bad + "'"), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("TIME:KEY"), std::string::npos) << e.what();
    }
  }
  EXPECT_FALSE(x4step::sim::port::find(0));  // nothing simulated
}

// The module's input handler codes Linux keys with x4_key_code()
// (engine/x4_keys.h); each named key gets the code its Linux key does.
TEST(SimKeyMap, ModuleCodesLinuxKeys) {
  EXPECT_EQ(x4_key_code(0), 0u);
  EXPECT_EQ(x4_key_code(KEY_ESC), 1u);
  EXPECT_EQ(x4_key_code(KEY_A), 30u);
  EXPECT_EQ(x4_key_code(KEY_F12), 88u);  // the last of the plain codes
  EXPECT_EQ(x4_key_code(KEY_KPENTER), 28u);
  EXPECT_EQ(x4_key_code(KEY_RIGHTCTRL), 29u);
  EXPECT_EQ(x4_key_code(KEY_HOME), 71u);
  EXPECT_EQ(x4_key_code(KEY_PAGEDOWN), 81u);
  EXPECT_EQ(x4_key_code(KEY_DELETE), 83u);
  EXPECT_EQ(x4_key_code(KEY_COMPOSE), 93u);
  EXPECT_EQ(x4_key_code(KEY_F13), 0u);  // no set-1 code
  EXPECT_EQ(x4_key_code(KEY_MUTE), 0u);
  for (const x4_key &k : x4_keys) {
    if (k.name) {
      EXPECT_EQ(x4step::sim::key_code(k.name), x4_key_code(k.key)) << k.name;
    }
  }
}

TEST(SimKeyMap, NamesAndCodesAreTheModulesDefaultMap) {
  using x4step::sim::key_code;
  EXPECT_EQ(key_code("esc"), 1u);
  EXPECT_EQ(key_code("1"), 2u);
  EXPECT_EQ(key_code("0"), 11u);
  EXPECT_EQ(key_code("q"), 16u);
  EXPECT_EQ(key_code("P"), 25u);
  EXPECT_EQ(key_code("enter"), 28u);
  EXPECT_EQ(key_code("a"), 30u);
  EXPECT_EQ(key_code("`"), 41u);
  EXPECT_EQ(key_code("\\"), 43u);
  EXPECT_EQ(key_code("z"), 44u);
  EXPECT_EQ(key_code("/"), 53u);
  EXPECT_EQ(key_code("space"), 57u);
  EXPECT_EQ(key_code("up"), 72u);
  EXPECT_EQ(key_code("delete"), 83u);
  EXPECT_EQ(key_code("f1"), 0u);
  const auto keys = x4step::sim::parse_keys("2s:57,1.5s:x");
  ASSERT_EQ(keys.size(), 3u);  // x: its press and release, in time order
  EXPECT_EQ(keys[0].t_ns, 1500000000u);
  EXPECT_EQ(keys[0].code, 45u);
  EXPECT_EQ(keys[1].code, 45u + 128);
  EXPECT_EQ(keys[2].t_ns, 2000000000u);
  EXPECT_EQ(keys[2].code, 57u);
}

TEST(SimKeyMap, TerminalBytesAreKeys) {
  using x4step::sim::terminal_keys;
  using v = std::vector<unsigned>;
  EXPECT_EQ(terminal_keys("\033"), v{1});
  EXPECT_EQ(terminal_keys("\033[A\033[B\033[C\033[D"), (v{72, 80, 77, 75}));
  EXPECT_EQ(terminal_keys("\033OH\033[F\033[5~\033[6~\033[2~\033[3~"), (v{71, 79, 73, 81, 82, 83}));
  EXPECT_EQ(terminal_keys("\033[1;5C"), v{77});  // Ctrl-Right: the key
  EXPECT_EQ(terminal_keys(" \r\n\t\x7f"), (v{57, 28, 28, 15, 14}));
  EXPECT_EQ(terminal_keys("aZ1-"), (v{30, 44, 2, 12}));
  EXPECT_EQ(terminal_keys("\x01"), v{});  // Ctrl-A: no key of the map
}
