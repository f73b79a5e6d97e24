// SPDX-License-Identifier: GPL-2.0
// Host tests of x4ctl: command line parsing, help texts, the TEST.EXE
// command language and its interpreter on a simulated port, formatting.
// No device is needed; the in-QEMU sessions are tests/qemu/x4ctl/x4ctl.sh.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <deque>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <tuple>
#include <utility>

#include "cli.hpp"
#include "commands.hpp"
#include "held_key.hpp"
#include "json.hpp"
#include "lang.hpp"
#include "motion.hpp"
#include "path.hpp"
#include "position.hpp"
#include "run_display.hpp"
#include "show.hpp"
#include "subcommand.hpp"
#include "term.hpp"
#include "toolpath_svg.hpp"

namespace x4ctl {
namespace {

using std::chrono::milliseconds;

config parse(std::vector<std::string> args) {
  args.insert(args.begin(), "x4ctl");
  return parse_args(args);
}

// The message of the usage_error that parsing args throws ("" if none).
std::string usage_message(std::vector<std::string> args) {
  try {
    parse(std::move(args));
  } catch (const usage_error &e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string &text, const std::string &part) {
  return text.find(part) != std::string::npos;
}

// ---- command line -----------------------------------------------------------------

TEST(Cli, NoCommandIsInteractiveOnLpt1) {
  const config c = parse({});
  EXPECT_EQ(c.cmd, &main_command());
  EXPECT_EQ(c.lpt, 1);
  EXPECT_EQ(device_of(c), "/dev/x4step0");
}

TEST(Cli, PortLikeTestExe) {
  EXPECT_EQ(parse({"2"}).lpt, 2);  // TEST 2
  EXPECT_EQ(parse({"2"}).cmd, &main_command());
  EXPECT_EQ(usage_message({"5"}), "port 5 out of range: use 1 to 4 (LPT1..LPT4)");
}

TEST(Cli, PortAndDeviceOptions) {
  EXPECT_EQ(parse({"-p", "3", "status"}).lpt, 3);
  EXPECT_EQ(parse({"-p3", "status"}).lpt, 3);
  EXPECT_EQ(parse({"--port=4", "status"}).lpt, 4);
  EXPECT_EQ(parse({"--port", "2", "status"}).lpt, 2);
  EXPECT_EQ(parse({"status", "-p", "2"}).lpt, 2);  // after the subcommand too
  EXPECT_EQ(device_of(parse({"-p", "4", "status"})), "/dev/x4step3");
  EXPECT_EQ(device_of(parse({"-d", "/tmp/node", "status"})), "/tmp/node");
  EXPECT_EQ(device_of(parse({"-d", "/tmp/node", "-p", "2", "status"})), "/dev/x4step1");  // the last one wins
  EXPECT_EQ(usage_message({"-p", "0", "status"}), "port 0 out of range: use 1 to 4 (LPT1..LPT4)");
  EXPECT_EQ(usage_message({"-p", "x", "status"}), "port 'x' is not a whole number");
  EXPECT_EQ(usage_message({"status", "-p"}), "status: option '-p' needs a value");
}

TEST(Cli, UnknownThings) {
  EXPECT_EQ(usage_message({"fly"}), "unknown command 'fly'");
  EXPECT_EQ(usage_message({"--fly"}), "unknown option '--fly'");
  EXPECT_EQ(usage_message({"move", "1", "--fly"}), "move: unknown option '--fly'");
  EXPECT_EQ(usage_message({"move", "1", "-x"}), "move: unknown option '-x'");
  EXPECT_EQ(usage_message({"status", "extra"}), "status: unexpected argument 'extra'");
  EXPECT_EQ(usage_message({"move", "1", "--wait=yes"}), "move: option '--wait' takes no value");
}

TEST(Cli, Move) {
  const config c = parse({"move", "1000", "-800", "600", "-400", "--freq", "2000", "-r", "40", "-w"});
  EXPECT_EQ(c.cmd->name, "move");
  EXPECT_EQ(c.move.steps, (std::array<long, 4>{1000, -800, 600, -400}));
  EXPECT_EQ(c.move.freq_hz, 2000);
  EXPECT_EQ(c.move.ramp, milliseconds(40));
  EXPECT_TRUE(c.wait);
}

TEST(Cli, MoveNegativeNumbersAndDefaults) {
  const config c = parse({"move", "-5"});
  EXPECT_EQ(c.move.steps, (std::array<long, 4>{-5, 0, 0, 0}));
  EXPECT_EQ(c.move.freq_hz, 1000);
  EXPECT_EQ(c.move.ramp, milliseconds(50));
  EXPECT_TRUE(c.wait) << "a move stays in the foreground by default";
  EXPECT_FALSE(parse({"move", "-5", "--background"}).wait);
  EXPECT_FALSE(parse({"move", "-5", "-b"}).wait);
  EXPECT_TRUE(parse({"move", "-5", "-b", "-w"}).wait) << "the last one counts";
  EXPECT_EQ(parse({"move", "--freq=20", "1"}).move.ramp,
            milliseconds(20));  // default never exceeds the frequency
  EXPECT_EQ(parse({"move", "-f20", "1", "-r0"}).move.ramp, milliseconds(0));
  EXPECT_EQ(parse({"move", "--", "-1", "-2"}).move.steps, (std::array<long, 4>{-1, -2, 0, 0}));
}

TEST(Cli, MoveErrorsInTheLibrarysWords) {
  EXPECT_EQ(usage_message({"move", "100", "--freq", "30000"}),
            "move: frequency too high: use at most 20000 Hz");
  EXPECT_EQ(usage_message({"move", "100", "--freq", "9"}), "move: frequency too low: use at least 10 Hz");
  EXPECT_EQ(usage_message({"move", "100", "--ramp", "1001"}), "move: ramp too long: use at most 1000 ms");
  EXPECT_EQ(usage_message({"move", "100", "--ramp", "-1"}), "move: ramp -1 out of range: use 0 to 1000 ms");
  EXPECT_EQ(usage_message({"move", "100", "--freq", "100", "--ramp", "101"}),
            "move: ramp too long for the frequency: ramp (ms) must not exceed frequency (Hz)");
  EXPECT_EQ(usage_message({"move", "16777217"}), "move: path too long: at most 16777216 steps per axis");
  EXPECT_EQ(usage_message({"move", "-16777217"}), "move: path too long: at most 16777216 steps per axis");
  EXPECT_EQ(usage_message({"move", "0", "0"}), "move: no steps: give at least one axis a non-zero path");
  EXPECT_EQ(usage_message({"move"}), "move: missing arguments");
  EXPECT_EQ(usage_message({"move", "1", "2", "3", "4", "5"}), "move: unexpected argument '5'");
  EXPECT_EQ(usage_message({"move", "12abc"}), "move: steps '12abc' is not a whole number");
  EXPECT_EQ(usage_message({"move", "0x10"}), "move: steps '0x10' is not a whole number");
  EXPECT_EQ(usage_message({"move", "99999999999999999999"}), "move: steps 99999999999999999999 out of range");
  EXPECT_NO_THROW(parse({"move", "16777216", "-16777216"}));
}

// The X4Step manual's first example: the way back preloaded while the first move runs.
TEST(Cli, MoveThen) {
  config c = parse({"move", "1000", "800", "600", "400", "--freq", "1000", "--ramp", "50", "--then", "-1000",
                    "-800", "-600", "-400", "--wait"});
  EXPECT_EQ(c.move.steps, (std::array<long, 4>{1000, 800, 600, 400}));
  ASSERT_EQ(c.then.size(), 1u);
  EXPECT_EQ(c.then[0].steps, (std::array<long, 4>{-1000, -800, -600, -400}));
  EXPECT_EQ(c.then[0].freq_hz, 1000);
  EXPECT_EQ(c.then[0].ramp, milliseconds(50));
  EXPECT_TRUE(c.wait);

  // Repeatable; missing axes stay; --freq and --ramp apply to every move, wherever they stand.
  c = parse({"move", "--then", "-5", "--then=3", "0", "7", "-f", "2000", "5", "--ramp=10"});
  EXPECT_EQ(c.move.steps, (std::array<long, 4>{5, 0, 0, 0}));
  ASSERT_EQ(c.then.size(), 2u);
  EXPECT_EQ(c.then[0].steps, (std::array<long, 4>{-5, 0, 0, 0}));
  EXPECT_EQ(c.then[1].steps, (std::array<long, 4>{3, 0, 7, 0}));
  for (const auto &m : c.then) {
    EXPECT_EQ(m.freq_hz, 2000);
    EXPECT_EQ(m.ramp, milliseconds(10));
  }
  EXPECT_TRUE(c.wait);
  // The default ramp follows the frequency for them too.
  EXPECT_EQ(parse({"move", "1", "--then", "-1", "--freq", "20"}).then.at(0).ramp, milliseconds(20));
  // "--" ends the path of --then as it ends the options.
  c = parse({"move", "--then", "1", "2", "--", "-3"});
  EXPECT_EQ(c.then.at(0).steps, (std::array<long, 4>{1, 2, 0, 0}));
  EXPECT_EQ(c.move.steps, (std::array<long, 4>{-3, 0, 0, 0}));
  EXPECT_TRUE(parse({"move", "1"}).then.empty());
}

TEST(Cli, MoveThenErrors) {
  EXPECT_EQ(usage_message({"move", "1", "--then", "abc"}), "move: --then steps 'abc' is not a whole number");
  EXPECT_EQ(usage_message({"move", "1", "--then", "5", "x"}), "move: --then steps 'x' is not a whole number");
  EXPECT_EQ(usage_message({"move", "1", "--then", "16777217"}),
            "move: --then path too long: at most 16777216 steps per axis");
  EXPECT_EQ(usage_message({"move", "1", "--then", "0", "0"}),
            "move: --then no steps: give at least one axis a non-zero path");
  EXPECT_EQ(usage_message({"move", "1", "--then", "1", "2", "3", "4", "5"}),
            "move: --then: unexpected argument '5'");
  EXPECT_EQ(usage_message({"move", "1", "--then"}), "move: option '--then' needs a value");
  EXPECT_EQ(usage_message({"move", "1", "--then", "--wait"}),
            "move: --then steps '--wait' is not a whole number");
  // The second --then is checked like the first, and the first path as ever.
  EXPECT_EQ(usage_message({"move", "1", "--then", "-1", "--then", "1.5"}),
            "move: --then steps '1.5' is not a whole number");
  EXPECT_EQ(usage_message({"move", "--then", "1"}), "move: missing arguments");
  EXPECT_EQ(usage_message({"move", "1", "--then", "1", "--freq", "10", "--ramp", "20"}),
            "move: ramp too long for the frequency: ramp (ms) must not exceed frequency (Hz)");
  EXPECT_EQ(usage_message({"jog", "1", "+", "--then", "1"}), "jog: unknown option '--then'");
  EXPECT_TRUE(parse({"move", "--then", "x", "--help"}).help);
}

TEST(Cli, Jog) {
  config c = parse({"jog", "3", "-", "--freq", "500", "--time", "250"});
  EXPECT_EQ(c.axis, x4step::axis::z);
  EXPECT_EQ(c.dir, x4step::direction::negative);
  EXPECT_EQ(c.move.freq_hz, 500);
  EXPECT_EQ(c.time, milliseconds(250));
  EXPECT_FALSE(c.wait);
  c = parse({"jog", "1", "+", "-w"});
  EXPECT_EQ(c.dir, x4step::direction::positive);
  EXPECT_FALSE(c.time);
  EXPECT_TRUE(c.wait);
  EXPECT_EQ(usage_message({"jog", "1", "up"}), "jog: direction 'up': use + or -");
  EXPECT_EQ(usage_message({"jog", "0", "+"}), "jog: axis 0 out of range: use 1 to 4");
  EXPECT_EQ(usage_message({"jog", "1", "+", "--time", "-5"}), "jog: time -5 out of range: use 0 ms or more");
  EXPECT_EQ(usage_message({"jog", "1", "+", "--freq", "20001"}),
            "jog: frequency too high: use at most 20000 Hz");
}

TEST(Cli, Sweep) {
  const config c = parse({"sweep", "2", "1000", "200", "500", "20"});
  EXPECT_EQ(c.axis, x4step::axis::y);
  EXPECT_EQ(c.move.steps[1], 1000);
  EXPECT_EQ(c.sweep_from, 200);
  EXPECT_EQ(c.sweep_to, 500);
  EXPECT_EQ(c.sweep_step, 20);
  EXPECT_EQ(c.move.ramp, milliseconds(0));  // resonance tests: constant speed
  EXPECT_EQ(usage_message({"sweep", "2", "1000", "200", "500", "0"}),
            "sweep: frequency step 0 out of range: use 1 to 20000 Hz");
  EXPECT_EQ(usage_message({"sweep", "2", "1000", "20", "500", "10", "--ramp", "30"}),
            "sweep: ramp too long for the frequency: ramp (ms) must not exceed frequency (Hz)");
  EXPECT_EQ(usage_message({"sweep", "2", "0", "200", "500", "10"}),
            "sweep: no steps: give at least one axis a non-zero path");
  EXPECT_EQ(usage_message({"sweep", "2", "1000", "200", "50000", "10"}),
            "sweep: frequency too high: use at most 20000 Hz");
}

TEST(Cli, OutKeysMonitorRunStatus) {
  config c = parse({"out", "2", "on", "--time", "100"});
  EXPECT_EQ(c.signal, x4step::signal::two);
  EXPECT_TRUE(c.level);
  EXPECT_EQ(c.time, milliseconds(100));
  EXPECT_FALSE(parse({"out", "1", "off"}).level);
  EXPECT_EQ(usage_message({"out", "3", "on"}), "out: signal 3: use 1 (pin 1) or 2 (pin 14)");
  EXPECT_EQ(usage_message({"out", "1", "dim"}), "out: level 'dim': use on or off");

  EXPECT_EQ(parse({"keys", "28", "156"}).codes, (std::vector<int>{28, 156}));
  EXPECT_TRUE(parse({"keys"}).codes.empty());
  EXPECT_EQ(usage_message({"keys", "128"}),
            "keys: key code 128 out of range: use 1..127 (press) or 129..255 (release)");
  EXPECT_EQ(usage_message({"keys", "256"}),
            "keys: key code 256 out of range: use 1..127 (press) or 129..255 (release)");

  EXPECT_EQ(parse({"monitor", "-n", "3"}).moves, 3);
  EXPECT_EQ(usage_message({"monitor", "--moves", "0"}), "monitor: moves 0 out of range: use 1 or more");

  c = parse({"run", "-c", "--echo", "script.x4"});
  EXPECT_EQ(c.file, "script.x4");
  EXPECT_TRUE(c.check);
  EXPECT_TRUE(c.echo);
  EXPECT_EQ(parse({"run"}).file, "-");

  EXPECT_TRUE(parse({"status", "--json"}).json);
  EXPECT_TRUE(parse({"in", "-w"}).watch);
  EXPECT_EQ(parse({"watch"}).cmd->name, "watch");
  EXPECT_TRUE(parse({"watch", "-j"}).json);
  EXPECT_EQ(parse({"watch", "-n", "5"}).count, 5);
  EXPECT_FALSE(parse({"watch"}).count);
  EXPECT_EQ(usage_message({"watch", "--count", "0"}), "watch: count 0 out of range: use 1 or more");
  EXPECT_EQ(usage_message({"watch", "1"}).rfind("watch: ", 0), 0u);
  EXPECT_TRUE(parse({"in", "--read-only"}).read_only);
  EXPECT_TRUE(parse({"in", "-r", "-w"}).read_only);
  EXPECT_FALSE(parse({"in"}).read_only);
  EXPECT_EQ(parse({"help", "jog"}).topic->name, "jog");
  EXPECT_EQ(usage_message({"help", "fly"}), "help: no command 'fly'");
}

TEST(Cli, Timing) {
  config c = parse({"timing"});
  EXPECT_EQ(c.cmd->name, "timing");
  EXPECT_FALSE(c.pulse || c.space || c.dir_setup || c.dir_hold);
  EXPECT_FALSE(c.json);
  c = parse({"timing", "--pulse", "5000", "--space=20000", "--setup", "0", "--hold", "1000000", "-j"});
  EXPECT_EQ(c.pulse, std::chrono::nanoseconds(5000));
  EXPECT_EQ(c.space, std::chrono::nanoseconds(20000));
  EXPECT_EQ(c.dir_setup, std::chrono::nanoseconds(0));
  EXPECT_EQ(c.dir_hold, std::chrono::nanoseconds(1000000));
  EXPECT_TRUE(c.json);
  c = parse({"timing", "--hold", "300"});  // only the times given change
  EXPECT_FALSE(c.pulse || c.space || c.dir_setup);
  EXPECT_EQ(c.dir_hold, std::chrono::nanoseconds(300));
  EXPECT_EQ(parse({"timing", "--pulse", "0"}).pulse, std::chrono::nanoseconds(0));  // symmetric clock
  EXPECT_EQ(parse({"timing", "--pulse", "1000"}).pulse, std::chrono::nanoseconds(1000));
  EXPECT_EQ(parse({"-p", "2", "timing", "--space", "7"}).lpt, 2);

  EXPECT_EQ(usage_message({"timing", "--pulse", "999"}),
            "timing: pulse 999 out of range: use 0 (symmetric clock) or 1000 to 1000000 ns");
  EXPECT_EQ(usage_message({"timing", "--pulse", "1000001"}),
            "timing: pulse 1000001 out of range: use 0 (symmetric clock) or 1000 to 1000000 ns");
  EXPECT_EQ(usage_message({"timing", "--pulse", "-1"}),
            "timing: pulse -1 out of range: use 0 (symmetric clock) or 1000 to 1000000 ns");
  EXPECT_EQ(usage_message({"timing", "--space", "1000001"}),
            "timing: space 1000001 out of range: use 0 to 1000000 ns");
  EXPECT_EQ(usage_message({"timing", "--space", "-5"}), "timing: space -5 out of range: use 0 to 1000000 ns");
  EXPECT_EQ(usage_message({"timing", "--setup", "2000000"}),
            "timing: setup 2000000 out of range: use 0 to 1000000 ns");
  EXPECT_EQ(usage_message({"timing", "--hold", "-1"}), "timing: hold -1 out of range: use 0 to 1000000 ns");
  EXPECT_EQ(usage_message({"timing", "--hold", "5us"}), "timing: hold '5us' is not a whole number");
  EXPECT_EQ(usage_message({"timing", "--pulse"}), "timing: option '--pulse' needs a value");
  EXPECT_EQ(usage_message({"timing", "5000"}), "timing: unexpected argument '5000'");
  EXPECT_EQ(usage_message({"timing", "--freq", "5000"}), "timing: unknown option '--freq'");
  EXPECT_TRUE(parse({"timing", "--help"}).help);
}

TEST(Cli, Mode) {
  config c = parse({"mode"});
  EXPECT_EQ(c.cmd->name, "mode");
  EXPECT_FALSE(c.mode);
  EXPECT_EQ(parse({"mode", "clock-dir"}).mode, x4step::output_mode::clock_dir);
  EXPECT_EQ(parse({"mode", "step-dir"}).mode,
            x4step::output_mode::clock_dir);  // the machine file's other name
  EXPECT_EQ(parse({"mode", "smc-phase"}).mode, x4step::output_mode::smc_phase);
  EXPECT_EQ(parse({"mode", "smc-hold", "-p", "3"}).mode, x4step::output_mode::smc_phase_hold);
  EXPECT_EQ(usage_message({"mode", "smc"}), "mode: no mode 'smc': use clock-dir, smc-phase, smc-hold");
  EXPECT_EQ(usage_message({"mode", "SMC-PHASE"}),
            "mode: no mode 'SMC-PHASE': use clock-dir, smc-phase, smc-hold");
  EXPECT_EQ(usage_message({"mode", "clock-dir", "smc-hold"}), "mode: unexpected argument 'smc-hold'");
  EXPECT_TRUE(parse({"mode", "--json"}).json);
  EXPECT_EQ(usage_message({"mode", "--jason"}), "mode: unknown option '--jason'");
  EXPECT_TRUE(parse({"mode", "bogus", "--help"}).help);  // --help wins over a bad operand
}

TEST(Cli, Profile) {
  config c = parse({"profile", "2"});
  EXPECT_EQ(c.cmd->name, "profile");
  EXPECT_EQ(c.axis, x4step::axis::y);
  EXPECT_FALSE(c.v0 || c.ve || c.vm || c.a0 || c.ae);
  c = parse({"profile", "4", "--v0", "0", "--ve=100000", "--vm", "100000", "--a0", "1000000", "--ae=0"});
  EXPECT_EQ(c.v0, 0u);
  EXPECT_EQ(c.ve, 100000u);
  EXPECT_EQ(c.vm, 100000u);
  EXPECT_EQ(c.a0, 1000000u);
  EXPECT_EQ(c.ae, 0u);
  EXPECT_EQ(usage_message({"profile"}), "profile: missing arguments");
  EXPECT_EQ(usage_message({"profile", "5"}), "profile: axis 5 out of range: use 1 to 4");
  EXPECT_EQ(usage_message({"profile", "1", "2"}), "profile: unexpected argument '2'");
  EXPECT_EQ(usage_message({"profile", "1", "--vm", "0"}),
            "profile: vm 0 out of range: use 1 to 100000 steps/s");
  EXPECT_EQ(usage_message({"profile", "1", "--vm", "100001"}),
            "profile: vm 100001 out of range: use 1 to 100000 steps/s");
  EXPECT_EQ(usage_message({"profile", "1", "--v0", "-1"}),
            "profile: v0 -1 out of range: use 0 to 100000 steps/s");
  EXPECT_EQ(usage_message({"profile", "1", "--a0", "1000001"}),
            "profile: a0 1000001 out of range: use 0 to 1000000 steps/s^2");
  EXPECT_EQ(usage_message({"profile", "1", "--ae", "x"}), "profile: ae 'x' is not a whole number");
  EXPECT_EQ(usage_message({"profile", "1", "--freq", "5"}), "profile: unknown option '--freq'");
}

TEST(Cli, Goto) {
  config c = parse({"goto", "1=1000", "3=-2147483648"});
  EXPECT_EQ(c.cmd->name, "goto");
  EXPECT_EQ(c.axes.mask(), 0x5u);
  EXPECT_EQ(c.targets, (std::array<long, 4>{1000, 0, -2147483648L, 0}));
  EXPECT_FALSE(c.relative);
  EXPECT_FALSE(c.no_wait);
  c = parse({"goto", "4=-5", "--relative", "--no-wait", "2=2147483647"});
  EXPECT_EQ(c.axes.mask(), 0xau);
  EXPECT_EQ(c.targets, (std::array<long, 4>{0, 2147483647L, 0, -5}));
  EXPECT_TRUE(c.relative);
  EXPECT_TRUE(c.no_wait);
  EXPECT_EQ(usage_message({"goto"}), "goto: missing arguments");
  EXPECT_EQ(usage_message({"goto", "1000"}), "goto: '1000': use AXIS=POSITION, e.g. 1=1000");
  EXPECT_EQ(usage_message({"goto", "--relative", "5"}), "goto: '5': use AXIS=DISTANCE, e.g. 1=1000");
  EXPECT_EQ(usage_message({"goto", "5=1"}), "goto: axis 5 out of range: use 1 to 4");
  EXPECT_EQ(usage_message({"goto", "x=1"}), "goto: axis 'x' is not a whole number");
  EXPECT_EQ(usage_message({"goto", "1=1", "1=2"}), "goto: axis 1 given twice");
  EXPECT_EQ(usage_message({"goto", "1=2147483648"}),
            "goto: position 2147483648 out of range: use -2147483648 to 2147483647");
  EXPECT_EQ(usage_message({"goto", "1=-3000000000", "--relative"}),
            "goto: distance -3000000000 out of range: use -2147483648 to 2147483647");
  EXPECT_EQ(usage_message({"goto", "1="}), "goto: position '' is not a whole number");
  EXPECT_EQ(usage_message({"goto", "1=1", "2=2", "3=3", "4=4", "1=5"}), "goto: unexpected argument '1=5'");
  EXPECT_EQ(usage_message({"goto", "1=5", "--wait"}), "goto: unknown option '--wait'");
}

TEST(Cli, Home) {
  config c = parse({"home", "3"});
  EXPECT_EQ(c.cmd->name, "home");
  EXPECT_EQ(c.axis, x4step::axis::z);
  EXPECT_EQ(c.homing.phase1_speed(), -1000);  // the library's defaults
  EXPECT_EQ(c.homing.phase2_speed(), 100);
  EXPECT_EQ(c.homing.max_travel(), 100000ul);
  EXPECT_TRUE(c.homing.phase1() && c.homing.phase2());
  c = parse({"home", "1", "--vref1", "100000", "--vref2=-1", "--sref", "2147483647", "--phase", "2"});
  EXPECT_EQ(c.homing.phase1_speed(), 100000);
  EXPECT_EQ(c.homing.phase2_speed(), -1);
  EXPECT_EQ(c.homing.max_travel(), 2147483647ul);
  EXPECT_FALSE(c.homing.phase1());
  EXPECT_TRUE(c.homing.phase2());
  c = parse({"home", "1", "--phase=1"});
  EXPECT_TRUE(c.homing.phase1());
  EXPECT_FALSE(c.homing.phase2());
  const std::string vref =
      " out of range: use -100000 to -1 or 1 to 100000 steps/s (the sign is the direction)";
  EXPECT_EQ(usage_message({"home", "1", "--vref1", "0"}), "home: vref1 0" + vref);
  EXPECT_EQ(usage_message({"home", "1", "--vref2", "-100001"}), "home: vref2 -100001" + vref);
  EXPECT_EQ(usage_message({"home", "1", "--sref", "0"}),
            "home: sref 0 out of range: use 1 to 2147483647 steps");
  EXPECT_EQ(usage_message({"home", "1", "--sref", "2147483648"}),
            "home: sref 2147483648 out of range: use 1 to 2147483647 steps");
  EXPECT_EQ(usage_message({"home", "1", "--phase", "3"}), "home: phase 3: use 1 or 2 (both: no --phase)");
  EXPECT_EQ(usage_message({"home"}), "home: missing arguments");
  EXPECT_EQ(usage_message({"home", "1", "2"}), "home: unexpected argument '2'");
}

// home, jog and panel in a machine's units: axis letters, --machine, --feed, --distance.
TEST(Cli, MachineUnits) {
  config c = parse({"home", "--machine", "m.ini"});
  EXPECT_TRUE(c.machine_units());
  EXPECT_EQ(c.letters, "");
  c = parse({"home", "x", "ZY", "-m", "m.ini"});
  EXPECT_EQ(c.letters, "XZY");
  c = parse({"home", "Z"});  // the machine file from $X4STEP_MACHINE or /etc
  EXPECT_TRUE(c.machine_units());
  EXPECT_FALSE(parse({"home", "2"}).machine_units());
  EXPECT_EQ(
      usage_message({"home", "X", "--vref1", "100"}),
      "home: --vref1, --vref2, --sref, --phase and --brake are for AXIS in steps; the machine file gives "
      "the homing of axis letters");
  EXPECT_EQ(usage_message({"home", "--machine", "m.ini", "1"}),
            "home: '1': give axis letters (X Y Z A B C), or one AXIS 1..4");
  c = parse({"jog", "z-", "--machine", "m.ini", "--feed", "120.5", "--distance", "0.25"});
  EXPECT_EQ(c.cmd->name, "jog");
  EXPECT_EQ(c.letters, "Z");
  EXPECT_EQ(c.dir, x4step::direction::negative);
  EXPECT_EQ(c.feed, 120.5);
  EXPECT_EQ(c.distance, 0.25);
  c = parse({"jog", "A+"});
  EXPECT_EQ(c.dir, x4step::direction::positive);
  EXPECT_FALSE(c.distance);
  EXPECT_FALSE(parse({"jog", "1", "+"}).machine_units());
  EXPECT_EQ(usage_message({"jog", "X"}),
            "jog: 'X': give an axis letter and a sign (X+, Z-), or AXIS +|- in steps");
  EXPECT_EQ(
      usage_message({"jog", "X+", "--freq", "100"}),
      "jog: --freq, --ramp, --time and --wait are for AXIS +|- in steps; X+ takes --machine, --feed and "
      "--distance");
  EXPECT_EQ(usage_message({"jog", "1", "+", "--distance", "2"}),
            "jog: --machine, --feed and --distance jog an axis letter, e.g. 'jog X+ --machine FILE'");
  EXPECT_EQ(usage_message({"jog", "X+", "--distance", "0"}), "jog: distance '0': use a number above 0 units");
  EXPECT_EQ(usage_message({"jog", "X+", "--feed", "fast"}),
            "jog: feed 'fast': use a number above 0 units/min");
  c = parse({"panel", "-m", "m.ini", "--feed", "300"});
  EXPECT_EQ(c.cmd->name, "panel");
  EXPECT_EQ(c.machine, "m.ini");
  EXPECT_EQ(c.feed, 300.0);
  EXPECT_EQ(usage_message({"panel", "X"}), "panel: unexpected argument 'X'");
}

TEST(Cli, ZeroHaltLimits) {
  config c = parse({"zero", "1", "4"});
  EXPECT_EQ(c.cmd->name, "zero");
  EXPECT_EQ(c.axes.mask(), 0x9u);
  EXPECT_EQ(c.at, 0);
  EXPECT_EQ(parse({"zero", "2", "--at", "-1500"}).at, -1500);
  EXPECT_EQ(usage_message({"zero"}), "zero: missing arguments");
  EXPECT_EQ(usage_message({"zero", "2", "2"}), "zero: axis 2 given twice");
  EXPECT_EQ(usage_message({"zero", "1", "--at", "2147483648"}),
            "zero: position 2147483648 out of range: use -2147483648 to 2147483647");

  c = parse({"halt", "2", "3"});
  EXPECT_EQ(c.cmd->name, "halt");
  EXPECT_EQ(c.axes.mask(), 0x6u);
  EXPECT_FALSE(c.halt_stop);
  EXPECT_TRUE(parse({"halt", "1", "--stop"}).halt_stop);
  EXPECT_TRUE(parse({"halt", "1", "-s"}).halt_stop);
  EXPECT_EQ(usage_message({"halt"}), "halt: missing arguments");
  EXPECT_EQ(usage_message({"halt", "0"}), "halt: axis 0 out of range: use 1 to 4");

  c = parse({"limits"});
  EXPECT_EQ(c.cmd->name, "limits");
  EXPECT_TRUE(c.axes.empty());
  EXPECT_FALSE(c.ref || c.plus || c.minus || c.nc);
  c = parse({"limits", "2", "--ref", "3", "--plus=1", "--minus", "none"});
  EXPECT_EQ(c.axis, x4step::axis::y);
  EXPECT_EQ(c.axes.mask(), 0x2u);
  EXPECT_EQ(c.ref, 3);
  EXPECT_EQ(c.plus, 1);
  EXPECT_EQ(c.minus, 0);
  EXPECT_EQ(parse({"limits", "1"}).axes, x4step::axis::x);  // shows
  EXPECT_EQ(parse({"limits", "--nc", "1,3,5"}).nc, 0x15u);
  EXPECT_EQ(parse({"limits", "--nc", "4"}).nc, 0x8u);
  EXPECT_EQ(parse({"limits", "--nc", "0x1f"}).nc, 0x1fu);
  EXPECT_EQ(parse({"limits", "--nc", "none"}).nc, 0u);
  EXPECT_EQ(parse({"limits", "4", "--minus", "0", "--nc", "0x00"}).nc, 0u);
  EXPECT_EQ(usage_message({"limits", "--ref", "3"}),
            "limits: --ref, --plus and --minus need an AXIS, e.g. 'x4ctl limits 1 --ref 3'");
  EXPECT_EQ(usage_message({"limits", "1", "--plus", "6"}),
            "limits: input 6 out of range: use 1 to 5 (pins 15, 13, 12, 10, 11), or 0 for none");
  EXPECT_EQ(usage_message({"limits", "1", "2"}), "limits: unexpected argument '2'");
  EXPECT_EQ(usage_message({"limits", "--nc", "1,6"}),
            "limits: --nc input 6 out of range: use 1 to 5 (pins 15, 13, 12, 10, 11), or 0 for none");
  EXPECT_EQ(usage_message({"limits", "--nc", "1,0"}), "limits: --nc input 0: use 1 to 5, e.g. --nc 1,3");
  EXPECT_EQ(usage_message({"limits", "--nc", "1,"}), "limits: --nc input '' is not a whole number");
  EXPECT_EQ(usage_message({"limits", "--nc", "0x20"}),
            "limits: nc mask 0x20 out of range: use 0x00 to 0x1f (bit k: input k+1)");
  EXPECT_EQ(usage_message({"limits", "--nc", "0xg"}),
            "limits: nc mask 0xg out of range: use 0x00 to 0x1f (bit k: input k+1)");
}

TEST(Cli, HelpWinsOverMissingArguments) {
  EXPECT_TRUE(parse({"move", "--help"}).help);
  EXPECT_TRUE(parse({"sweep", "-h"}).help);
  EXPECT_EQ(parse({"--help", "jog"}).cmd->name, "jog");
  EXPECT_TRUE(parse({"-h"}).help);
  EXPECT_TRUE(parse({"--version"}).version);
}

// Every command of the registry has a help with a Usage line, lines of at
// most 80 columns, and each of its options; the overview lists it; the
// parser takes every option its help lists. The words are what the help of
// some commands must say besides.
TEST(Cli, HelpTexts) {
  const std::map<std::string, std::vector<std::string>> expected = {
      {"x4ctl",
       {"--port",    "--device", "--help",      "--version", "move",         "jog",           "brake",
        "stop",      "status",   "in",          "out",       "keys",         "sweep",         "monitor",
        "run",       "timing",   "mode [MODE]", "smc-phase", "profile AXIS", "goto AXIS=POS", "home AXIS",
        "zero AXIS", "limits",   "halt AXIS",   "watch",     "Exit status"}},
      {"profile",
       {"--v0", "--ve", "--vm", "--a0", "--ae", "0..100000 steps/s", "1..100000", "0..1000000 steps/s^2",
        "3600 s", "--port", "--device", "--help", "Exit status"}},
      {"goto",
       {"--relative", "--no-wait", "-2147483648..2147483647", "limit switch", "x4ctl halt", "--port",
        "--device", "--help", "Exit status"}},
      {"home",
       {"--vref1", "--vref2", "--sref", "--phase", "sign is the direction", "--ref INPUT", "--port",
        "--device", "--help", "Exit status"}},
      {"zero", {"--at", "synchronized", "--port", "--device", "--help", "Exit status"}},
      {"limits",
       {"--ref", "--plus", "--minus", "--nc", "pins 15, 13", "normally closed", "ambiguous", "--port",
        "--device", "--help", "Exit status"}},
      {"halt", {"--stop", "goto --no-wait", "--port", "--device", "--help", "Exit status"}},
      {"move",
       {"--freq", "--ramp", "--wait", "--then", "--port", "--device", "--help", "Exit status", "background",
        "preload", "the rest do not start"}},
      {"jog", {"--freq", "--ramp", "--time", "--wait", "--port", "--device", "--help"}},
      {"brake", {"--port", "--device", "--help", "Exit status"}},
      {"stop", {"--port", "--device", "--help", "Exit status"}},
      {"status", {"--json", "--port", "--device", "--help", "coordinate", "synchronized"}},
      {"in", {"--watch", "--read-only", "--port", "--device", "--help", "pins 15, 13, 12, 10", "stale"}},
      {"out", {"--time", "--port", "--device", "--help", "pin 14"}},
      {"keys", {"--port", "--device", "--help", "ESC (1)"}},
      {"sweep", {"--ramp", "--port", "--device", "--help"}},
      {"monitor", {"--moves", "--port", "--device", "--help", "read-only"}},
      {"watch", {"--json", "--count", "--port", "--device", "--help", "read-only", "missed N events"}},
      {"run", {"--check", "--echo", "--port", "--device", "--help", "Ax,y,z", "M+ 500"}},
      {"timing",
       {"--pulse", "--space", "--setup", "--hold", "--json", "--port", "--device", "--help",
        "0 (symmetric clock", "1000..1000000 ns", "0..1000000 ns", "frequency too high", "after x4ctl exits",
        "Exit status"}},
      {"mode",
       {"clock-dir", "smc-phase", "smc-hold", "SMC800/SMC1500", "motors off at rest",
        "reduced holding current", "axis 4", "--port", "--device", "--help", "after x4ctl exits",
        "Exit status", "step-dir"}},
      {"machine",
       {"check FILE...", "import [OPTIONS] INI [HAL]", "--output", "did you mean", "FILE:LINE:COLUMN",
        "StepConf", "not carried", "pin map", "Exit status"}},
  };
  std::vector<const subcommand *> all = {&main_command()};
  for (const command_group &g : command_groups()) all.insert(all.end(), g.commands.begin(), g.commands.end());
  EXPECT_EQ(all.size(), 29u);
  const std::string overview = help_text(main_command());
  for (const subcommand *cmd : all) {
    const std::string name = name_of(*cmd);
    const std::string h = help_text(*cmd);
    const std::string usage =
        cmd->name.empty() || cmd->overview ? "Usage: x4ctl [" : "Usage: x4ctl " + name + " ";
    EXPECT_EQ(h.rfind(usage, 0), 0u) << h;
    if (!cmd->name.empty()) {
      EXPECT_TRUE(contains(overview, "\n  " + name + " ")) << name;
    }
    if (const auto w = expected.find(name); w != expected.end()) {
      for (const auto &word : w->second) EXPECT_TRUE(contains(h, word)) << name << " help lacks " << word;
    }
    for (const option &o : cmd->options) {
      if (!o.help.empty()) {
        EXPECT_TRUE(contains(h, "--" + o.name)) << name << " help lacks --" << o.name;
      }
    }
    std::istringstream lines(h);
    for (std::string line; std::getline(lines, line);) {
      EXPECT_LE(line.size(), 80u) << line;
      // "  -f, --freq=HZ ..." or "      --then STEPS...": the parser knows it.
      const size_t dashes = line.find("--");
      if (!(line.rfind("  -", 0) == 0 || line.rfind("      --", 0) == 0) || dashes == std::string::npos)
        continue;
      const std::string opt = line.substr(dashes, line.find_first_of("= ", dashes) - dashes);
      const bool value = line[dashes + opt.size()] == '=' || opt == "--then";
      std::vector<std::string> args = {"x4ctl"};
      if (!cmd->name.empty() && !cmd->overview) args.push_back(name);
      args.push_back(opt);
      if (value) args.push_back("1");
      args.push_back("--help");
      try {
        parse_args(args);
      } catch (const usage_error &e) {
        EXPECT_FALSE(contains(e.what(), "unknown option")) << name << ": " << e.what();
      }
    }
  }
}

// ---- run_main: exit status and streams ------------------------------------------------

struct captured {
  int status;
  std::string out, err;
};

captured run(std::vector<std::string> args) {
  args.insert(args.begin(), "x4ctl");
  std::ostringstream out, err;
  auto *old_out = std::cout.rdbuf(out.rdbuf());
  auto *old_err = std::cerr.rdbuf(err.rdbuf());
  const int status = run_main(args);
  std::cout.rdbuf(old_out);
  std::cerr.rdbuf(old_err);
  return {status, out.str(), err.str()};
}

// A script file that is removed again.
class temp_file {
 public:
  explicit temp_file(const std::string &text) {
    char name[] = "/tmp/x4ctl-test-XXXXXX";
    const int fd = ::mkstemp(name);
    ::close(fd);
    path_ = name;
    std::ofstream(path_) << text;
  }
  ~temp_file() { std::remove(path_.c_str()); }
  const std::string &path() const { return path_; }

 private:
  std::string path_;
};

TEST(Main, HelpAndVersion) {
  captured r = run({"--help"});
  EXPECT_EQ(r.status, 0);
  EXPECT_TRUE(contains(r.out, "Usage: x4ctl"));
  EXPECT_EQ(r.err, "");
  for (const char *c :
       {"move",   "jog",  "brake",   "stop", "status", "in",   "out",    "keys", "sweep", "monitor", "run",
        "timing", "mode", "profile", "goto", "home",   "zero", "limits", "halt", "watch", "help"}) {
    r = run({c, "--help"});
    EXPECT_EQ(r.status, 0) << c;
    EXPECT_TRUE(contains(r.out, "Usage: x4ctl ")) << c;
  }
  r = run({"help", "sweep"});
  EXPECT_EQ(r.status, 0);
  EXPECT_TRUE(contains(r.out, "Usage: x4ctl sweep"));
  r = run({"--version"});
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.out.rfind("x4ctl ", 0), 0u);
}

TEST(Main, UsageErrorsExit2WithAHint) {
  captured r = run({"move", "100", "--freq", "30000"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err, "x4ctl: move: frequency too high: use at most 20000 Hz\nTry 'x4ctl move --help'.\n");
  r = run({"fly"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "x4ctl: unknown command 'fly'\nTry 'x4ctl --help'.\n");
}

// A bad path after --then is found before the device is opened: nothing moves.
TEST(Main, MoveThenUsageErrorsExit2) {
  captured r = run({"-d", "/nonexistent/x4step9", "move", "100", "--then", "-100", "--then", "x", "--wait"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err, "x4ctl: move: --then steps 'x' is not a whole number\nTry 'x4ctl move --help'.\n");
  r = run({"-d", "/nonexistent/x4step9", "move", "100", "--then", "-100", "--wait"});
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "x4ctl: move: /nonexistent/x4step9: port not found")) << r.err;
}

// Bad times and modes are found before the device is opened: exit 2, not 1.
TEST(Main, TimingAndModeUsageErrorsExit2) {
  captured r = run({"-d", "/nonexistent/x4step9", "timing", "--pulse", "500"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err,
            "x4ctl: timing: pulse 500 out of range: use 0 (symmetric clock) or 1000 to 1000000 ns\n"
            "Try 'x4ctl timing --help'.\n");
  r = run({"-d", "/nonexistent/x4step9", "timing", "--setup", "1000001"});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.err, "setup 1000001 out of range: use 0 to 1000000 ns")) << r.err;
  r = run({"-d", "/nonexistent/x4step9", "mode", "half-step"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err,
            "x4ctl: mode: no mode 'half-step': use clock-dir, smc-phase, smc-hold\n"
            "Try 'x4ctl mode --help'.\n");
  r = run({"-d", "/nonexistent/x4step9", "timing", "--pulse", "5000"});
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "x4ctl: timing: /nonexistent/x4step9: port not found")) << r.err;
  r = run({"-d", "/nonexistent/x4step9", "mode"});
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "x4ctl: mode: /nonexistent/x4step9: port not found")) << r.err;
}

