// SPDX-License-Identifier: GPL-2.0
// Host tests of x4ctl: command line parsing, help texts, the TEST.EXE
// command language and its interpreter on a simulated port, formatting.
// No device is needed; the in-QEMU sessions are tests/x4ctl/guest-x4ctl.sh.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <deque>
#include <fstream>
#include <iostream>
#include <sstream>
#include <tuple>
#include <utility>

#include "cli.hpp"
#include "commands.hpp"
#include "lang.hpp"
#include "motion.hpp"
#include "show.hpp"
#include "term.hpp"

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
  EXPECT_EQ(c.cmd, subcommand::interactive);
  EXPECT_EQ(c.lpt, 1);
  EXPECT_EQ(device_of(c), "/dev/x4step0");
}

TEST(Cli, PortLikeTestExe) {
  EXPECT_EQ(parse({"2"}).lpt, 2);  // TEST 2
  EXPECT_EQ(parse({"2"}).cmd, subcommand::interactive);
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
  EXPECT_EQ(c.cmd, subcommand::move);
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
  EXPECT_FALSE(c.wait);
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
  EXPECT_FALSE(c.wait);
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
  EXPECT_EQ(c.axis, 3);
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
  EXPECT_EQ(c.axis, 2);
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
  EXPECT_EQ(parse({"help", "jog"}).topic, subcommand::jog);
  EXPECT_EQ(usage_message({"help", "fly"}), "help: no command 'fly'");
}

TEST(Cli, Timing) {
  config c = parse({"timing"});
  EXPECT_EQ(c.cmd, subcommand::timing);
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
  EXPECT_EQ(c.cmd, subcommand::mode);
  EXPECT_FALSE(c.mode);
  EXPECT_EQ(parse({"mode", "clock-dir"}).mode, x4step::output_mode::clock_dir);
  EXPECT_EQ(parse({"mode", "smc-phase"}).mode, x4step::output_mode::smc_phase);
  EXPECT_EQ(parse({"mode", "smc-hold", "-p", "3"}).mode, x4step::output_mode::smc_phase_hold);
  EXPECT_EQ(usage_message({"mode", "smc"}), "mode: no mode 'smc': use clock-dir, smc-phase, smc-hold");
  EXPECT_EQ(usage_message({"mode", "SMC-PHASE"}),
            "mode: no mode 'SMC-PHASE': use clock-dir, smc-phase, smc-hold");
  EXPECT_EQ(usage_message({"mode", "clock-dir", "smc-hold"}), "mode: unexpected argument 'smc-hold'");
  EXPECT_EQ(usage_message({"mode", "--json"}), "mode: unknown option '--json'");
  EXPECT_TRUE(parse({"mode", "bogus", "--help"}).help);  // --help wins over a bad operand
}

TEST(Cli, HelpWinsOverMissingArguments) {
  EXPECT_TRUE(parse({"move", "--help"}).help);
  EXPECT_TRUE(parse({"sweep", "-h"}).help);
  EXPECT_EQ(parse({"--help", "jog"}).cmd, subcommand::jog);
  EXPECT_TRUE(parse({"-h"}).help);
  EXPECT_TRUE(parse({"--version"}).version);
}