TEST(Main, MissingPortExits1) {
  captured r = run({"-d", "/nonexistent/x4step9", "status"});
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err,
            "x4ctl: status: /nonexistent/x4step9: port not found: is x4step loaded, the port present and not "
            "in use?\n");
  r = run({"-d", "/nonexistent/x4step9", "move", "10", "--wait"});
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "x4ctl: move: /nonexistent/x4step9: port not found")) << r.err;
  r = run({"-d", "/nonexistent/x4step9", "brake"});
  EXPECT_EQ(r.status, 1);
  r = run({"-d", "/nonexistent/x4step9"});
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "x4ctl: /nonexistent/x4step9: port not found")) << r.err;
}

// Positioning: bad values are found before the device is opened (exit 2);
// a missing port is exit 1.
TEST(Main, PositioningUsageErrorsExit2) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> bad = {
      {{"goto", "1=x"}, "goto: position 'x' is not a whole number"},
      {{"profile", "1", "--vm", "100001"}, "profile: vm 100001 out of range: use 1 to 100000 steps/s"},
      {{"home", "1", "--vref1", "0"}, "home: vref1 0 out of range"},
      {{"zero"}, "zero: missing arguments"},
      {{"limits", "--plus", "1"}, "limits: --ref, --plus and --minus need an AXIS"},
      {{"halt", "7"}, "halt: axis 7 out of range: use 1 to 4"},
  };
  for (auto [args, want] : bad) {
    const std::string name = args[0];
    args.insert(args.begin(), {"-d", "/nonexistent/x4step9"});
    const captured r = run(args);
    EXPECT_EQ(r.status, 2) << name;
    EXPECT_EQ(r.out, "") << name;
    EXPECT_TRUE(contains(r.err, "x4ctl: " + want)) << r.err;
    EXPECT_TRUE(contains(r.err, "Try 'x4ctl " + name + " --help'.")) << r.err;
  }
  for (const auto &args : std::vector<std::vector<std::string>>{{"goto", "1=5"},
                                                                {"goto", "1=5", "--no-wait"},
                                                                {"profile", "1"},
                                                                {"home", "1"},
                                                                {"zero", "1"},
                                                                {"limits"},
                                                                {"halt", "1"}}) {
    std::vector<std::string> a = {"-d", "/nonexistent/x4step9"};
    a.insert(a.end(), args.begin(), args.end());
    const captured r = run(a);
    EXPECT_EQ(r.status, 1) << args[0];
    EXPECT_TRUE(contains(r.err, "x4ctl: " + args[0] + ": /nonexistent/x4step9: port not found")) << r.err;
  }
}

TEST(Main, RunCheckNeedsNoDevice) {
  const temp_file good("# the manual's second example\ns1\nd1000\nf10000\nr100\ns2\nd500\ns3\nd100\ng\n");
  captured r = run({"-d", "/nonexistent", "run", "--check", good.path()});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "9 commands, no errors")) << r.out;

  const temp_file bad("s1\nd1000\nf20\ng\n");  // ramp 50 ms > 20 Hz, found before anything moves
  r = run({"-d", "/nonexistent", "run", bad.path()});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(
      contains(r.err, "x4ctl: run: " + bad.path() +
                          ":4: G: ramp too long for the frequency: ramp (ms) must not exceed frequency (Hz)"
                          " (G uses the leader axis 1: F20 R50)"))
      << r.err;

  const temp_file typo("s1\nd100\nz\n");
  r = run({"run", typo.path()});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "x4ctl: run: " + typo.path() + ":3: z: unknown command: H shows the commands\n");

  r = run({"run", "/nonexistent.x4"});
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "x4ctl: run: cannot read /nonexistent.x4")) << r.err;
}

// ---- x4ctl gcode --check: a program on a machine, checked without a port ---------------

const char *const pocket =
    "%\n"
    "(a small pocket with arcs)\n"
    "G21 G90 G17 G94 G64 P0.02\n"
    "G0 Z-0.5\n"
    "G0 X20 Y20\n"
    "M3 S1000\n"
    "G1 Z-1 F100\n"
    "G1 X60 F300\n"
    "G3 X70 Y30 I0 J10\n"
    "G1 Y60\n"
    "G2 X60 Y70 I-10 J0\n"
    "G1 X20\n"
    "G1 Y20\n"
    "G0 Z-0.5\n"
    "M5\n"
    "M2\n"
    "%\n";

const std::string mill = X4_SOURCE_DIR "/machines/smc1500-mill.ini";

TEST(Gcode, CheckSummarizesWithoutAPort) {
  const temp_file prog(pocket);
  captured r = run({"-d", "/nonexistent", "gcode", "--machine", mill, "--check", prog.path()});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(r.err, "");
  // 0.01 mm chords: 2 acos(1 - 0.01 / 10) per chord, 36 for a quarter circle.
  EXPECT_TRUE(
      contains(r.out, prog.path() + ": OK: 16 lines, 79 segments, 252.6 mm along the path, about 0:48"))
      << r.out;
  // Extents from where the motion starts (Z 0, the machine's position), work and machine
  // coordinates (the same: the machine file has no parameter file).
  EXPECT_TRUE(contains(r.out,
                       "extents (mm, work coordinates): X 0..70 Y 0..70 Z -1..0; machine: X 0..70 Y 0..70 "
                       "Z -1..0\n"))
      << r.out;
  r = run({"gcode", "-m", mill, "-c", "--json", prog.path()});
  EXPECT_EQ(r.status, 0) << r.out;
  EXPECT_TRUE(contains(r.out, "\"lines\":16,\"segments\":79,\"length\":252.59")) << r.out;
  EXPECT_TRUE(contains(r.out,
                       "\"extents\":{\"X\":[0,70],\"Y\":[0,70],\"Z\":[-1,0]},\"machine_extents\":{\"X\":[0,"
                       "70],\"Y\":[0,70],\"Z\":[-1,0]}}\n"))
      << r.out;
  // The machine from $X4STEP_MACHINE when --machine is not given.
  ::setenv("X4STEP_MACHINE", mill.c_str(), 1);
  r = run({"gcode", "--check", prog.path()});
  ::unsetenv("X4STEP_MACHINE");
  EXPECT_EQ(r.status, 0) << r.err;
}

TEST(RunDisplay, FitLineShortensInItsOrderThenCuts) {
  const std::vector<std::vector<std::string>> fields = {
      {"gcode: running 5.0%", "running 5.0%"}, {"line 123", "L123", ""}, {"12:34 left", ""}};
  const std::vector<size_t> shrink = {0, 1, 1, 2};
  EXPECT_EQ(x4ctl::fit_line(fields, shrink, 80), "gcode: running 5.0% | line 123 | 12:34 left");
  EXPECT_EQ(x4ctl::fit_line(fields, shrink, 36), "running 5.0% | line 123 | 12:34 left");
  EXPECT_EQ(x4ctl::fit_line(fields, shrink, 35), "running 5.0% | L123 | 12:34 left");
  EXPECT_EQ(x4ctl::fit_line(fields, shrink, 30), "running 5.0% | 12:34 left");
  EXPECT_EQ(x4ctl::fit_line(fields, shrink, 20), "running 5.0%");
  EXPECT_EQ(x4ctl::fit_line(fields, shrink, 7), "running");
  EXPECT_EQ(x4ctl::clock_text(59.6), "1:00");
  EXPECT_EQ(x4ctl::clock_text(3725), "1:02:05");
}

TEST(RunDisplay, GridStepsAreOneTwoFive) {
  EXPECT_DOUBLE_EQ(x4ctl::round_up_125(0.03), 0.05);
  EXPECT_DOUBLE_EQ(x4ctl::round_up_125(2), 2);
  EXPECT_DOUBLE_EQ(x4ctl::round_up_125(7), 10);
  EXPECT_DOUBLE_EQ(x4ctl::grid_step(183.5, 8), 20);
  EXPECT_DOUBLE_EQ(x4ctl::grid_step(0.3, 4), 0.1);
  EXPECT_DOUBLE_EQ(x4ctl::grid_step(600, 8), 100);
}