// Every subcommand has a help with a Usage line and mentions each of its options.
TEST(Cli, HelpTexts) {
  const std::vector<std::pair<subcommand, std::vector<std::string>>> expected = {
      {subcommand::interactive,
       {"--port", "--device", "--help", "--version", "move", "jog", "brake", "stop", "status", "in", "out",
        "keys", "sweep", "monitor", "run", "timing", "mode [MODE]", "smc-phase", "Exit status"}},
      {subcommand::move,
       {"--freq", "--ramp", "--wait", "--then", "--port", "--device", "--help", "Exit status", "background",
        "preload", "the rest do not start"}},
      {subcommand::jog, {"--freq", "--ramp", "--time", "--wait", "--port", "--device", "--help"}},
      {subcommand::brake, {"--port", "--device", "--help", "Exit status"}},
      {subcommand::stop, {"--port", "--device", "--help", "Exit status"}},
      {subcommand::status, {"--json", "--port", "--device", "--help"}},
      {subcommand::in, {"--watch", "--port", "--device", "--help", "pins 15, 13, 12, 10"}},
      {subcommand::out, {"--time", "--port", "--device", "--help", "pin 14"}},
      {subcommand::keys, {"--port", "--device", "--help", "ESC (1)"}},
      {subcommand::sweep, {"--ramp", "--port", "--device", "--help"}},
      {subcommand::monitor, {"--moves", "--port", "--device", "--help", "read-only"}},
      {subcommand::run, {"--check", "--echo", "--port", "--device", "--help", "Ax,y,z", "M+ 500"}},
      {subcommand::timing,
       {"--pulse", "--space", "--setup", "--hold", "--json", "--port", "--device", "--help",
        "0 (symmetric clock", "1000..1000000 ns", "0..1000000 ns", "frequency too high", "after x4ctl exits",
        "Exit status"}},
      {subcommand::mode,
       {"clock-dir", "smc-phase", "smc-hold", "SMC800/SMC1500", "motors off at rest",
        "reduced holding current", "axis 4", "--port", "--device", "--help", "after x4ctl exits",
        "Exit status"}},
  };
  for (const auto &[cmd, words] : expected) {
    const std::string h = help_text(cmd);
    const std::string usage =
        cmd == subcommand::interactive ? "Usage: x4ctl [" : std::string("Usage: x4ctl ") + name_of(cmd) + " ";
    EXPECT_EQ(h.rfind(usage, 0), 0u) << h;
    for (const auto &w : words) EXPECT_TRUE(contains(h, w)) << name_of(cmd) << " help lacks " << w;
    std::istringstream lines(h);
    for (std::string line; std::getline(lines, line);) EXPECT_LE(line.size(), 80u) << line;
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
  for (const char *c : {"move", "jog", "brake", "stop", "status", "in", "out", "keys", "sweep", "monitor",
                        "run", "timing", "mode", "help"}) {
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
  void move_endless(int axis, x4step::direction dir, int freq_hz, milliseconds ramp) override {
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
    for (const auto ns : {t.pulse, t.space, t.dir_setup, t.dir_hold})
      if (ns.count() < 0 || ns.count() > 1000000)
        throw x4step::error(x4step::make_error_code(x4step::errc::param_fail));
    if (t.pulse.count() && t.pulse.count() < 1000)
      throw x4step::error(x4step::make_error_code(x4step::errc::param_fail));
    if (s_.active) throw x4step::error(x4step::make_error_code(x4step::errc::is_active));
    timing = t;
    timing_sets++;
  }
  x4step::step_timing get_step_timing() const override { return timing; }

 private:
  // The module's checks of the settings (x4_engine_load, x4_engine_endless).
  void refuse(int freq_hz, bool axis4) const {
    const long long period = 1000000000LL / freq_hz;
    const bool phase = cfg.mode != x4step::output_mode::clock_dir;
    if (!phase && (timing.pulse.count() ? timing.pulse.count() + timing.space.count() > period
                                        : timing.space.count() > period / 2))
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
  p.cfg.mode = x4step::output_mode::smc_phase;
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
  p.cfg.mode = x4step::output_mode::smc_phase;  // changed behind x4ctl's back
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
  p.timing.dir_hold = std::chrono::nanoseconds(7000);
  std::ostringstream out;
  timing_command(p, parse({"-p", "2", "timing", "--pulse", "10000", "--space", "90000"}), out);
  EXPECT_EQ(p.timing_sets, 1);
  EXPECT_EQ(p.timing.pulse, std::chrono::nanoseconds(10000));
  EXPECT_EQ(p.timing.space, std::chrono::nanoseconds(90000));
  EXPECT_EQ(p.timing.dir_setup, std::chrono::nanoseconds(100000));  // kept
  EXPECT_EQ(p.timing.dir_hold, std::chrono::nanoseconds(7000));     // kept
  EXPECT_TRUE(contains(out.str(), "device       /dev/x4step1\n")) << out.str();
  EXPECT_TRUE(contains(out.str(), "pulse        10000 ns\n")) << out.str();
  EXPECT_TRUE(contains(out.str(), "dir hold     7000 ns\n")) << out.str();
  EXPECT_TRUE(contains(out.str(), "max freq     10000 Hz\n")) << out.str();

  std::ostringstream json;
  timing_command(p, parse({"timing", "--setup", "0", "--json"}), json);
  EXPECT_EQ(json.str(),
            "{\"device\":\"/dev/x4step0\",\"pulse_ns\":10000,\"space_ns\":90000,\"dir_setup_ns\":0,"
            "\"dir_hold_ns\":7000,\"mode\":\"clock-dir\",\"max_freq_hz\":10000}\n");
  EXPECT_EQ(p.timing_sets, 2);
  EXPECT_EQ(p.timing.pulse, std::chrono::nanoseconds(10000));
}

TEST(Settings, ModeKeepsTheRestOfTheConfig) {
  fake_port p;
  p.cfg.clock_invert = 0x5;
  p.cfg.dir_invert = 0x2;
  p.cfg.keys_swallow = true;
  std::ostringstream out;
  mode_command(p, parse({"mode"}), out);
  EXPECT_EQ(p.config_sets, 0);
  EXPECT_EQ(out.str(), "clock-dir: clock and direction signals per axis (X4Step)\n");
  out.str("");
  mode_command(p, parse({"mode", "smc-phase"}), out);
  EXPECT_EQ(p.config_sets, 1);
  EXPECT_EQ(p.cfg.mode, x4step::output_mode::smc_phase);
  EXPECT_EQ(p.cfg.clock_invert, 0x5u);
  EXPECT_EQ(p.cfg.dir_invert, 0x2u);
  EXPECT_TRUE(p.cfg.keys_swallow);
  EXPECT_EQ(out.str(), "smc-phase: SMC800/SMC1500 half-step phase drive of axes 1..3, motors off at rest\n");
  out.str("");
  mode_command(p, parse({"mode", "smc-hold"}), out);
  EXPECT_EQ(p.cfg.mode, x4step::output_mode::smc_phase_hold);
  EXPECT_EQ(out.str().rfind("smc-hold: ", 0), 0u) << out.str();
  out.str("");
  mode_command(p, parse({"mode"}), out);
  EXPECT_EQ(out.str().rfind("smc-hold: ", 0), 0u) << out.str();
  EXPECT_EQ(p.config_sets, 2);
}

TEST(Settings, PhaseModeRefusesAxis4Clearly) {
  fake_console con;
  fake_port p;
  p.cfg.mode = x4step::output_mode::smc_phase;
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
  p.cfg.mode = x4step::output_mode::smc_phase_hold;
  try {
    start_endless(p, 4, x4step::direction::negative, 1000, milliseconds(0));
    FAIL() << "axis 4 jogged";
  } catch (const failure &e) {
    EXPECT_TRUE(contains(e.what(), "axis 4 cannot move in smc-hold mode")) << e.what();
  }
  EXPECT_EQ(p.starts, 1);
  EXPECT_TRUE(p.endless.empty());
  p.cfg.mode = x4step::output_mode::clock_dir;
  load_move(p, x4step::move{{0, 0, 0, 5}, 1000, milliseconds(0)});  // fine with clock and direction
  EXPECT_EQ(p.loads.size(), 2u);
}

TEST(Settings, FrequencyTooHighForTheTiming) {
  fake_console con;
  fake_port p;
  p.timing.pulse = std::chrono::nanoseconds(100000);
  p.timing.space = std::chrono::nanoseconds(100000);
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
    start_endless(p, 1, x4step::direction::positive, 5001, milliseconds(0));
    FAIL() << "jogged";
  } catch (const failure &e) {
    EXPECT_EQ(e.what(), why);
  }
  // The symmetric clock: the space in half a period.
  p.timing.pulse = std::chrono::nanoseconds(0);
  p.timing.space = std::chrono::nanoseconds(250000);
  try {
    load_move(p, x4step::move{{10, 0, 0, 0}, 2001, milliseconds(0)});
    FAIL() << "loaded";
  } catch (const failure &e) {
    EXPECT_TRUE(contains(e.what(), "allow at most 2000 Hz")) << e.what();
  }
  // Pulse and space do not apply to phase patterns.
  p.cfg.mode = x4step::output_mode::smc_phase;
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
  EXPECT_EQ(key_name(1), "ESC");
  EXPECT_EQ(key_name(28), "key code 28");
  EXPECT_EQ(key_name(156), "key code 156 (release of 28)");
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
  EXPECT_EQ(
      status_json(s, "/dev/x4step0"),
      "{\"device\":\"/dev/x4step0\",\"active\":true,\"loaded\":false,\"controlled\":true,"
      "\"steps\":[1,-2,3,0],\"inputs\":17,\"input_pins\":{\"15\":1,\"13\":0,\"12\":0,\"10\":0,\"11\":1},"
      "\"outputs\":9,\"signal1\":1,\"signal2\":0,\"boost\":0,\"aktiv\":1,\"last_brake_code\":1,"
      "\"moves_ended\":7}");
  EXPECT_EQ(json_string("a\"b\\c\n"), "\"a\\\"b\\\\c\\u000a\"");
  const std::string text = status_text(s, "/dev/x4step0");
  EXPECT_TRUE(contains(text, "state        running, controlled\n")) << text;
  EXPECT_TRUE(contains(text, "braked by    ESC\n")) << text;
}

TEST(Show, TimingAndMode) {
  x4step::step_timing t;
  EXPECT_EQ(max_freq_hz(t, x4step::output_mode::clock_dir), 20000);
  t.space = std::chrono::nanoseconds(30000);  // symmetric clock: 60 us periods
  EXPECT_EQ(max_freq_hz(t, x4step::output_mode::clock_dir), 16666);
  t.pulse = std::chrono::nanoseconds(1000000);
  t.space = std::chrono::nanoseconds(1000000);
  EXPECT_EQ(max_freq_hz(t, x4step::output_mode::clock_dir), 500);
  EXPECT_EQ(max_freq_hz(t, x4step::output_mode::smc_phase), 20000);
  t.pulse = std::chrono::nanoseconds(10000);
  t.space = std::chrono::nanoseconds(40000);
  EXPECT_EQ(max_freq_hz(t, x4step::output_mode::clock_dir), 20000);
  const std::string text = timing_text(t, x4step::output_mode::smc_phase_hold, "/dev/x4step3");
  EXPECT_TRUE(contains(text, "pulse        10000 ns\n")) << text;
  EXPECT_TRUE(contains(text, "max freq     20000 Hz (smc-hold mode: pulse and space do not apply)\n"))
      << text;
  EXPECT_EQ(timing_json(t, x4step::output_mode::smc_phase, "/dev/x4step3"),
            "{\"device\":\"/dev/x4step3\",\"pulse_ns\":10000,\"space_ns\":40000,\"dir_setup_ns\":100000,"
            "\"dir_hold_ns\":0,\"mode\":\"smc-phase\",\"max_freq_hz\":20000}");
  std::vector<std::string> names;
  for (const auto m : output_modes) {
    names.push_back(mode_name(m));
    EXPECT_EQ(mode_text(m).rfind(names.back() + ": ", 0), 0u) << mode_text(m);
  }
  EXPECT_EQ(names, (std::vector<std::string>{"clock-dir", "smc-phase", "smc-hold"}));
}

// ---- keys from a terminal ------------------------------------------------------------------

TEST(Term, DecodeKeys) {
  EXPECT_EQ(decode_key("", false).k, key::none);
  EXPECT_EQ(decode_key("\x1b", false).used, 0u);  // maybe the start of a sequence
  EXPECT_EQ(decode_key("\x1b", true).k, key::esc);
  EXPECT_EQ(decode_key("\x1b[C", false).k, key::right);
  EXPECT_EQ(decode_key("\x1b[D", false).k, key::left);
  EXPECT_EQ(decode_key("\x1bOD", false).k, key::left);
  EXPECT_EQ(decode_key("\x1b[1;2C", false).k, key::right);  // shift-right
  EXPECT_EQ(decode_key("\x1b[1;2C", false).used, 6u);
  EXPECT_EQ(decode_key("\x1b[A", false).k, key::other);
  EXPECT_EQ(decode_key("\x1b[", false).used, 0u);
  EXPECT_EQ(decode_key("\x1bx", false).k, key::esc);
  EXPECT_EQ(decode_key("\x1bx", false).used, 1u);
  EXPECT_EQ(decode_key("\x03", false).k, key::interrupt);
  EXPECT_EQ(decode_key("q", false).k, key::other);
}

TEST(Term, StripKeysFromTypedLines) {
  EXPECT_EQ(strip_keys("\x1b"
                       "d20"),
            "d20");  // ESC that came after the move's end
  EXPECT_EQ(strip_keys("s1\x1b[A\x1b[1;5Cd5"), "s1d5");
  EXPECT_EQ(strip_keys("a200,\t500\x7f"), "a200,\t500\x7f");
  EXPECT_EQ(strip_keys("g\x03\x1b"), "g");
}

}  // namespace
}  // namespace x4ctl