TEST(Gcode, CheckRefusesWithFileAndLine) {
  std::string text = pocket;
  text.replace(text.find("G0 X20 Y20"), 10, "G0 X20 Y-20");
  const temp_file beyond(text);
  captured r = run({"-d", "/nonexistent", "gcode", "-m", mill, "--check", beyond.path()});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err,
            "x4ctl: gcode: " + beyond.path() + ":5:1: Y -20 is beyond the soft limit [AXIS_Y] MIN_LIMIT 0\n");
  r = run({"gcode", "-m", mill, "--check", "--json", beyond.path()});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(
      contains(r.out, "{\"schema\":1,\"error\":{\"message\":\"gcode: " + beyond.path() + ":5:1: Y -20"))
      << r.out;
  // An arc bulging past X 200 between ends inside.
  const temp_file bulge("G0 X195 Y60\nG2 X195 Y40 I0 J-10 F100\nM2\n");
  r = run({"gcode", "-m", mill, "--check", bulge.path()});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.err, bulge.path() + ":2:1: X 20")) << r.err;
  // The interpreter's refusals.
  const temp_file unknown("G0 X1\nG5 X2\nM2\n");
  r = run({"gcode", "-m", mill, "--check", unknown.path()});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.err, "x4ctl: gcode: " + unknown.path() + ":2:")) << r.err;
  // Without --check too, before the port is opened (it is not there).
  r = run({"-d", "/nonexistent", "gcode", "-m", mill, unknown.path()});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.err, "x4ctl: gcode: " + unknown.path() + ":2:")) << r.err;
  const temp_file unended("G0 X1\n");
  r = run({"gcode", "-m", mill, "--check", unended.path()});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.err, unended.path() + ":2:1: file ended without M2, M30 or '%'")) << r.err;
  // An axis the machine does not have.
  const temp_file a_axis("G0 A10\nM2\n");
  r = run({"gcode", "-m", mill, "--check", a_axis.path()});
  EXPECT_EQ(r.err,
            "x4ctl: gcode: " + a_axis.path() + ":1:1: the machine has no A axis ([TRAJ] COORDINATES)\n");
}

TEST(Gcode, CheckRefusesABadMachineOrUsage) {
  const temp_file prog(pocket);
  const temp_file bad_machine("[X4STEP]\nARC_TOLERANCE = 0.01\nJUNCTION_DEVIATON = 0.02\n");
  captured r = run({"gcode", "-m", bad_machine.path(), "--check", prog.path()});
  EXPECT_EQ(r.status, 2);
  // Every mistake, a line each.
  EXPECT_EQ(r.err, "x4ctl: gcode: " + bad_machine.path() +
                       ": [TRAJ]: no [TRAJ] section: it needs COORDINATES and LINEAR_UNITS\n"
                       "x4ctl: gcode: " +
                       bad_machine.path() +
                       ":3:1: [X4STEP] JUNCTION_DEVIATON: unknown key: did you mean JUNCTION_DEVIATION?\n");
  r = run({"gcode", "-m", "/nonexistent.ini", "--check", prog.path()});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "x4ctl: gcode: /nonexistent.ini: cannot read the machine file\n");
  r = run({"gcode", "-m", mill, "--check", "/nonexistent.ngc"});
  EXPECT_EQ(r.status, 1);
  EXPECT_TRUE(contains(r.err, "x4ctl: gcode: cannot read /nonexistent.ngc")) << r.err;
  r = run({"gcode", "-m", mill, "--check"});
  EXPECT_EQ(r.status, 2);
  r = run({"gcode", "-m", mill, "--override", "0", prog.path()});
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.err, "override")) << r.err;
  r = run({"gcode", "--help"});
  EXPECT_EQ(r.status, 0);
  EXPECT_TRUE(contains(r.out, "Usage: x4ctl gcode [OPTIONS] FILE")) << r.out;
}

// ---- the command language --------------------------------------------------------------

std::string parse_error(const std::string &text) {
  try {
    parse_command(text);
  } catch (const usage_error &e) {
    return e.what();
  }
  return "";
}

TEST(Language, EveryCommandCaseInsensitive) {
  struct {
    const char *text;
    verb what;
    std::vector<long> args;
  } cases[] = {
      {"S2", verb::select, {2}},
      {"s 3", verb::select, {3}},
      {"D1000", verb::distance, {1000}},
      {"d-250", verb::distance, {-250}},
      {"d +7", verb::distance, {7}},
      {"F2000", verb::frequency, {2000}},
      {"r50", verb::ramp, {50}},
      {"g", verb::go, {}},
      {"I", verb::info, {}},
      {"m+", verb::endless, {}},
      {"c", verb::cursor, {}},
      {"a200,500,20", verb::sweep, {200, 500, 20}},
      {"A 200, 500 ,20", verb::sweep, {200, 500, 20}},
      {"t", verb::toggle, {}},
      {"E", verb::inputs, {}},
      {"h", verb::help, {}},
      {"?", verb::help, {}},
      {"q", verb::quit, {}},
      {"o1,1", verb::output, {1, 1}},
      {"k28,156", verb::keys, {28, 156}},
      {"K", verb::keys, {}},
      {"w100", verb::wait, {100}},
  };
  for (const auto &c : cases) {
    const command cmd = parse_command(c.text);
    EXPECT_EQ(cmd.what, c.what) << c.text;
    EXPECT_EQ(cmd.args, c.args) << c.text;
    EXPECT_EQ(cmd.text, c.text) << c.text;
  }
}

TEST(Language, EndlessAndTimes) {
  command c = parse_command("M-");
  EXPECT_EQ(c.what, verb::endless);
  EXPECT_EQ(c.dir, x4step::direction::negative);
  EXPECT_FALSE(c.time_ms);
  c = parse_command("m+ 500");
  EXPECT_EQ(c.dir, x4step::direction::positive);
  EXPECT_EQ(c.time_ms, 500);
  EXPECT_EQ(parse_command("M-250").time_ms, 250);
  EXPECT_EQ(parse_command("T 1000").time_ms, 1000);
  EXPECT_EQ(parse_command("e 300").time_ms, 300);
}

TEST(Language, BadCommandsSayWhatIsWrong) {
  EXPECT_EQ(parse_error("x"), "x: unknown command: H shows the commands");
  EXPECT_EQ(parse_error("S5"), "S5: axis 5 out of range: use 1 to 4");
  EXPECT_EQ(parse_error("s"), "s: S needs a number, e.g. S1");
  EXPECT_EQ(parse_error("dx"), "dx: steps 'x' is not a whole number");
  EXPECT_EQ(parse_error("d16777217"), "d16777217: path too long: at most 16777216 steps per axis");
  EXPECT_EQ(parse_error("f30000"), "f30000: frequency too high: use at most 20000 Hz");
  EXPECT_EQ(parse_error("F9"), "F9: frequency too low: use at least 10 Hz");
  EXPECT_EQ(parse_error("r1001"), "r1001: ramp too long: use at most 1000 ms");
  EXPECT_EQ(parse_error("r-1"), "r-1: ramp -1 out of range: use 0 to 1000 ms");
  EXPECT_EQ(parse_error("g1"), "g1: G takes no argument");
  EXPECT_EQ(parse_error("m"), "m: M needs a direction: M+ or M-");
  EXPECT_EQ(parse_error("m+ x"), "m+ x: time 'x' is not a whole number");
  EXPECT_EQ(parse_error("a200,500"), "a200,500: A needs 3 numbers, e.g. A200,500,20");
  EXPECT_EQ(parse_error("a200,50000,20"), "a200,50000,20: frequency too high: use at most 20000 Hz");
  EXPECT_EQ(parse_error("a200,500,0"), "a200,500,0: frequency step 0 out of range: use 1 to 20000 Hz");
  EXPECT_EQ(parse_error("o3,1"), "o3,1: signal 3: use 1 (pin 1) or 2 (pin 14)");
  EXPECT_EQ(parse_error("o1,2"), "o1,2: level 2: use 1 (on) or 0 (off)");
  EXPECT_EQ(parse_error("k0"), "k0: key code 0 out of range: use 1..127 (press) or 129..255 (release)");
  EXPECT_EQ(parse_error("t-5"), "t-5: time -5 out of range: use 0 ms or more");
}

TEST(Language, Lines) {
  const auto v = parse_line("s2; d500 ;f1000  # comment; g");
  ASSERT_EQ(v.size(), 3u);
  EXPECT_EQ(v[0].what, verb::select);
  EXPECT_EQ(v[1].args, std::vector<long>{500});
  EXPECT_EQ(v[2].what, verb::frequency);
  EXPECT_TRUE(parse_line("   ").empty());
  EXPECT_TRUE(parse_line("# only a comment").empty());
  EXPECT_TRUE(parse_line(";;").empty());
  EXPECT_THROW(parse_line("s1; x; g"), usage_error);
}

// ---- the interpreter on a simulated port ------------------------------------------------

// A port whose moves advance a quarter of the leader's path per wait();
// a brake takes two more waits, a long wait() runs to the end like the real one.
class fake_port : public port {
 public:
  std::vector<x4step::move> loads;
  std::vector<bool> loaded_while_active;  // per load: a move ran then (a preload)
  std::vector<step_counts> started;       // the steps of each move started, in order
  int starts = 0, brakes = 0, stops = 0;
  std::vector<std::tuple<int, x4step::direction, int, long long>> endless;  // axis, dir, freq, ramp ms
  std::vector<std::pair<x4step::signal, bool>> outputs;
  std::vector<std::vector<int>> codes;
  unsigned inputs = 0x15;
  x4step::config cfg;          // as the module keeps it per port
  x4step::step_timing timing;  // the module's defaults
  int config_sets = 0, timing_sets = 0;

  void load(const x4step::move &m) override {
    refuse(m.freq_hz, m.steps[3] != 0);
    if (loaded_) throw x4step::error(x4step::make_error_code(x4step::errc::is_loaded));
    loads.push_back(m);
    loaded_while_active.push_back(s_.active);
    loaded_ = true;
  }
  void start() override {
    if (!loaded_) throw x4step::error(x4step::make_error_code(x4step::errc::not_loaded));
    if (s_.active) throw x4step::error(x4step::make_error_code(x4step::errc::is_active));
    loaded_ = false;
    starts++;
    begin(false);
    target_ = steps_of(loads.back());
    started.push_back(target_);
  }
  void brake() override {
    if (!s_.active) throw x4step::error(x4step::make_error_code(x4step::errc::not_active));
    brakes++;
    if (!braking_) braking_ = 2;
  }
  void stop() override {
    if (!s_.active) throw x4step::error(x4step::make_error_code(x4step::errc::not_active));
    stops++;
    s_.active = false;
  }
  void move_endless(x4step::axis a, x4step::direction dir, int freq_hz, milliseconds ramp) override {
    const int axis = a.number();
    refuse(freq_hz, axis == 4);
    endless.emplace_back(axis, dir, freq_hz, ramp.count());
    begin(true);
    axis_ = axis;
    sign_ = dir == x4step::direction::positive ? 1 : -1;
  }
  x4step::status get_status() const override {
    x4step::status s = s_;
    s.inputs = inputs;
    s.loaded = loaded_;
    return s;
  }
  bool wait(milliseconds timeout) const override {
    for (int i = 0; i < (timeout >= milliseconds(1000) ? 100 : 1) && s_.active; i++) advance();
    return !s_.active;
  }
  void set_output(x4step::signal s, bool high) override { outputs.emplace_back(s, high); }
  void set_brake_codes(const std::vector<int> &c) override { codes.push_back(c); }
  void set_config(const x4step::config &c) override {
    if (s_.active) throw x4step::error(x4step::make_error_code(x4step::errc::is_active));
    cfg = c;
    config_sets++;
  }
  x4step::config get_config() const override { return cfg; }
  void set_step_timing(const x4step::step_timing &t) override {
    for (const auto ns : {t.pulse(), t.space(), t.dir_setup(), t.dir_hold()})
      if (ns.count() < 0 || ns.count() > 1000000)
        throw x4step::error(x4step::make_error_code(x4step::errc::param_fail));
    if (t.pulse().count() && t.pulse().count() < 1000)
      throw x4step::error(x4step::make_error_code(x4step::errc::param_fail));
    if (s_.active) throw x4step::error(x4step::make_error_code(x4step::errc::is_active));
    timing = t;
    timing_sets++;
  }
  x4step::step_timing get_step_timing() const override { return timing; }

  // Positioning: an axis' own move goes a quarter of its way per
  // wait_axes() (a long wait runs it to the end), or stops at its E+
  // switch; a brake takes two more waits, a step each; each phase of a
  // reference run takes two waits; phase 2 ends at 0, synchronized.
  std::array<x4step::profile, x4step::axes> profiles{};
  x4step::switches sw;
  std::array<std::optional<long>, x4step::axes> e_plus{};  // where each axis' E+ switch is
  bool ref_found = true;                                   // reference runs find their switch
  std::vector<std::tuple<unsigned, coordinates, bool>> gotos;
  std::vector<std::pair<int, x4step::homing>> homes;
  std::vector<std::pair<unsigned, x4step::halt_mode>> halts;
  int profile_sets = 0, switch_sets = 0;

  void set_profile(x4step::axis a, const x4step::profile &p) override {
    const int axis = a.number();
    if (x4step::check(p) != x4step::errc::ok)
      throw x4step::error(x4step::make_error_code(x4step::errc::param_fail));
    if (ax_.axis.at(axis - 1).running) throw x4step::error(x4step::make_error_code(x4step::errc::is_active));
    profiles[axis - 1] = p;
    profile_sets++;
  }
  x4step::profile get_profile(x4step::axis a) const override { return profiles.at(a.index()); }
  void move_to(x4step::axis_set axes, const coordinates &targets, bool relative) override {
    const unsigned axis_mask = axes.mask();
    refuse(1000, axis_mask & 8u);
    if (runs(axis_mask)) throw x4step::error(x4step::make_error_code(x4step::errc::is_active));
    gotos.emplace_back(axis_mask, targets, relative);
    for (int i = 0; i < x4step::axes; i++) {
      if (!(axis_mask >> i & 1u)) continue;
      x4step::axis_status &a = ax_.axis[i];
      own_[i] = {a.position, relative ? a.position + targets[i] : targets[i], 0, 0, 0, {}};
      a.error = 0;
      a.running = own_[i].to != a.position;
    }
  }
  void home(x4step::axis ax, const x4step::homing &h) override {
    const int axis = ax.number();
    if (!sw.ref.at(axis - 1)) throw x4step::error(x4step::make_error_code(x4step::errc::param_fail));
    homes.emplace_back(axis, h);
    x4step::axis_status &a = ax_.axis[axis - 1];
    own_[axis - 1] = {a.position, a.position, 0, 0, h.phase1() ? 1 : 2, h};
    a.error = 0;
    a.running = true;
    a.ref1 = h.phase1();
    a.ref2 = !h.phase1();
  }
  void halt(x4step::axis_set axes, x4step::halt_mode how) override {
    const unsigned axis_mask = axes.mask();
    if (!runs(axis_mask)) throw x4step::error(x4step::make_error_code(x4step::errc::not_active));
    halts.emplace_back(axis_mask, how);
    for (int i = 0; i < x4step::axes; i++) {
      x4step::axis_status &a = ax_.axis[i];
      if (!(axis_mask >> i & 1u) || !a.running) continue;
      if (how == x4step::halt_mode::brake) {
        own_[i].braking = 2;
      } else {
        a.running = a.ref1 = a.ref2 = false;
        a.synced = false;
      }
    }
  }
  void set_position(x4step::axis ax, long position) override {
    x4step::axis_status &a = ax_.axis.at(ax.index());
    a.running = a.ref1 = a.ref2 = false;
    a.position = position;
    a.synced = true;
  }
  void set_switches(const x4step::switches &s) override {
    if (runs(all_axes.mask())) throw x4step::error(x4step::make_error_code(x4step::errc::is_active));
    sw = s;
    switch_sets++;
  }
  x4step::switches get_switches() const override { return sw; }
  x4step::axes_status get_axes() const override {
    x4step::axes_status a = ax_;
    a.inputs = inputs;
    return a;
  }
  bool wait_axes(x4step::axis_set axes, milliseconds timeout) const override {
    const unsigned axis_mask = axes.mask();
    for (int i = 0; i < (timeout >= milliseconds(1000) ? 100 : 1) && runs(axis_mask); i++) advance_axes();
    return !runs(axis_mask);
  }
  // Where the axes are; for tests to place them.
  x4step::axes_status &axes() { return ax_; }

 private:
  struct own_move {
    long from, to;
    int n, braking;
    int phase;  // of a reference run, else 0
    x4step::homing h;
  };

  bool runs(unsigned axis_mask) const {
    for (int i = 0; i < x4step::axes; i++)
      if ((axis_mask >> i & 1u) && ax_.axis[i].running) return true;
    return false;
  }
  void advance_axes() const {
    for (int i = 0; i < x4step::axes; i++) {
      x4step::axis_status &a = ax_.axis[i];
      own_move &m = own_[i];
      if (!a.running) continue;
      if (m.braking) {
        a.position += m.to >= m.from ? 1 : -1;
        a.running = --m.braking > 0;
      } else if (m.phase) {
        if (++m.n < 2) continue;
        const int ref_bit = 1 << (sw.ref[i] - 1);
        if (!ref_found) {
          const long travel = static_cast<long>(m.h.max_travel());
          a.position += (m.phase == 1 ? m.h.phase1_speed() : m.h.phase2_speed()) > 0 ? travel : -travel;
          a.error = x4step::axis_error::ref_travel;
          a.running = a.ref1 = a.ref2 = false;
        } else if (m.phase == 1) {
          a.position -= 300;
          ax_.switches_active |= ref_bit;  // found
          a.ref1 = false;
          a.ref2 = m.h.phase2();
          a.running = m.h.phase2();
          m = {0, 0, 0, 0, 2, m.h};
        } else {
          ax_.switches_active &= ~ref_bit;  // left again
          a.position = 0;
          a.synced = true;
          a.running = a.ref2 = false;
        }
      } else {
        const long next = m.from + (m.to - m.from) * std::min(++m.n, 4) / 4;
        if (e_plus[i] && m.to > m.from && next >= *e_plus[i]) {
          a.position = *e_plus[i];
          a.error = x4step::axis_error::limit_pos;
          a.running = false;
        } else {
          a.position = next;
          a.running = m.n < 4;
        }
      }
    }
  }

  // The module's checks of the settings (x4_engine_load, x4_engine_endless).
  void refuse(int freq_hz, bool axis4) const {
    const long long period = 1000000000LL / freq_hz;
    const bool phase = cfg.mode() != x4step::output_mode::clock_dir;
    if (!phase && (timing.pulse().count() ? timing.pulse().count() + timing.space().count() > period
                                          : timing.space().count() > period / 2))
      throw x4step::error(x4step::make_error_code(x4step::errc::freq_too_high));
    if (phase && axis4) throw x4step::error(x4step::make_error_code(x4step::errc::param_fail));
  }

  void begin(bool endless) {
    s_.steps = {};
    s_.active = true;
    endless_ = endless;
    braking_ = 0;
    n_ = 0;
  }
  void advance() const {
    if (braking_) {
      s_.active = --braking_ > 0;
      return;
    }
    n_++;
    if (endless_) {
      s_.steps[axis_ - 1] += sign_ * 10;
      return;
    }
    for (int i = 0; i < x4step::axes; i++) s_.steps[i] = target_[i] * std::min(n_, 4) / 4;
    s_.active = n_ < 4;
  }

  // wait() is const in port, as in x4step::controller; the simulation moves on in it.
  mutable x4step::status s_;
  mutable x4step::axes_status ax_;
  mutable std::array<own_move, x4step::axes> own_{};
  mutable int braking_ = 0, n_ = 0;
  step_counts target_{};
  bool loaded_ = false, endless_ = false;
  int axis_ = 1, sign_ = 1;
};

// Output into a string; keys from a script, one per read_key.
class fake_console : public console {
 public:
  explicit fake_console(bool keyboard = false) : keyboard_(keyboard) {}
  std::deque<key> keys;
  std::ostringstream text;
  std::ostream &out() override { return text; }
  bool live() const override { return false; }
  bool has_keyboard() const override { return keyboard_; }
  key read_key(milliseconds) override {
    if (keys.empty()) return key::none;
    const key k = keys.front();
    keys.pop_front();
    return k;
  }

 private:
  bool keyboard_;
};

void run_lines(interpreter &in, const std::string &script) {
  std::istringstream lines(script);
  for (std::string line; std::getline(lines, line);)
    for (const auto &c : parse_line(line)) in.execute(c);
}

TEST(Interpreter, KeepsValuesPerAxis) {
  fake_console con;
  interpreter in(con, nullptr, true);
  EXPECT_EQ(in.prompt(), "1-> ");
  run_lines(in, "d100\nf2000\nr20\ns3\nd-50\nF500");
  EXPECT_EQ(in.prompt(), "3-> ");
  EXPECT_EQ(in.values(1).distance, 100);
  EXPECT_EQ(in.values(1).freq_hz, 2000);
  EXPECT_EQ(in.values(1).ramp_ms, 20);
  EXPECT_EQ(in.values(3).distance, -50);
  EXPECT_EQ(in.values(3).freq_hz, 500);
  EXPECT_EQ(in.values(3).ramp_ms, 50);  // default
  EXPECT_EQ(in.values(2).distance, 0);
}

// The manual's second example: G runs at the leader's frequency and ramp.
TEST(Interpreter, GoUsesTheLeadersFrequencyAndRamp) {
  fake_console con;
  fake_port p;
  interpreter in(con, &p, true);
  run_lines(in, "s1\nd1000\nf10000\nr100\ns2\nd500\ns3\nd100\ng");
  ASSERT_EQ(p.loads.size(), 1u);
  EXPECT_EQ(p.loads[0].steps, (std::array<long, 4>{1000, 500, 100, 0}));
  EXPECT_EQ(p.loads[0].freq_hz, 10000);
  EXPECT_EQ(p.loads[0].ramp, milliseconds(100));
  EXPECT_EQ(p.starts, 1);
  EXPECT_TRUE(contains(con.text.str(), "G: 1000 500 100 0 at 10000 Hz, ramp 100 ms (leader axis 1)\n"));
  EXPECT_TRUE(contains(con.text.str(), "done: 1000 500 100 0\n"));

  // A longer negative path leads; equal paths: the first axis.
  run_lines(in, "s4\nd-2000\nf3000\nr10");
  EXPECT_EQ(in.leader(), 4);
  EXPECT_EQ(in.go_move().freq_hz, 3000);
  run_lines(in, "d1000");
  EXPECT_EQ(in.leader(), 1);
}

TEST(Interpreter, InfoNamesTheLeader) {
  fake_console con;
  interpreter in(con, nullptr, false);
  run_lines(in, "i");
  EXPECT_TRUE(contains(con.text.str(), "No axis has a distance yet")) << con.text.str();
  run_lines(in, "s2\nd-700\nf4000\nr40\ns1\nd300\ni");
  const std::string s = con.text.str();
  EXPECT_TRUE(contains(s, "> 1        300     1000       50\n")) << s;
  EXPECT_TRUE(contains(s, "  2       -700     4000       40  leader\n")) << s;
  EXPECT_TRUE(contains(s, "axis 2, 4000 Hz, 40 ms")) << s;
}

TEST(Interpreter, NothingMovesAfterAnError) {
  fake_console con;
  fake_port p;
  interpreter in(con, &p, true);
  run_lines(in, "d100\nf20");  // the default ramp, 50 ms, is too long for 20 Hz
  try {
    run_lines(in, "g");
    FAIL() << "G ran";
  } catch (const usage_error &e) {
    EXPECT_STREQ(e.what(),
                 "G: ramp too long for the frequency: ramp (ms) must not exceed frequency (Hz) "
                 "(G uses the leader axis 1: F20 R50)");
  }
  EXPECT_THROW(run_lines(in, "s2\ng"), usage_error);      // axis 1 still leads
  EXPECT_THROW(run_lines(in, "s1\nd0\ng"), usage_error);  // no steps
  EXPECT_THROW(run_lines(in, "s1\nd10\nr30\nt"), usage_error);
  EXPECT_THROW(run_lines(in, "a10,100,10"), usage_error);
  EXPECT_THROW(run_lines(in, "m+"), usage_error);
  EXPECT_TRUE(p.loads.empty());
  EXPECT_EQ(p.starts, 0);
  EXPECT_TRUE(p.endless.empty());
}

TEST(Interpreter, EscBrakesAndAHaltedGoFailsOnlyInScripts) {
  fake_console con(true);
  fake_port p;
  interpreter in(con, &p, false);
  con.keys = {key::none, key::esc};
  run_lines(in, "d1000\ng");
  EXPECT_EQ(p.brakes, 1);
  EXPECT_TRUE(contains(con.text.str(), "halted (ESC) at 500 of 1000 steps: 500 0 0 0\n")) << con.text.str();

  fake_console script_con;
  interpreter strict(script_con, &p, true);
  script_con.keys = {key::brake_request};
  try {
    run_lines(strict, "d1000\ng");
    FAIL() << "no failure";
  } catch (const failure &e) {
    EXPECT_STREQ(e.what(), "G: halted (brake request) at 250 of 1000 steps: 250 0 0 0");
  }
}

TEST(Interpreter, CtrlCTwiceStops) {
  fake_console con(true);
  fake_port p;
  interpreter in(con, &p, false);
  con.keys = {key::interrupt, key::interrupt};  // the second one while braking
  run_lines(in, "d1000\ng");
  EXPECT_EQ(p.brakes, 1);
  EXPECT_EQ(p.stops, 1);
  EXPECT_TRUE(contains(con.text.str(), "halted (Ctrl-C, stopped) at 250 of 1000 steps")) << con.text.str();
}

TEST(Interpreter, EndlessMoves) {
  fake_console con;
  fake_port p;
  interpreter in(con, &p, true);
  con.keys = {key::none, key::none, key::brake_request};
  run_lines(in, "s3\nf10000\nr500\nm-");
  ASSERT_EQ(p.endless.size(), 1u);
  EXPECT_EQ(p.endless[0], std::make_tuple(3, x4step::direction::negative, 10000, 500LL));
  EXPECT_EQ(p.brakes, 1);
  EXPECT_TRUE(contains(con.text.str(), "M-: axis 3 endless at 10000 Hz, ramp 500 ms")) << con.text.str();
  EXPECT_TRUE(contains(con.text.str(), "halted (brake request): 0 0 -30 0")) << con.text.str();

  run_lines(in, "m+ 0");  // a time: brakes by itself
  EXPECT_EQ(std::get<1>(p.endless.at(1)), x4step::direction::positive);
  EXPECT_EQ(p.brakes, 2);
  EXPECT_TRUE(contains(con.text.str(), "halted (time up)")) << con.text.str();
}

TEST(Interpreter, BackAndForth) {
  fake_console con;
  fake_port p;
  interpreter in(con, &p, true);
  // Three full moves (the fake's moves read three keys each), then ESC in the fourth.
  con.keys.assign(3 * 3, key::none);
  con.keys.push_back(key::esc);
  run_lines(in, "s2\nd2000\nf5000\nr100\nt");
  ASSERT_EQ(p.loads.size(), 4u);
  EXPECT_EQ(p.loads[0].steps[1], 2000);
  EXPECT_EQ(p.loads[1].steps[1], -2000);
  EXPECT_EQ(p.loads[2].steps[1], 2000);
  EXPECT_EQ(p.loads[3].steps[1], -2000);
  EXPECT_EQ(p.loads[0].freq_hz, 5000);
  EXPECT_EQ(p.loads[0].ramp, milliseconds(100));
  EXPECT_TRUE(contains(con.text.str(), "T: 3 moves, then halted (ESC)")) << con.text.str();
}

// ---- move --then: a sequence of moves, each preloaded while the one before runs ----------

std::vector<x4step::move> manual_example() {
  const milliseconds ramp(50);
  return {{{1000, 800, 600, 400}, 1000, ramp}, {{-1000, -800, -600, -400}, 1000, ramp}};
}

TEST(Sequence, PreloadsWhileThePreviousMoveRuns) {
  fake_console con;
  fake_port p;
  auto moves = manual_example();
  moves.push_back({{0, 0, 5, 0}, 1000, milliseconds(50)});
  start_moves(p, moves);
  // X4Load, X4Start, X4Load while the first move runs.
  EXPECT_EQ(p.starts, 1);
  ASSERT_EQ(p.loads.size(), 2u);
  EXPECT_TRUE(p.get_status().active);
  EXPECT_TRUE(p.get_status().loaded);

  std::vector<size_t> ended;
  const auto done = follow_moves(p, con, moves, [&](size_t i, const outcome &o) {
    ended.push_back(i);
    EXPECT_TRUE(o.completed) << i;
    // The next move runs already when the end of this one is reported, the one after it is loaded.
    EXPECT_EQ(p.starts, static_cast<int>(std::min(i + 2, moves.size()))) << i;
    EXPECT_EQ(p.get_status().active, i + 1 < moves.size()) << i;
    EXPECT_EQ(p.get_status().loaded, i + 2 < moves.size()) << i;
  });
  EXPECT_EQ(ended, (std::vector<size_t>{0, 1, 2}));
  ASSERT_EQ(done.size(), 3u);
  for (size_t i = 0; i < done.size(); i++) {
    EXPECT_TRUE(done[i].completed) << i;
    EXPECT_EQ(done[i].end.steps, steps_of(moves[i])) << i;
  }
  ASSERT_EQ(p.loads.size(), 3u);
  for (size_t i = 0; i < 3; i++) {
    EXPECT_EQ(p.loads[i].steps, moves[i].steps) << i;
    EXPECT_EQ(p.loads[i].freq_hz, 1000) << i;
    EXPECT_EQ(p.loads[i].ramp, milliseconds(50)) << i;
  }
  // Only the first load found the port idle; every other came while a move ran.
  EXPECT_EQ(p.loaded_while_active, (std::vector<bool>{false, true, true}));
  EXPECT_EQ(p.started,
            (std::vector<step_counts>{steps_of(moves[0]), steps_of(moves[1]), steps_of(moves[2])}));
  EXPECT_EQ(p.brakes, 0);
  EXPECT_EQ(p.get_status().steps, steps_of(moves[2]));
  EXPECT_FALSE(p.get_status().active);
}

TEST(Sequence, OneMoveIsAPlainMove) {
  fake_console con;
  fake_port p;
  const std::vector<x4step::move> one{{{30, -20, 0, 0}, 2000, milliseconds(10)}};
  start_moves(p, one);
  const auto done = follow_moves(p, con, one);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_TRUE(done[0].completed);
  EXPECT_EQ(p.loads.size(), 1u);
  EXPECT_EQ(p.starts, 1);
  EXPECT_EQ(describe(done[0], steps_of(one[0])), "done: 30 -20 0 0");
}

// A braked move ends the sequence: the moves after it never start.
TEST(Sequence, ABrakedMoveEndsIt) {
  for (const key k : {key::esc, key::brake_request, key::interrupt, key::stop_request}) {
    fake_console con(true);
    fake_port p;
    auto moves = manual_example();
    moves.push_back({{7, 0, 0, 0}, 1000, milliseconds(50)});
    con.keys.assign(3, key::none);  // the first move: four waits, a key read after each of the first three
    con.keys.push_back(key::none);
    con.keys.push_back(k);  // halfway through the second move
    start_moves(p, moves);
    const auto done = follow_moves(p, con, moves);
    ASSERT_EQ(done.size(), 2u) << static_cast<int>(k);
    EXPECT_TRUE(done[0].completed);
    EXPECT_FALSE(done[1].completed);
    EXPECT_FALSE(done[1].halted_by.empty());
    EXPECT_EQ(p.starts, 2);  // the third was loaded, but never started
    EXPECT_EQ(p.loads.size(), 3u);
    EXPECT_EQ(p.started, (std::vector<step_counts>{steps_of(moves[0]), steps_of(moves[1])}));
    EXPECT_EQ(p.brakes + p.stops, 1);
    EXPECT_FALSE(p.get_status().active);
    EXPECT_NE(p.get_status().steps, steps_of(moves[1]));
  }
}

// A port on which a brake finds the move at its end (the module says "not active")
// while the move still completes: the brake request came too late for the move,
// not for the sequence.
class late_brake_port : public fake_port {
 public:
  void brake() override { throw x4step::error(x4step::make_error_code(x4step::errc::not_active)); }
};

TEST(Sequence, ALateBrakeRequestStillEndsIt) {
  fake_console con;
  late_brake_port p;
  const auto moves = manual_example();
  con.keys = {key::none, key::none, key::brake_request};
  start_moves(p, moves);
  const auto done = follow_moves(p, con, moves);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_TRUE(done[0].completed);
  EXPECT_EQ(done[0].late_halt, "brake request");
  EXPECT_TRUE(done[0].halted_by.empty());
  EXPECT_EQ(p.starts, 1);
}

// A later move the port's settings refuse is found before anything moves.
TEST(Sequence, RefusedLaterMoveMovesNothing) {
  fake_port p;
  p.cfg.mode(x4step::output_mode::smc_phase);
  const std::vector<x4step::move> moves{{{3, 0, 0, 0}, 1000, milliseconds(0)},
                                        {{0, 0, 0, 5}, 1000, milliseconds(0)}};
  try {
    start_moves(p, moves);
    FAIL() << "started";
  } catch (const failure &e) {
    EXPECT_TRUE(contains(e.what(), "axis 4 cannot move in smc-phase mode")) << e.what();
  }
  EXPECT_TRUE(p.loads.empty());
  EXPECT_EQ(p.starts, 0);
}

// Should a preload be refused all the same, the running move is braked, not left alone.
TEST(Sequence, RefusedPreloadBrakesTheRunningMove) {
  fake_console con;
  fake_port p;
  auto moves = manual_example();
  moves.push_back({{0, 0, 0, 9}, 1000, milliseconds(50)});
  start_moves(p, moves);
  p.cfg.mode(x4step::output_mode::smc_phase);  // changed behind x4ctl's back
  EXPECT_THROW(follow_moves(p, con, moves), failure);
  EXPECT_EQ(p.starts, 2);
  EXPECT_EQ(p.brakes, 1);
  EXPECT_FALSE(p.get_status().active);
}

TEST(Interpreter, SweepAlternatesDirection) {
  fake_console con;
  fake_port p;
  interpreter in(con, &p, true);
  run_lines(in, "s2\nd1000\nr0\na200,260,20");
  ASSERT_EQ(p.loads.size(), 4u);
  const int freqs[] = {200, 220, 240, 260};
  for (int i = 0; i < 4; i++) {
    EXPECT_EQ(p.loads[i].freq_hz, freqs[i]);
    EXPECT_EQ(p.loads[i].steps[1], i % 2 ? -1000 : 1000);
    EXPECT_EQ(p.loads[i].ramp, milliseconds(0));
  }
  EXPECT_TRUE(contains(con.text.str(), "A: 220 Hz -1000 steps done\n")) << con.text.str();
  p.loads.clear();
  run_lines(in, "a500,300,150");  // downwards: 500, 350
  ASSERT_EQ(p.loads.size(), 2u);
  EXPECT_EQ(p.loads[1].freq_hz, 350);
}

TEST(Interpreter, InputsOutputsKeys) {
  fake_console con;
  fake_port p;
  interpreter in(con, &p, true);
  run_lines(in, "e\no2,1\no1,0\nk28,156\nk");
  const std::string s = con.text.str();
  EXPECT_TRUE(contains(s, "E: pin15=1 pin13=0 pin12=1 pin10=0 pin11=1\n")) << s;
  ASSERT_EQ(p.outputs.size(), 2u);
  EXPECT_EQ(p.outputs[0], std::make_pair(x4step::signal::two, true));
  EXPECT_EQ(p.outputs[1], std::make_pair(x4step::signal::one, false));
  ASSERT_EQ(p.codes.size(), 2u);
  EXPECT_EQ(p.codes[0], (std::vector<int>{28, 156}));
  EXPECT_TRUE(p.codes[1].empty());
  EXPECT_TRUE(contains(s, "K: brake keys 28 156 and ESC\n")) << s;
  EXPECT_TRUE(contains(s, "K: only ESC brakes\n")) << s;
}

TEST(Interpreter, CursorNeedsAKeyboard) {
  fake_console con(false);
  fake_port p;
  interpreter in(con, &p, true);
  try {
    run_lines(in, "c");
    FAIL() << "C ran";
  } catch (const usage_error &e) {
    EXPECT_STREQ(e.what(), "C: C needs a terminal for the cursor keys; in scripts use M+ or M- with a time");
  }
}

TEST(Interpreter, CursorMovesWhileHeld) {
  fake_console con(true);
  fake_port p;
  interpreter in(con, &p, false);
  // RIGHT, held (repeats), then LEFT: brake, the other way; ESC ends.
  con.keys = {key::right, key::right, key::right, key::left, key::esc};
  run_lines(in, "s2\nf800\nr10\nc");
  ASSERT_EQ(p.endless.size(), 2u);
  EXPECT_EQ(p.endless[0], std::make_tuple(2, x4step::direction::positive, 800, 10LL));
  EXPECT_EQ(std::get<1>(p.endless[1]), x4step::direction::negative);
  EXPECT_EQ(p.brakes, 2);  // LEFT brakes the RIGHT jog, ESC the LEFT one
  EXPECT_TRUE(contains(con.text.str(), "C: axis 2 ended 0 steps from where C began")) << con.text.str();
}

TEST(Interpreter, QuitAndHelp) {
  fake_console con;
  interpreter in(con, nullptr, false);
  EXPECT_FALSE(in.execute(parse_command("Q")));
  EXPECT_TRUE(in.execute(parse_command("?")));
  EXPECT_EQ(con.text.str(), language_help());
  for (const char *w : {"Sx", "Dx", "Fx", "Rx", "G ", "I ", "M+", "M-", "C ", "Ax,y,z", "T ", "E ", "H, ?",
                        "Q ", "leader", "M+ 500"})
    EXPECT_TRUE(contains(language_help(), w)) << w;
}

TEST(Interpreter, CheckOnlyTouchesNothing) {
  fake_console con;
  interpreter in(con, nullptr, true);
  run_lines(in, "s1\nd100\ng\nm+\nt 10\na100,200,50\ne\no1,1\nk1\nw10000");
  EXPECT_EQ(con.text.str(), "");
}

// ---- timing and mode on the simulated port ---------------------------------------------

TEST(Settings, TimingShowsWithoutChanging) {
  fake_port p;
  std::ostringstream out;
  timing_command(p, parse({"timing"}), out);
  EXPECT_EQ(p.timing_sets, 0);
  EXPECT_EQ(out.str(),
            "device       /dev/x4step0\n"
            "pulse        0 ns (symmetric clock)\n"
            "space        0 ns\n"
            "dir setup    100000 ns\n"
            "dir hold     0 ns\n"
            "max freq     20000 Hz\n");
}

TEST(Settings, TimingChangesOnlyTheTimesGiven) {
  fake_port p;
  p.timing.dir_hold(std::chrono::nanoseconds(7000));
  std::ostringstream out;
  timing_command(p, parse({"-p", "2", "timing", "--pulse", "10000", "--space", "90000"}), out);
  EXPECT_EQ(p.timing_sets, 1);
  EXPECT_EQ(p.timing.pulse(), std::chrono::nanoseconds(10000));
  EXPECT_EQ(p.timing.space(), std::chrono::nanoseconds(90000));
  EXPECT_EQ(p.timing.dir_setup(), std::chrono::nanoseconds(100000));  // kept
  EXPECT_EQ(p.timing.dir_hold(), std::chrono::nanoseconds(7000));     // kept
  EXPECT_TRUE(contains(out.str(), "device       /dev/x4step1\n")) << out.str();
  EXPECT_TRUE(contains(out.str(), "pulse        10000 ns\n")) << out.str();
  EXPECT_TRUE(contains(out.str(), "dir hold     7000 ns\n")) << out.str();
  EXPECT_TRUE(contains(out.str(), "max freq     10000 Hz\n")) << out.str();

  std::ostringstream json;
  timing_command(p, parse({"timing", "--setup", "0", "--json"}), json);
  EXPECT_EQ(
      json.str(),
      "{\"schema\":1,\"device\":\"/dev/x4step0\",\"pulse_ns\":10000,\"space_ns\":90000,\"dir_setup_ns\":0,"
      "\"dir_hold_ns\":7000,\"mode\":\"clock-dir\",\"max_freq_hz\":10000}\n");
  EXPECT_EQ(p.timing_sets, 2);
  EXPECT_EQ(p.timing.pulse(), std::chrono::nanoseconds(10000));
}

TEST(Settings, ModeKeepsTheRestOfTheConfig) {
  fake_port p;
  p.cfg.clock_invert(x4step::axis::x | x4step::axis::z).dir_invert(x4step::axis::y).keys_swallow(true);
  std::ostringstream out;
  mode_command(p, parse({"mode"}), out);
  EXPECT_EQ(p.config_sets, 0);
  EXPECT_EQ(out.str(), "clock-dir: clock and direction signals per axis (X4Step)\n");
  out.str("");
  mode_command(p, parse({"mode", "smc-phase"}), out);
  EXPECT_EQ(p.config_sets, 1);
  EXPECT_EQ(p.cfg.mode(), x4step::output_mode::smc_phase);
  EXPECT_EQ(p.cfg.clock_invert(), x4step::axis::x | x4step::axis::z);
  EXPECT_EQ(p.cfg.dir_invert(), x4step::axis::y);
  EXPECT_TRUE(p.cfg.keys_swallow());
  EXPECT_EQ(out.str(), "smc-phase: SMC800/SMC1500 half-step phase drive of axes 1..3, motors off at rest\n");
  out.str("");
  mode_command(p, parse({"mode", "smc-hold"}), out);
  EXPECT_EQ(p.cfg.mode(), x4step::output_mode::smc_phase_hold);
  EXPECT_EQ(out.str().rfind("smc-hold: ", 0), 0u) << out.str();
  out.str("");
  mode_command(p, parse({"mode"}), out);
  EXPECT_EQ(out.str().rfind("smc-hold: ", 0), 0u) << out.str();
  EXPECT_EQ(p.config_sets, 2);
}

TEST(Settings, PhaseModeRefusesAxis4Clearly) {
  fake_console con;
  fake_port p;
  p.cfg.mode(x4step::output_mode::smc_phase);
  interpreter in(con, &p, true);
  run_lines(in, "s1\nd3\nr0\ns2\nd-2\ng");  // axes 1..3 move
  EXPECT_EQ(p.starts, 1);
  EXPECT_TRUE(contains(con.text.str(), "done: 3 -2 0 0\n")) << con.text.str();
  try {
    run_lines(in, "s4\nd5\ng");
    FAIL() << "axis 4 moved";
  } catch (const failure &e) {
    EXPECT_STREQ(e.what(),
                 "axis 4 cannot move in smc-phase mode: the SMC800/SMC1500 boards drive axes 1 to 3 "
                 "('x4ctl mode clock-dir' for clock and direction signals)");
  }
  p.cfg.mode(x4step::output_mode::smc_phase_hold);
  try {
    start_endless(p, x4step::axis::a, x4step::direction::negative, 1000, milliseconds(0));
    FAIL() << "axis 4 jogged";
  } catch (const failure &e) {
    EXPECT_TRUE(contains(e.what(), "axis 4 cannot move in smc-hold mode")) << e.what();
  }
  EXPECT_EQ(p.starts, 1);
  EXPECT_TRUE(p.endless.empty());
  p.cfg.mode(x4step::output_mode::clock_dir);
  load_move(p, x4step::move{{0, 0, 0, 5}, 1000, milliseconds(0)});  // fine with clock and direction
  EXPECT_EQ(p.loads.size(), 2u);
}

TEST(Settings, FrequencyTooHighForTheTiming) {
  fake_console con;
  fake_port p;
  p.timing.pulse(std::chrono::nanoseconds(100000));
  p.timing.space(std::chrono::nanoseconds(100000));
  interpreter in(con, &p, true);
  run_lines(in, "d10\nf5000\nr0\ng");  // 200 us: just fits
  EXPECT_EQ(p.starts, 1);
  const std::string why =
      "frequency too high for the step timing: 5001 Hz, but pulse 100000 ns and space 100000 ns allow at "
      "most "
      "5000 Hz ('x4ctl timing' changes them)";
  try {
    run_lines(in, "f5001\ng");
    FAIL() << "moved";
  } catch (const failure &e) {
    EXPECT_EQ(e.what(), why);
  }
  try {
    start_endless(p, x4step::axis::x, x4step::direction::positive, 5001, milliseconds(0));
    FAIL() << "jogged";
  } catch (const failure &e) {
    EXPECT_EQ(e.what(), why);
  }
  // The symmetric clock: the space in half a period.
  p.timing.pulse(std::chrono::nanoseconds(0));
  p.timing.space(std::chrono::nanoseconds(250000));
  try {
    load_move(p, x4step::move{{10, 0, 0, 0}, 2001, milliseconds(0)});
    FAIL() << "loaded";
  } catch (const failure &e) {
    EXPECT_TRUE(contains(e.what(), "allow at most 2000 Hz")) << e.what();
  }
  // Pulse and space do not apply to phase patterns.
  p.cfg.mode(x4step::output_mode::smc_phase);
  load_move(p, x4step::move{{10, 0, 0, 0}, 20000, milliseconds(0)});
  EXPECT_EQ(p.loads.size(), 2u);
  // Other refusals stay the library's.
  try {
    load_move(p, x4step::move{{10, 0, 0, 0}, 1000, milliseconds(0)});
    FAIL() << "loaded twice";
  } catch (const x4step::error &e) {
    EXPECT_EQ(e.code(), x4step::errc::is_loaded);
  }
}

// ---- formatting ----------------------------------------------------------------------

TEST(Show, Texts) {
  EXPECT_EQ(steps_text({1000, -800, 0, 4}), "1000 -800 0 4");
  EXPECT_EQ(bar(50, 100, 10), "[#####-----]");
  EXPECT_EQ(bar(-100, -100, 4), "[####]");
  EXPECT_EQ(bar(0, 0, 4), "[----]");
  EXPECT_EQ(progress_line({412, 0, 0, 0}, 412, 1000),
            "      412         0         0         0 [########------------] 41%");
  EXPECT_EQ(inputs_text(0x1f), "pin15=1 pin13=1 pin12=1 pin10=1 pin11=1");
  EXPECT_EQ(inputs_text(0x02), "pin15=0 pin13=1 pin12=0 pin10=0 pin11=0");
  x4step::status st;
  st.inputs_stale = true;
  const auto now = std::chrono::steady_clock::now();
  EXPECT_EQ(stale_text(st, now), "(stale: no controller has the port; never read)");
  st.inputs_time = now - std::chrono::milliseconds(2500);
  EXPECT_EQ(stale_text(st, now), "(stale: no controller has the port; read 2.5 s ago)");
  EXPECT_EQ(key_name(1), "ESC");
  EXPECT_EQ(key_name(28), "key code 28");
  EXPECT_EQ(key_name(156), "key code 156 (release of 28)");
}

TEST(Show, Events) {
  x4step::event e;
  e.seq = 12;
  e.time = std::chrono::steady_clock::time_point(std::chrono::nanoseconds(105001234567));
  e.type = x4step::event_type::move_ended;
  e.axes = x4step::axis_set(0x3u);
  e.how = static_cast<unsigned>(x4step::end_reason::braked);
  e.position = {100, -50, 0, 0};
  EXPECT_EQ(event_text(e), "#12 105.001234 move ended: axes 1 2, braked; at 100 -50 0 0");
  EXPECT_EQ(event_json(e),
            "{\"schema\":1,\"seq\":12,\"time_ns\":105001234567,\"type\":\"move_ended\",\"axes\":[1,2],"
            "\"how\":\"braked\","
            "\"value\":0,\"ambiguous\":false,\"position\":[100,-50,0,0]}");
  e.type = x4step::event_type::brake;
  e.axes = x4step::axis_set(0xfu);
  e.how = static_cast<unsigned>(x4step::brake_source::key);
  e.value = 72;
  EXPECT_EQ(event_text(e), "#12 105.001234 brake: axes 1 2 3 4, by key code 72; at 100 -50 0 0");
  e.type = x4step::event_type::switch_hit;
  e.axes = x4step::axis_set(0x2u);
  e.how = static_cast<unsigned>(x4step::switch_kind::limit_pos);
  e.value = 3;
  e.ambiguous = true;
  EXPECT_EQ(event_text(e),
            "#12 105.001234 switch: axes 2, E+ on input 3 (pin 12), ambiguous; at 100 -50 0 0");
  EXPECT_EQ(event_json(e),
            "{\"schema\":1,\"seq\":12,\"time_ns\":105001234567,\"type\":\"switch\",\"axes\":[2],\"how\":"
            "\"limit_pos\","
            "\"value\":3,\"ambiguous\":true,\"position\":[100,-50,0,0]}");
  e = {};
  e.seq = 1;
  e.type = x4step::event_type::controller;
  e.how = static_cast<unsigned>(x4step::controller_change::released);
  EXPECT_EQ(event_text(e), "#1 0.000000 controller: released the port; at 0 0 0 0");
  // A newer module's types and how values: numbers, not guesses.
  e.type = static_cast<x4step::event_type>(17);
  e.how = 2;
  EXPECT_EQ(event_text(e), "#1 0.000000 event type 17: how 2; at 0 0 0 0");
  EXPECT_EQ(event_json(e),
            "{\"schema\":1,\"seq\":1,\"time_ns\":0,\"type\":17,\"axes\":[],\"how\":2,\"value\":0,"
            "\"ambiguous\":false,"
            "\"position\":[0,0,0,0]}");
  EXPECT_EQ(missed_text(3), "missed 3 events (the module keeps the last 256)");
  EXPECT_EQ(missed_json(1), "{\"schema\":1,\"missed\":1}");
  // The emergency halt from any reader (x4ctl brake/stop).
  e.type = x4step::event_type::brake;
  e.axes = x4step::axis::x;
  e.how = static_cast<unsigned>(x4step::brake_source::emergency);
  e.value = 1;
  EXPECT_EQ(event_text(e),
            "#1 0.000000 brake: axes 1, emergency stop (x4ctl stop/brake, any reader); at 0 0 0 0");
  EXPECT_TRUE(contains(event_json(e), "\"type\":\"brake\",\"axes\":[1],\"how\":\"emergency\",\"value\":1,"))
      << event_json(e);
}

TEST(Show, StatusJson) {
  x4step::status s;
  s.active = true;
  s.controlled = true;
  s.steps = {1, -2, 3, 0};
  s.inputs = 0x11;
  s.outputs = 0x9;
  s.last_brake_code = 1;
  s.moves_ended = 7;
  x4step::axes_status a;
  a.axis[0].position = 1200;
  a.axis[0].synced = true;
  a.axis[1].position = -7;
  a.axis[1].running = true;
  a.axis[1].velocity = 850;
  a.axis[1].ref2 = true;
  a.axis[1].cruising = true;
  a.axis[3].error = x4step::axis_error::limit_neg | x4step::axis_error::ambiguous;
  a.switches_active = 0x5;
  EXPECT_EQ(
      status_json(s, a, "/dev/x4step0"),
      "{\"schema\":1,\"device\":\"/dev/x4step0\",\"active\":true,\"loaded\":false,\"controlled\":true,"
      "\"steps\":[1,-2,3,0],\"inputs\":17,\"inputs_stale\":false,\"input_pins\":{\"15\":true,"
      "\"13\":false,\"12\":false,\"10\":false,\"11\":true},"
      "\"outputs\":9,\"signal1\":true,\"signal2\":false,\"boost\":false,\"aktiv\":true,\"last_brake_code\":1,"
      "\"moves_ended\":7,\"axes\":["
      "{\"axis\":1,\"position\":1200,\"velocity\":0,\"running\":false,\"synced\":true,\"homing\":0,"
      "\"ramp\":\"none\",\"error\":0,\"errors\":[]},"
      "{\"axis\":2,\"position\":-7,\"velocity\":850,\"running\":true,\"synced\":false,\"homing\":2,"
      "\"ramp\":\"cruise\",\"error\":0,\"errors\":[]},"
      "{\"axis\":3,\"position\":0,\"velocity\":0,\"running\":false,\"synced\":false,\"homing\":0,"
      "\"ramp\":\"none\",\"error\":0,\"errors\":[]},"
      "{\"axis\":4,\"position\":0,\"velocity\":0,\"running\":false,\"synced\":false,\"homing\":0,"
      "\"ramp\":\"none\",\"error\":12,\"errors\":[\"limit_neg\",\"ambiguous\"]}],"
      "\"switches_active\":5}");
  EXPECT_EQ(json_string("a\"b\\c\n"), "\"a\\\"b\\\\c\\u000a\"");
  const std::string text = status_text(s, a, "/dev/x4step0");
  EXPECT_TRUE(contains(text, "state        running, controlled\n")) << text;
  EXPECT_TRUE(contains(text, "braked by    ESC\n")) << text;
  EXPECT_TRUE(contains(text, "axis 1       1200, synchronized, idle\n")) << text;
  EXPECT_TRUE(
      contains(text, "axis 2       -7, not synchronized, running 850 steps/s, reference phase 2, cruising\n"))
      << text;
  EXPECT_TRUE(
      contains(text,
               "axis 4       0, not synchronized, idle, error: stopped at E-, ambiguous: the input serves "
               "other limits too\n"))
      << text;
}

TEST(Show, Positioning) {
  EXPECT_EQ(errors_text(0), "");
  EXPECT_EQ(errors_text(x4step::axis_error::ref_travel | x4step::axis_error::limit_pos),
            "reference travel exceeded, stopped at E+");
  x4step::axes_status a;
  a.axis[0].position = 5;
  a.axis[2].position = -2147483648L;
  EXPECT_EQ(positions_text(a, x4step::axis::x | x4step::axis::z), "1=5 3=-2147483648");
  EXPECT_EQ(coordinates_text(a), "5 0 -2147483648 0");
  EXPECT_EQ(input_name(0), "none");
  EXPECT_EQ(input_name(5), "input 5 (pin 11)");
  EXPECT_EQ(profile_text(x4step::axis::y, x4step::profile{}.start_speed(100).top_speed(3100).decel(0)),
            "axis         2\n"
            "v0           100 steps/s (start)\n"
            "ve           0 steps/s (stop)\n"
            "vm           3100 steps/s (maximum)\n"
            "a0           1000 steps/s^2 (ramp 3.000 s)\n"
            "ae           0 steps/s^2 (no ramp: jumps to 0 steps/s)\n");
  x4step::switches sw;
  sw.ref[0] = 3;
  sw.plus = {1, 1, 0, 0};
  sw.minus[0] = 2;
  sw.nc = 0x3;
  a.inputs = 0x06;
  a.switches_active = 0x01;
  EXPECT_EQ(limits_text(sw, a),
            "axis 1       ref input 3 (pin 12), E+ input 1 (pin 15), E- input 2 (pin 13)\n"
            "axis 2       ref none, E+ input 1 (pin 15), E- none\n"
            "axis 3       ref none, E+ none, E- none\n"
            "axis 4       ref none, E+ none, E- none\n"
            "input 1      pin 15 LOW, normally closed, active, E+ 1, E+ 2\n"
            "input 2      pin 13 HIGH, normally closed, idle, E- 1\n"
            "input 3      pin 12 HIGH, normally open, idle, ref 1\n"
            "input 4      pin 10 LOW, free (X4GetIn only)\n"
            "input 5      pin 11 LOW, free (X4GetIn only)\n");
}

TEST(Show, TimingAndMode) {
  x4step::step_timing t;
  EXPECT_EQ(max_freq_hz(t, x4step::output_mode::clock_dir), 20000);
  t.space(std::chrono::nanoseconds(30000));  // symmetric clock: 60 us periods
  EXPECT_EQ(max_freq_hz(t, x4step::output_mode::clock_dir), 16666);
  t.pulse(std::chrono::nanoseconds(1000000));
  t.space(std::chrono::nanoseconds(1000000));
  EXPECT_EQ(max_freq_hz(t, x4step::output_mode::clock_dir), 500);
  EXPECT_EQ(max_freq_hz(t, x4step::output_mode::smc_phase), 20000);
  t.pulse(std::chrono::nanoseconds(10000));
  t.space(std::chrono::nanoseconds(40000));
  EXPECT_EQ(max_freq_hz(t, x4step::output_mode::clock_dir), 20000);
  const std::string text = timing_text(t, x4step::output_mode::smc_phase_hold, "/dev/x4step3");
  EXPECT_TRUE(contains(text, "pulse        10000 ns\n")) << text;
  EXPECT_TRUE(contains(text, "max freq     20000 Hz (smc-hold mode: pulse and space do not apply)\n"))
      << text;
  EXPECT_EQ(timing_json(t, x4step::output_mode::smc_phase, "/dev/x4step3"),
            "{\"schema\":1,\"device\":\"/dev/"
            "x4step3\",\"pulse_ns\":10000,\"space_ns\":40000,\"dir_setup_ns\":100000,"
            "\"dir_hold_ns\":0,\"mode\":\"smc-phase\",\"max_freq_hz\":20000}");
  std::vector<std::string> names;
  for (const auto m : output_modes) {
    names.push_back(mode_name(m));
    EXPECT_EQ(mode_text(m).rfind(names.back() + ": ", 0), 0u) << mode_text(m);
  }
  EXPECT_EQ(names, (std::vector<std::string>{"clock-dir", "smc-phase", "smc-hold"}));
}

// ---- positioning on the simulated port -------------------------------------------------

// A console whose brake and stop requests name some axes (`x4ctl halt 2`).
class halt_console : public fake_console {
 public:
  x4step::axis_set axes = all_axes;
  x4step::axis_set requested_axes() const override { return axes; }
};

TEST(Position, ProfileShowsAndChangesOnlyWhatIsGiven) {
  fake_port p;
  p.profiles[1] = x4step::profile{};
  std::ostringstream out;
  profile_command(p, parse({"profile", "2"}), out);
  EXPECT_EQ(p.profile_sets, 0);
  EXPECT_TRUE(contains(out.str(), "axis         2\nv0           0 steps/s (start)\n")) << out.str();
  EXPECT_TRUE(contains(out.str(), "a0           1000 steps/s^2 (ramp 1.000 s)\n")) << out.str();
  out.str("");
  profile_command(p, parse({"profile", "2", "--vm", "8000", "--v0", "200"}), out);
  EXPECT_EQ(p.profile_sets, 1);
  EXPECT_EQ(p.profiles[1].start_speed(), 200u);
  EXPECT_EQ(p.profiles[1].top_speed(), 8000u);
  EXPECT_EQ(p.profiles[1].end_speed(), 0u);  // kept
  EXPECT_EQ(p.profiles[1].accel(), 1000u);   // kept
  EXPECT_TRUE(contains(out.str(), "vm           8000 steps/s (maximum)\n")) << out.str();
  EXPECT_TRUE(contains(out.str(), "a0           1000 steps/s^2 (ramp 7.800 s)\n")) << out.str();
}

TEST(Position, ProfileThatDoesNotFitChangesNothing) {
  fake_port p;
  p.profiles[0] = x4step::profile{};
  std::ostringstream out;
  try {
    profile_command(p, parse({"profile", "1", "--v0", "2000"}), out);  // above the vm the port has
    FAIL() << "set";
  } catch (const usage_error &e) {
    EXPECT_STREQ(e.what(),
                 "profile: v0 2000, ve 0, vm 1000, a0 1000, ae 1000 do not fit together: v0 and ve must not "
                 "exceed vm, and a ramp from rest to vm must last at most 3600 s (vm / a0 and vm / ae)");
  }
  EXPECT_THROW(profile_command(p, parse({"profile", "1", "--vm", "40000", "--a0", "10"}), out), usage_error);
  EXPECT_EQ(p.profile_sets, 0);
  EXPECT_EQ(out.str(), "");
}

TEST(Position, LimitsNameInputsOfOneAxis) {
  fake_port p;
  p.sw.plus[1] = 5;
  std::ostringstream out;
  limits_command(p, parse({"limits"}), out);
  EXPECT_EQ(p.switch_sets, 0);
  EXPECT_TRUE(contains(out.str(), "axis 2       ref none, E+ input 5 (pin 11), E- none\n")) << out.str();
  out.str("");
  limits_command(p, parse({"limits", "1", "--ref", "3", "--minus", "2"}), out);
  EXPECT_EQ(p.switch_sets, 1);
  EXPECT_EQ(p.sw.ref, (std::array<int, 4>{3, 0, 0, 0}));
  EXPECT_EQ(p.sw.plus, (std::array<int, 4>{0, 5, 0, 0}));  // kept
  EXPECT_EQ(p.sw.minus, (std::array<int, 4>{2, 0, 0, 0}));
  EXPECT_TRUE(contains(out.str(), "axis 1       ref input 3 (pin 12), E+ none, E- input 2 (pin 13)\n"))
      << out.str();
  limits_command(p, parse({"limits", "--nc", "2,5"}), out);
  EXPECT_EQ(p.sw.nc, 0x12u);
  EXPECT_EQ(p.sw.ref[0], 3);  // kept
  limits_command(p, parse({"limits", "1", "--ref", "none"}), out);
  EXPECT_EQ(p.sw.ref[0], 0);
  EXPECT_EQ(p.sw.nc, 0x12u);
  EXPECT_EQ(p.switch_sets, 3);
  limits_command(p, parse({"limits", "3"}), out);  // an axis alone: show
  EXPECT_EQ(p.switch_sets, 3);
}

TEST(Position, ZeroSetsAndSynchronizes) {
  fake_port p;
  p.axes().axis[0].position = 500;
  p.axes().axis[2].position = -7;
  std::ostringstream out;
  zero_command(p, parse({"zero", "1", "3"}), out);
  EXPECT_EQ(out.str(), "axis 1 at 0, synchronized\naxis 3 at 0, synchronized\n");
  out.str("");
  zero_command(p, parse({"zero", "2", "--at", "-1500"}), out);
  EXPECT_EQ(out.str(), "axis 2 at -1500, synchronized\n");
  EXPECT_EQ(coordinates_text(p.get_axes()), "0 -1500 0 0");
}

TEST(Position, GotoWaitsAndShowsTheCoordinates) {
  fake_console con;
  fake_port p;
  p.axes().axis[3].position = 40;
  std::ostringstream out;
  config c = parse({"goto", "1=1000", "2=-500"});
  coordinates want = start_goto_command(p, c, out);
  ASSERT_EQ(p.gotos.size(), 1u);
  EXPECT_EQ(std::get<0>(p.gotos[0]), 0x3u);
  EXPECT_EQ(std::get<1>(p.gotos[0]), (coordinates{1000, -500, 0, 0}));
  EXPECT_FALSE(std::get<2>(p.gotos[0]));
  finish_goto_command(p, con, c, want, out);
  EXPECT_EQ(out.str(), "goto: 1 to 1000, 2 to -500\ndone: 1000 -500 0 40\n");

  out.str("");
  c = parse({"goto", "4=-50", "1=5", "--relative"});
  want = start_goto_command(p, c, out);
  EXPECT_EQ(want, (coordinates{1005, 0, 0, -10}));
  EXPECT_TRUE(std::get<2>(p.gotos[1]));
  finish_goto_command(p, con, c, want, out);
  EXPECT_EQ(out.str(), "goto: 1 by 5 to 1005, 4 by -50 to -10\ndone: 1005 -500 0 -10\n");
}

TEST(Position, GotoRelativeWrapsAsTheCoordinates) {
  fake_port p;
  p.axes().axis[0].position = 2147483600L;
  std::ostringstream out;
  EXPECT_EQ(start_goto_command(p, parse({"goto", "1=100", "--relative"}), out)[0], -2147483596L);
}

TEST(Position, GotoStoppedByALimitFails) {
  fake_console con;
  fake_port p;
  p.e_plus[0] = 600;
  std::ostringstream out;
  const config c = parse({"goto", "1=1000", "2=300"});
  const coordinates want = start_goto_command(p, c, out);
  try {
    finish_goto_command(p, con, c, want, out);
    FAIL() << "done";
  } catch (const failure &e) {
    EXPECT_STREQ(e.what(), "axis 1: stopped at E+ at 600 (target 1000); coordinates 600 300 0 0");
  }
}

TEST(Position, GotoEscBrakesEveryAxis) {
  fake_console con;
  fake_port p;
  con.keys = {key::esc};
  std::ostringstream out;
  const config c = parse({"goto", "1=1000", "3=-1000"});
  const coordinates want = start_goto_command(p, c, out);
  try {
    finish_goto_command(p, con, c, want, out);
    FAIL() << "done";
  } catch (const failure &e) {
    EXPECT_STREQ(e.what(),
                 "axis 1 halted (ESC) at 252 (target 1000); axis 3 halted (ESC) at -252 (target -1000); "
                 "coordinates 252 0 -252 0");
  }
  ASSERT_EQ(p.halts.size(), 1u);
  EXPECT_EQ(p.halts[0], std::make_pair(0x5u, x4step::halt_mode::brake));
}

// `x4ctl halt 3` asks the goto's x4ctl to halt axis 3: axis 1 goes on to its target.
TEST(Position, HaltRequestsHaltOnlyTheAxesNamed) {
  halt_console con;
  fake_port p;
  con.axes = x4step::axis_set(0x4u);
  con.keys = {key::brake_request};
  const axes_outcome o = [&] {
    p.move_to(x4step::axis::x | x4step::axis::z, {1000, 0, 1000, 0}, false);
    return follow_axes(p, con, x4step::axis::x | x4step::axis::z);
  }();
  ASSERT_EQ(p.halts.size(), 1u);
  EXPECT_EQ(p.halts[0], std::make_pair(0x4u, x4step::halt_mode::brake));
  EXPECT_EQ(o.halted_by, "brake request");
  EXPECT_EQ(o.end.axis[0].position, 1000);
  EXPECT_EQ(o.end.axis[2].position, 252);
  // A stop request of axis 1: it stops; another request for it finds it halted.
  fake_port q;
  con.keys = {key::stop_request, key::none, key::brake_request};
  con.axes = x4step::axis_set(0x1u);
  q.move_to(x4step::axis::x | x4step::axis::z, {1000, 0, 1000, 0}, false);
  EXPECT_EQ(follow_axes(q, con, x4step::axis::x | x4step::axis::z).halted_by, "stop request");
  ASSERT_EQ(q.halts.size(), 1u);
  EXPECT_EQ(q.halts[0], std::make_pair(0x1u, x4step::halt_mode::stop));
  EXPECT_FALSE(q.get_axes().axis[0].synced);
  EXPECT_EQ(q.get_axes().axis[2].position, 1000);
  // Requests for other axes than the followed ones are not ours.
  fake_port r;
  con.keys = {key::brake_request};
  con.axes = x4step::axis_set(0x2u);
  r.move_to(x4step::axis::x, {100, 0, 0, 0}, false);
  EXPECT_EQ(follow_axes(r, con, x4step::axis::x).halted_by, "");
  EXPECT_TRUE(r.halts.empty());
}

TEST(Position, GotoInPhaseModeRefusesAxis4Clearly) {
  fake_port p;
  p.cfg.mode(x4step::output_mode::smc_phase_hold);
  std::ostringstream out;
  try {
    start_goto_command(p, parse({"goto", "4=10"}), out);
    FAIL() << "moved";
  } catch (const failure &e) {
    EXPECT_TRUE(contains(e.what(), "axis 4 cannot move in smc-hold mode")) << e.what();
  }
  EXPECT_TRUE(p.gotos.empty());
}

TEST(Position, HomeBothPhases) {
  fake_console con;
  fake_port p;
  p.sw.ref[1] = 3;
  p.axes().axis[1].position = 4711;
  std::ostringstream out;
  home_command(p, con, parse({"home", "2", "--vref1", "-2000", "--vref2", "50", "--sref", "9000"}), out);
  ASSERT_EQ(p.homes.size(), 1u);
  EXPECT_EQ(p.homes[0].first, 2);
  EXPECT_EQ(p.homes[0].second.phase1_speed(), -2000);
  EXPECT_EQ(p.homes[0].second.max_travel(), 9000ul);
  EXPECT_EQ(out.str(),
            "home: axis 2, phase 1 at -2000 steps/s, phase 2 at 50 steps/s, at most 9000 steps each\n"
            "done: axis 2 at 0, synchronized\n");
  EXPECT_TRUE(p.get_axes().axis[1].synced);
}

TEST(Position, HomePhase1Only) {
  fake_console con;
  fake_port p;
  p.sw.ref[0] = 1;
  std::ostringstream out;
  home_command(p, con, parse({"home", "1", "--phase", "1"}), out);
  EXPECT_TRUE(p.homes.at(0).second.phase1());
  EXPECT_FALSE(p.homes.at(0).second.phase2());
  EXPECT_TRUE(contains(out.str(),
                       "done: axis 1 at -300, reference switch active (phase 1; 'x4ctl home 1 --phase 2' "
                       "completes it)\n"))
      << out.str();
}

TEST(Position, HomeFailures) {
  fake_console con;
  fake_port p;
  std::ostringstream out;
  try {
    home_command(p, con, parse({"home", "3"}), out);
    FAIL() << "homed";
  } catch (const failure &e) {
    EXPECT_STREQ(e.what(),
                 "axis 3 has no reference switch: 'x4ctl limits 3 --ref INPUT' names its input (1..5)");
  }
  EXPECT_TRUE(p.homes.empty());
  p.sw.ref[2] = 2;
  p.ref_found = false;
  try {
    home_command(p, con, parse({"home", "3", "--sref", "5000"}), out);
    FAIL() << "homed";
  } catch (const failure &e) {
    EXPECT_STREQ(e.what(),
                 "axis 3: reference travel exceeded at -5000: the reference switch did not become active "
                 "(phase 1) or change again (phase 2) within 5000 steps (sref); check its input ('x4ctl "
                 "limits') and the direction (sign) of the speed");
  }
  p.ref_found = true;
  con.keys = {key::esc};
  try {
    home_command(p, con, parse({"home", "3"}), out);
    FAIL() << "homed";
  } catch (const failure &e) {
    EXPECT_STREQ(e.what(), "axis 3 halted (ESC) at -4998: not referenced");
  }
  EXPECT_FALSE(p.get_axes().axis[2].synced);
}

TEST(Term, HaltRequestsCarryTheirAxes) {
  install_signal_handlers();
  while (take_signal() != key::none) {
  }
  ASSERT_TRUE(send_request(::getpid(), false, x4step::axis_set(0x4u)));
  EXPECT_EQ(take_signal(), key::brake_request);
  EXPECT_EQ(taken_axes().mask(), 0x4u);
  ASSERT_TRUE(send_request(::getpid(), true, x4step::axis_set(0x3u)));
  EXPECT_EQ(take_signal(), key::stop_request);
  EXPECT_EQ(taken_axes().mask(), 0x3u);
  ::kill(::getpid(), SIGUSR1);  // `x4ctl brake`, or kill from a shell: every axis
  EXPECT_EQ(take_signal(), key::brake_request);
  EXPECT_EQ(taken_axes(), all_axes);
  ASSERT_TRUE(send_request(::getpid(), false, x4step::axis_set(0x1u)));
  ASSERT_TRUE(send_request(::getpid(), false, x4step::axis_set(0x8u)));  // requests add up until taken
  EXPECT_EQ(take_signal(), key::brake_request);
  EXPECT_EQ(taken_axes().mask(), 0x9u);
  EXPECT_EQ(take_signal(), key::none);
}

// ---- keys from a terminal ------------------------------------------------------------------

// The panel's jog while held: the key counts as held until no repeat has
// come for the terminal's repeat delay (first) or a repeat's gap (then).
TEST(HeldKey, LetGoAfterTheRepeatDelayOrAGapInTheRepeats) {
  using ms = std::chrono::milliseconds;
  const held_key::time_point t0{};
  held_key once(t0);  // one press: waits for the first repeat as long as a terminal delays it
  EXPECT_FALSE(once.let_go(t0 + ms(650)));
  EXPECT_FALSE(once.let_go(t0 + ms(700)));
  EXPECT_TRUE(once.let_go(t0 + ms(701)));
  held_key held(t0);  // repeats from 500 ms, every 40 ms, until 1500 ms
  for (int t = 500; t <= 1500; t += 40) {
    EXPECT_FALSE(held.let_go(t0 + ms(t))) << t;
    held.repeat(t0 + ms(t));
  }
  EXPECT_FALSE(held.let_go(t0 + ms(1500 + 100)));
  EXPECT_TRUE(held.let_go(t0 + ms(1500 + 101)));  // 0.1 s after the last repeat, not 0.7 s
  held.repeat(t0 + ms(1650));                     // a repeat once let go changes nothing
  EXPECT_TRUE(held.let_go(t0 + ms(1651)));
}

TEST(Term, DecodeKeys) {
  EXPECT_EQ(decode_key("", false).k, key::none);
  EXPECT_EQ(decode_key("\x1b", false).used, 0u);  // maybe the start of a sequence
  EXPECT_EQ(decode_key("\x1b", true).k, key::esc);
  EXPECT_EQ(decode_key("\x1b[C", false).k, key::right);
  EXPECT_EQ(decode_key("\x1b[D", false).k, key::left);
  EXPECT_EQ(decode_key("\x1bOD", false).k, key::left);
  EXPECT_EQ(decode_key("\x1b[1;2C", false).k, key::right);  // shift-right
  EXPECT_EQ(decode_key("\x1b[1;2C", false).used, 6u);
  EXPECT_EQ(decode_key("\x1b[A", false).k, key::up);
  EXPECT_EQ(decode_key("\x1bOB", false).k, key::down);
  EXPECT_EQ(decode_key("\x1b[5~", false).k, key::page_up);
  EXPECT_EQ(decode_key("\x1b[6~", false).k, key::page_down);
  EXPECT_EQ(decode_key("\x1b[6~", false).used, 4u);
  EXPECT_EQ(decode_key("\x1b[3~", false).k, key::other);  // Delete
  EXPECT_EQ(decode_key("\x1b[H", false).k, key::other);   // Home
  EXPECT_EQ(decode_key("\x1b[", false).used, 0u);
  EXPECT_EQ(decode_key("\x1bx", false).k, key::esc);
  EXPECT_EQ(decode_key("\x1bx", false).used, 1u);
  EXPECT_EQ(decode_key("\x03", false).k, key::interrupt);
  EXPECT_EQ(decode_key("q", false).k, key::other);
  EXPECT_EQ(decode_key("q", false).ch, 'q');
  EXPECT_EQ(decode_key("\r", false).ch, '\r');
  EXPECT_EQ(decode_key("\x1b[C", false).ch, 0);
  EXPECT_EQ(decode_key(" ", false).k, key::space);
  EXPECT_EQ(decode_key("+", false).k, key::plus);
  EXPECT_EQ(decode_key("=", false).k, key::plus);
  EXPECT_EQ(decode_key("-", false).k, key::minus);
}

TEST(Term, StripKeysFromTypedLines) {
  EXPECT_EQ(strip_keys("\x1b"
                       "d20"),
            "d20");  // ESC that came after the move's end
  EXPECT_EQ(strip_keys("s1\x1b[A\x1b[1;5Cd5"), "s1d5");
  EXPECT_EQ(strip_keys("a200,\t500\x7f"), "a200,\t500\x7f");
  EXPECT_EQ(strip_keys("g\x03\x1b"), "g");
}

// ---- --json: one style for every reading command ------------------------------------------

TEST(Json, EveryReadingCommandTakesIt) {
  for (const char *c : {"status", "in", "watch", "timing", "mode", "profile", "limits", "monitor", "list"}) {
    std::vector<std::string> args = {"x4ctl", c, "--json"};
    if (std::string(c) == "profile") args.push_back("1");
    EXPECT_TRUE(parse_args(args).json) << c;
    EXPECT_TRUE(contains(help_text(*find_command(c)), "--json")) << c;
  }
}

TEST(Json, ObjectsStartWithTheSchemaAndUseBooleans) {
  x4step::status s;
  s.inputs = 0x2;
  s.inputs_stale = true;
  EXPECT_EQ(inputs_json(s, "/dev/x4step0", std::chrono::steady_clock::now()),
            "{\"schema\":1,\"device\":\"/dev/x4step0\",\"inputs\":2,\"input_pins\":{\"15\":false,\"13\":true,"
            "\"12\":false,\"10\":false,\"11\":false},\"stale\":true,\"age_ms\":null}");
  s.inputs_stale = false;
  EXPECT_TRUE(
      contains(inputs_json(s, "d", std::chrono::steady_clock::now()), "\"stale\":false,\"age_ms\":0}"));
  x4step::profile p;
  p.top_speed(5000);
  EXPECT_EQ(profile_json(x4step::axis::y, p, "/dev/x4step1"),
            "{\"schema\":1,\"device\":\"/dev/x4step1\",\"axis\":2,\"v0\":0,\"ve\":0,\"vm\":5000,\"a0\":1000,"
            "\"ae\":1000}");
  EXPECT_EQ(mode_json(x4step::output_mode::smc_phase, "/dev/x4step0"),
            "{\"schema\":1,\"device\":\"/dev/x4step0\",\"mode\":\"smc-phase\",\"description\":\"" +
                mode_text(x4step::output_mode::smc_phase) + "\"}");
  x4step::switches sw;
  sw.ref[0] = 3;
  sw.nc = 0x4;
  x4step::axes_status a;
  a.inputs = 0x4;
  a.switches_active = 0;
  const std::string l = limits_json(sw, a, "/dev/x4step0");
  EXPECT_EQ(
      l.rfind("{\"schema\":1,\"device\":\"/dev/x4step0\",\"axes\":[{\"axis\":1,\"ref\":3,\"plus\":0,", 0), 0u)
      << l;
  EXPECT_TRUE(contains(l, "{\"input\":3,\"pin\":12,\"high\":true,\"nc\":true,\"active\":false}")) << l;
  x4step::status m;
  m.active = true;
  m.steps = {5, 0, 0, -1};
  EXPECT_EQ(monitor_json("started", m),
            "{\"schema\":1,\"event\":\"started\",\"active\":true,\"steps\":[5,0,0,-1],\"last_brake_code\":0,"
            "\"moves_ended\":0}");
  EXPECT_EQ(json_error("a \"b\"", 13), "{\"schema\":1,\"error\":{\"message\":\"a \\\"b\\\"\",\"errno\":13}}");
  EXPECT_EQ(json_error("x", 0), "{\"schema\":1,\"error\":{\"message\":\"x\",\"errno\":null}}");
}

TEST(Json, List) {
  port_entry free_port;
  free_port.device = "/dev/x4step0";
  free_port.abi = 4;
  port_entry held;
  held.device = "/dev/x4step1";
  held.parport = 1;
  held.abi = 4;
  held.controlled = true;
  held.controller = holder{42, "mill"};
  held.claimant = "x4step";
  port_entry lp;
  lp.device = "/dev/x4step2";
  lp.parport = 2;
  lp.abi = 4;
  lp.claimant = "lp";
  port_entry denied;
  denied.device = "/dev/x4step3";
  denied.parport = 3;
  denied.error = "/dev/x4step3: permission denied";
  denied.err = EACCES;
  const std::vector<port_entry> ports = {free_port, held, lp, denied};
  const std::string text = list_text(ports);
  EXPECT_TRUE(contains(text, "/dev/x4step0  parport0  ABI 4  free\n")) << text;
  EXPECT_TRUE(contains(text, "/dev/x4step1  parport1  ABI 4  controlled by PID 42 (mill)\n")) << text;
  EXPECT_TRUE(contains(text, "/dev/x4step2  parport2  ABI 4  free for x4step, but claimed by lp")) << text;
  EXPECT_TRUE(contains(text, "/dev/x4step3  parport3  /dev/x4step3: permission denied\n")) << text;
  const std::string json = list_json(ports);
  EXPECT_EQ(json.rfind("{\"schema\":1,\"library\":\"" + std::string(x4step::version()) + "\",\"ports\":[", 0),
            0u);
  EXPECT_TRUE(contains(json,
                       "{\"device\":\"/dev/x4step0\",\"parport\":0,\"abi\":4,\"controlled\":false,"
                       "\"controller\":null,\"claimed_by\":null}"))
      << json;
  EXPECT_TRUE(contains(json,
                       "\"controlled\":true,\"controller\":{\"pid\":42,\"name\":\"mill\"},"
                       "\"claimed_by\":\"x4step\"}"))
      << json;
  EXPECT_TRUE(contains(json,
                       "{\"device\":\"/dev/x4step3\",\"parport\":3,\"error\":{\"message\":"
                       "\"/dev/x4step3: permission denied\",\"errno\":13}}"))
      << json;
}

// Errors under --json are JSON on stdout, with the same exit status.
TEST(Json, ErrorsAreJsonOnStdout) {
  captured r = run({"-d", "/nonexistent/x4step9", "status", "--json"});
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.err, "");
  EXPECT_EQ(
      r.out,
      "{\"schema\":1,\"error\":{\"message\":\"/nonexistent/x4step9: port not found: is x4step loaded, the "
      "port present and not in use?\",\"errno\":" +
          std::to_string(ENOENT) + "}}\n");
  r = run({"-d", "/nonexistent/x4step9", "limits", "--json"});
  EXPECT_EQ(r.status, 1);
  EXPECT_EQ(r.out.rfind("{\"schema\":1,\"error\":{", 0), 0u) << r.out;
  r = run({"watch", "--json", "-n", "0"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "");
  EXPECT_EQ(r.out,
            "{\"schema\":1,\"error\":{\"message\":\"watch: count 0 out of range: use 1 or more\",\"errno\":" +
                std::to_string(EINVAL) + "}}\n");
  r = run({"-d", "/nonexistent/x4step9", "status"});  // without --json: text on stderr
  EXPECT_EQ(r.out, "");
  EXPECT_TRUE(contains(r.err, "x4ctl: status: /nonexistent/x4step9: port not found")) << r.err;
}

// ---- path --------------------------------------------------------------------------

std::vector<x4step::segment> path_of(const std::string &text, const path_defaults &d = {}) {
  std::istringstream in(text);
  return read_path(in, "square.path", d);
}

// The usage_error read_path throws for text ("" if none).
std::string path_error(const std::string &text) {
  try {
    path_of(text);
  } catch (const usage_error &e) {
    return e.what();
  }
  return "";
}

TEST(Path, LinesBecomeSegmentsInThousandthsOfASteps) {
  const auto s = path_of("# a square\n4000 0\n0 3000 speed=2000 accel=5000\n\n-4000 0 0 0 corner=100\n");
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0].steps(x4step::axis::x), 4000);
  EXPECT_EQ(s[0].length(), 4000000u);
  EXPECT_EQ(s[0].top_speed(), 1000000u);  // the default 1000 steps/s
  EXPECT_EQ(s[0].accel(), 10000000u);
  EXPECT_EQ(s[0].entry_speed(), 0u);  // from rest
  EXPECT_EQ(s[0].tag(), 2u);          // its line
  EXPECT_EQ(s[1].steps(x4step::axis::y), 3000);
  EXPECT_EQ(s[1].top_speed(), 2000000u);
  EXPECT_EQ(s[1].accel(), 5000000u);
  EXPECT_EQ(s[1].tag(), 3u);
  // A right angle at deviation 0.5 steps and 5000 steps/s^2:
  // v = sqrt(a d sin(45) / (1 - sin(45))) = sqrt(5000 * 0.5 * 2.414) = 77.69 steps/s.
  EXPECT_NEAR(s[1].entry_speed(), 77689.0, 10.0);
  EXPECT_EQ(s[2].entry_speed(), 100000u);  // corner= given
  EXPECT_EQ(s[2].tag(), 5u);
}

TEST(Path, StraightOnKeepsTheSpeedAReversalStops) {
  const auto s = path_of("100 100\n200 200\n-50 -50\n");
  EXPECT_EQ(s[1].entry_speed(), s[1].top_speed());
  EXPECT_EQ(s[2].entry_speed(), 0u);
  EXPECT_EQ(s[1].length(), 282843u);  // sqrt(2) * 200 steps
}

TEST(Path, BadLinesNameFileLineAndColumn) {
  EXPECT_EQ(path_error("100 0\n  12x 0\n"),
            "square.path:2:3: '12x' is no step count: use a whole number within +-16777216");
  EXPECT_EQ(path_error("1 2 3 4 5\n"),
            "square.path:1:9: more than 4 axes: a line is up to 4 step counts, then key=value");
  EXPECT_EQ(path_error("0 0\n"), "square.path:1:1: no steps: give at least one axis a non-zero count");
  EXPECT_EQ(path_error("10 speed=0\n"), "square.path:1:4: speed '0': use 1..100000 steps/s");
  EXPECT_EQ(path_error("10 accel=2000000\n"), "square.path:1:4: accel '2000000': use 1..1000000 steps/s^2");
  EXPECT_EQ(path_error("10 feed=3\n"), "square.path:1:4: unknown key 'feed': use speed=, accel= or corner=");
  EXPECT_EQ(path_error("10 speed=10 5\n"), "square.path:1:13: '5': step counts come first, then key=value");
  EXPECT_EQ(path_error("16777217\n"),
            "square.path:1:1: '16777217' is no step count: use a whole number within +-16777216");
  EXPECT_EQ(path_error("2147484 0\n"),
            "square.path:1:1: segment too long: split it (at most 2147483 steps along the path)");
  EXPECT_EQ(path_error("10 speed=45000 accel=20\n"),
            "square.path:1:1: speed / accel above 1800 s: accelerate faster or move slower");
}

TEST(Path, CommandLine) {
  const config c =
      parse({"path", "-s", "2000", "--accel", "30000", "--deviation", "0.25", "-o", "150", "p.txt"});
  EXPECT_EQ(c.cmd->name, "path");
  EXPECT_EQ(c.path.speed, 2000u);
  EXPECT_EQ(c.path.accel, 30000u);
  EXPECT_DOUBLE_EQ(c.path.deviation, 0.25);
  EXPECT_EQ(c.override_percent, 150u);
  EXPECT_EQ(c.file, "p.txt");
  EXPECT_EQ(usage_message({"path", "--override", "0"}), "path: override 0 out of range: use 1 to 200 %");
  EXPECT_TRUE(contains(usage_message({"path", "--deviation", "-1"}), "deviation '-1'"));
}

}  // namespace
}  // namespace x4ctl
