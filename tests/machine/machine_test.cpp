// SPDX-License-Identifier: GPL-2.0
// The machine file (lib/machine): the shipped examples read, and every
// kind of mistake is refused with file:line, the key and what to fix.
#include "machine.hpp"

#include <gtest/gtest.h>

#include <regex>
#include <sstream>

namespace m = x4step::machine;
namespace g = x4step::gcode;

namespace {

// A small valid machine; line numbers matter to the tests below.
const char *const base =
    "[X4STEP]\n"                   // 1
    "ARC_TOLERANCE = 0.01\n"       // 2
    "JUNCTION_DEVIATION = 0.02\n"  // 3
    "[TRAJ]\n"                     // 4
    "COORDINATES = XZ\n"           // 5
    "LINEAR_UNITS = mm\n"          // 6
    "[AXIS_X]\n"                   // 7
    "MIN_LIMIT = -10\n"            // 8
    "MAX_LIMIT = 100\n"            // 9
    "MAX_VELOCITY = 20\n"          // 10
    "MAX_ACCELERATION = 200\n"     // 11
    "[AXIS_Z]\n"                   // 12
    "MIN_LIMIT = -50\n"            // 13
    "MAX_LIMIT = 0\n"              // 14
    "MAX_VELOCITY = 10\n"          // 15
    "MAX_ACCELERATION = 100\n"     // 16
    "[JOINT_0]\n"                  // 17
    "MOTOR = 1\n"                  // 18
    "SCALE = 800\n"                // 19
    "[JOINT_1]\n"                  // 20
    "MOTOR = 3\n"                  // 21
    "SCALE = -400\n";              // 22

m::machine read(const std::string &text) {
  std::istringstream in(text);
  return m::read(in, "m.ini");
}

// The text with line n (1-based) replaced by `with` ("" drops it).
std::string replaced(int n, const std::string &with) {
  std::istringstream in(base);
  std::string out, l;
  for (int i = 1; std::getline(in, l); i++)
    if (i != n)
      out += l + "\n";
    else if (!with.empty())
      out += with + "\n";
  return out;
}

// The error a text gets; fails the test if it is accepted.
std::string refusal(const std::string &text) {
  try {
    read(text);
  } catch (const m::error &e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted:\n" << text;
  return "";
}

// Whether one of the lines (one per mistake) matches the pattern.
bool has_line(const std::string &lines, const std::string &pattern) {
  std::istringstream in(lines);
  for (std::string l; std::getline(in, l);)
    if (std::regex_search(l, std::regex(pattern))) return true;
  return false;
}

#define EXPECT_REFUSED(text, pattern) EXPECT_TRUE(has_line(refusal(text), pattern)) << refusal(text)

}  // namespace

TEST(Machine, ReadsTheBase) {
  const m::machine mc = read(base);
  EXPECT_EQ(mc.units, g::units::mm);
  EXPECT_EQ(mc.port, "LPT1");
  ASSERT_TRUE(mc.axes[g::X] && mc.axes[g::Z]);
  EXPECT_FALSE(mc.axes[g::Y]);
  EXPECT_EQ(mc.axes[g::X]->motor, 0);
  EXPECT_EQ(mc.axes[g::Z]->motor, 2);
  EXPECT_DOUBLE_EQ(mc.axes[g::Z]->scale, -400);
  EXPECT_DOUBLE_EQ(mc.axes[g::X]->max_limit, 100);
  EXPECT_DOUBLE_EQ(mc.arc_tolerance, 0.01);
  EXPECT_FALSE(mc.axes[g::X]->home.enabled);
}

// The planner asks within_soft_limits for every point; beyond_soft_limit
// says why, only when it is not. A billionth of the limit (at least of
// one unit) beyond still counts as within: rounding, not a move.
TEST(Machine, SoftLimitsAndTheirTolerance) {
  m::axis x;
  x.min_limit = -500;
  x.max_limit = 0.5;
  EXPECT_TRUE(m::within_soft_limits(x, 0.25));
  EXPECT_TRUE(m::within_soft_limits(x, 0.5 + 0.9e-9));
  EXPECT_FALSE(m::within_soft_limits(x, 0.5 + 1.1e-9));
  EXPECT_TRUE(m::within_soft_limits(x, -500 - 0.9 * 500e-9));
  EXPECT_FALSE(m::within_soft_limits(x, -500 - 1.1 * 500e-9));
  m::machine mc;
  mc.axes[g::X] = x;
  EXPECT_EQ(m::beyond_soft_limit(mc, g::X, 0.5 + 0.9e-9), "");
  EXPECT_EQ(m::beyond_soft_limit(mc, g::X, 0.75), "X 0.75 is beyond the soft limit [AXIS_X] MAX_LIMIT 0.5");
  EXPECT_EQ(m::beyond_soft_limit(mc, g::X, -501), "X -501 is beyond the soft limit [AXIS_X] MIN_LIMIT -500");
  EXPECT_EQ(m::beyond_soft_limit(mc, g::Y, 1e9), "");  // no such axis: no limit
}

TEST(Machine, ReadsTheShippedExamples) {
  const m::machine mill = m::read_file(X4_SOURCE_DIR "/machines/smc1500-mill.ini");
  EXPECT_EQ(mill.mode, m::output_mode::smc_phase);
  EXPECT_EQ(mill.spindle, m::pin::pin1);
  ASSERT_TRUE(mill.axes[g::Z]);
  EXPECT_TRUE(mill.axes[g::Z]->home.enabled);
  EXPECT_EQ(mill.axes[g::Z]->home.input, 1);
  EXPECT_DOUBLE_EQ(mill.axes[g::Z]->home.latch_vel, -0.5);
  // Both ship a tool table, so G43 H applies a length without a warning.
  EXPECT_EQ(g::read_tool_table(mill.tool_table, mill.units, mill.units).size(), 3u);
  const m::machine four = m::read_file(X4_SOURCE_DIR "/machines/x4step-4axis.ini");
  EXPECT_EQ(four.units, g::units::inch);
  ASSERT_TRUE(four.axes[g::A]);
  EXPECT_EQ(four.axes[g::A]->motor, 3);
  EXPECT_DOUBLE_EQ(four.axes[g::Y]->scale, -8000);
  EXPECT_EQ(four.tool_table, X4_SOURCE_DIR "/machines/x4step-4axis.tbl");
  EXPECT_EQ(four.flood, m::pin::pin14);
}

TEST(Machine, RefusesSyntax) {
  EXPECT_REFUSED(replaced(2, "ARC_TOLERANCE 0.01"),
                 "^m.ini:2:[0-9]+: \\[X4STEP\\]: 'ARC_TOLERANCE 0.01': write KEY = VALUE");
  EXPECT_REFUSED(replaced(4, "[TRAJ"), "^m.ini:4:[0-9]+: '\\[TRAJ' is no section header");
  EXPECT_REFUSED("A = 1\n" + std::string(base), "^m.ini:1:[0-9]+: A: a key before any \\[SECTION\\]");
  EXPECT_REFUSED(replaced(3, "ARC_TOLERANCE = 0.02"),
                 "^m.ini:3:[0-9]+: \\[X4STEP\\] ARC_TOLERANCE: given twice \\(first at line 2\\)");
  EXPECT_REFUSED(std::string(base) + "[TRAJ]\n",
                 "^m.ini:23:[0-9]+: \\[TRAJ\\]: section given twice \\(first at line 4\\)");
  EXPECT_REFUSED(replaced(2, "= 3"), "^m.ini:2:[0-9]+: \\[X4STEP\\]: '= 3' has no key");
}

TEST(Machine, RefusesUnknownNames) {
  EXPECT_REFUSED(std::string(base) + "[DISPLAYS]\nPOSITION_OFFSET = RELATIVE\n",
                 "^m.ini:23:1: \\[DISPLAYS\\]: unknown section: did you mean \\[DISPLAY\\]\\?$");
  EXPECT_REFUSED(std::string(base) + "[SPECIAL]\nA = 1\n",
                 "^m.ini:23:1: \\[SPECIAL\\]: unknown section: a machine");
  EXPECT_REFUSED(replaced(10, "MAX_VELOCITY = 20\nBACKLASH = 0.1"),
                 "^m.ini:11:1: \\[AXIS_X\\] BACKLASH: unknown key: \\[AXIS_X\\] takes MIN_LIMIT, MAX_LIMIT, "
                 "MAX_VELOCITY and MAX_ACCELERATION$");
  EXPECT_REFUSED(replaced(3, "JUNCTION_DEVIATION = 0.02\nARC_TOLLERANCE = 1"),
                 "^m.ini:4:1: \\[X4STEP\\] ARC_TOLLERANCE: unknown key: did you mean ARC_TOLERANCE\\?$");
  EXPECT_REFUSED(replaced(19, "SCALE = 800\nHOME_SERCH_VEL = -5"),
                 "^m.ini:20:1: \\[JOINT_0\\] HOME_SERCH_VEL: unknown key: did you mean HOME_SEARCH_VEL\\?$");
  EXPECT_REFUSED(replaced(10, "MAXVELOCITY = 20"),
                 "^m.ini:10:1: \\[AXIS_X\\] MAXVELOCITY: unknown key: did you mean MAX_VELOCITY\\?$");
  EXPECT_REFUSED(replaced(18, "MOTRO = 1"),
                 "^m.ini:18:1: \\[JOINT_0\\] MOTRO: unknown key: did you mean MOTOR\\?$");
  // A misspelt required key is named as unknown, and not also as the one missing.
  EXPECT_EQ(refusal(replaced(3, "JUNCTION_DEVIATON = 0.02")),
            "m.ini:3:1: [X4STEP] JUNCTION_DEVIATON: unknown key: did you mean JUNCTION_DEVIATION?");
  // A misspelt key in a LinuxCNC section x4step ignores is refused if it is near one of x4step's.
  EXPECT_REFUSED(replaced(5, "COORDINATE = XZ"),
                 "^m.ini:5:1: \\[TRAJ\\] COORDINATE: unknown key: did you mean COORDINATES\\?$");
}

// LinuxCNC's own sections and keys are accepted, listed once in the warnings.
TEST(Machine, AcceptsLinuxcncSettingsWithAWarning) {
  const std::string text =
      "[EMC]\nVERSION = 1.1\nMACHINE = mill\nDEBUG = 0\n[DISPLAY]\nDISPLAY = axis\n"
      "[FILTER]\nPROGRAM_EXTENSION = .py Python Script\nPROGRAM_EXTENSION = .nc G-Code\n"
      "[HAL]\nHALFILE = mill.hal\nHALFILE = custom.hal\n[KINS]\nJOINTS = 2\n" +
      replaced(19, "SCALE = 800\nFERROR = 1\nMIN_FERROR = .25\nSTEPGEN_MAXACCEL = 250") + "FERROR = 1\n";
  std::string t = text;
  t.replace(t.find("LINEAR_UNITS = mm"), 17,
            "LINEAR_UNITS = mm\nCYCLE_TIME = 0.01\nDEFAULT_LINEAR_VELOCITY = 5");
  const m::machine mc = read(t);
  EXPECT_EQ(mc.name, "mill");
  ASSERT_EQ(mc.warnings.size(), 2u);
  EXPECT_EQ(mc.warnings[0],
            "m.ini: LinuxCNC sections x4step does not use, ignored: [DISPLAY] [FILTER] [HAL] [KINS]");
  EXPECT_EQ(mc.warnings[1],
            "m.ini: LinuxCNC keys x4step does not use, ignored: [EMC] DEBUG VERSION; [TRAJ] CYCLE_TIME "
            "DEFAULT_LINEAR_VELOCITY; [JOINT_0] FERROR MIN_FERROR STEPGEN_MAXACCEL; [JOINT_1] FERROR");
  EXPECT_TRUE(read(base).warnings.empty());
  // Repeated keys are LinuxCNC's way in its own sections, not in x4step's.
  EXPECT_REFUSED(replaced(19, "SCALE = 800\nFERROR = 1\nFERROR = 2"),
                 "^m.ini:21:1: \\[JOINT_0\\] FERROR: given twice");
}

// Every mistake of a file in one pass, in file order, each with its line and column.
TEST(Machine, ReportsEveryMistakeInOnePass) {
  std::string t = replaced(2, "ARC_TOLERANCE = fine");
  t = t.replace(t.find("MAX_LIMIT = 100"), 15, "MAX_LIMIT = -20");
  t = t.replace(t.find("MAX_VELOCITY = 10"), 17, "MAX_VELOSITY = 10");
  t = t.replace(t.find("MOTOR = 3"), 9, "MOTOR = 1");
  t += "[AXIS_Q]\n";
  try {
    read(t);
    ADD_FAILURE() << "accepted";
  } catch (const m::error &e) {
    const std::vector<std::string> want = {
        "m.ini:2:17: [X4STEP] ARC_TOLERANCE: 'fine' is no number",
        "m.ini:9:13: [AXIS_X] MAX_LIMIT: MAX_LIMIT -20 must be above MIN_LIMIT -10",
        "m.ini:15:1: [AXIS_Z] MAX_VELOSITY: unknown key: did you mean MAX_VELOCITY?",
        "m.ini:21:9: [JOINT_1] MOTOR: motor 1 drives another axis already (line 18): one axis per motor",
        "m.ini:23:1: [AXIS_Q]: axis Q is not in [TRAJ] COORDINATES (XZ): add it or drop this",
    };
    EXPECT_EQ(e.lines(), want);
    EXPECT_EQ(e.line(), 2);
    EXPECT_EQ(e.col(), 17);
    EXPECT_EQ(e.key(), "[X4STEP] ARC_TOLERANCE");
    std::string all;
    for (const std::string &l : want) all += (all.empty() ? "" : "\n") + l;
    EXPECT_EQ(std::string(e.what()), all);
  }
  // A broken header is read as its name: its keys are not lost, nor reported missing.
  EXPECT_EQ(refusal(replaced(4, "[TRAJ")), "m.ini:4:1: '[TRAJ' is no section header: write [NAME]");
  EXPECT_EQ(refusal(replaced(4, "[TRAJ] XZ")), "m.ini:4:1: '[TRAJ] XZ' is no section header: write [NAME]");
  EXPECT_REFUSED(std::string(base) + "  [ ]\nA = 1\n", "^m.ini:23:3: '\\[ \\]' is no section header");
  EXPECT_EQ(refusal(replaced(2, "ARC_TOLERANCE 0.01")),
            "m.ini:2:1: [X4STEP]: 'ARC_TOLERANCE 0.01': write KEY = VALUE");
}

// "# ..." or "; ..." after a value (after a blank) is a comment.
TEST(Machine, InlineComments) {
  std::string t = replaced(2, "ARC_TOLERANCE = 0.05   # the most a chord leaves an arc");
  t = t.replace(t.find("SCALE = 800"), 11, "SCALE = 800 ; 200 steps x 4 / 1 mm pitch");
  t = "[EMC]\nMACHINE = mill#2 # the second one\n" + t;
  const m::machine mc = read(t);
  EXPECT_DOUBLE_EQ(mc.arc_tolerance, 0.05);
  EXPECT_DOUBLE_EQ(mc.axes[g::X]->scale, 800);
  EXPECT_EQ(mc.name, "mill#2");
  EXPECT_REFUSED(replaced(2, "ARC_TOLERANCE = 0.05# fine"),
                 "^m.ini:2:17: \\[X4STEP\\] ARC_TOLERANCE: '0.05# fine' is no number");
  EXPECT_REFUSED(replaced(2, "ARC_TOLERANCE = # none"),
                 "^m.ini:2:17: \\[X4STEP\\] ARC_TOLERANCE: '' is no number");
}

// clock-dir, as `x4ctl mode` says it, and step-dir, as the first machine files did.
TEST(Machine, ClockDirHasTwoNames) {
  EXPECT_EQ(read(replaced(1, "[X4STEP]\nOUTPUT_MODE = clock-dir")).mode, m::output_mode::clock_dir);
  EXPECT_EQ(read(replaced(1, "[X4STEP]\nOUTPUT_MODE = step-dir")).mode, m::output_mode::clock_dir);
  EXPECT_EQ(read(replaced(1, "[X4STEP]\nOUTPUT_MODE = smc-hold")).mode, m::output_mode::smc_hold);
}

TEST(Machine, NearestName) {
  const std::vector<std::string> names = {"MIN_LIMIT", "MAX_LIMIT", "MAX_VELOCITY", "MOTOR", "HOME"};
  EXPECT_EQ(m::nearest("MAX_LIMTI", names), "MAX_LIMIT");          // swapped
  EXPECT_EQ(m::nearest("MAX_VELOCTY", names), "MAX_VELOCITY");     // missing
  EXPECT_EQ(m::nearest("MAXX_VELOCITYY", names), "MAX_VELOCITY");  // two extra
  EXPECT_EQ(m::nearest("MOTORS", names), "MOTOR");
  EXPECT_EQ(m::nearest("HOMES", names), "HOME");
  EXPECT_EQ(m::nearest("MOTTORS", names), "");  // two in a short name
  EXPECT_EQ(m::nearest("SPEED", names), "");
  EXPECT_EQ(m::nearest("MAX_VELOCITY", names), "");  // itself is no suggestion
}

TEST(Machine, RefusesBadValues) {
  EXPECT_REFUSED(replaced(2, "ARC_TOLERANCE = fine"),
                 "^m.ini:2:[0-9]+: \\[X4STEP\\] ARC_TOLERANCE: 'fine' is no number");
  EXPECT_REFUSED(replaced(2, "ARC_TOLERANCE = 0"),
                 "^m.ini:2:[0-9]+: \\[X4STEP\\] ARC_TOLERANCE: '0': must be above 0");
  EXPECT_REFUSED(replaced(3, "JUNCTION_DEVIATION = -1"),
                 "^m.ini:3:[0-9]+: \\[X4STEP\\] JUNCTION_DEVIATION: must be 0");
  EXPECT_REFUSED(replaced(1, "[X4STEP]\nPORT = LPT5"),
                 "^m.ini:2:[0-9]+: \\[X4STEP\\] PORT: 'LPT5': use LPT1");
  EXPECT_REFUSED(replaced(1, "[X4STEP]\nOUTPUT_MODE = pwm"),
                 "^m.ini:2:15: \\[X4STEP\\] OUTPUT_MODE: 'pwm': use clock-dir \\(or step-dir\\), smc-phase "
                 "or smc-hold$");
  EXPECT_REFUSED(replaced(1, "[X4STEP]\nSPINDLE_PIN = 16"),
                 "^m.ini:2:[0-9]+: \\[X4STEP\\] SPINDLE_PIN: '16': use 1 \\(signal 1\\), 14");
  EXPECT_REFUSED(replaced(5, "COORDINATES = XQ"), "^m.ini:5:[0-9]+: \\[TRAJ\\] COORDINATES: 'Q' is no axis");
  EXPECT_REFUSED(replaced(5, "COORDINATES = XYZAB"),
                 "^m.ini:5:[0-9]+: \\[TRAJ\\] COORDINATES: 'XYZAB': a port drives at most 4 motors");
  EXPECT_REFUSED(replaced(5, "COORDINATES = "), "^m.ini:5:[0-9]+: \\[TRAJ\\] COORDINATES: no axis");
  EXPECT_REFUSED(replaced(6, "LINEAR_UNITS = furlong"),
                 "^m.ini:6:[0-9]+: \\[TRAJ\\] LINEAR_UNITS: 'FURLONG': use mm or inch");
  EXPECT_REFUSED(replaced(6, "LINEAR_UNITS = mm\nANGULAR_UNITS = radian"),
                 "^m.ini:7:[0-9]+: \\[TRAJ\\] ANGULAR_UNITS: 'radian'");
  EXPECT_REFUSED(replaced(6, "LINEAR_UNITS = mm\nMAX_LINEAR_VELOCITY = -3"),
                 "^m.ini:7:[0-9]+: \\[TRAJ\\] MAX_LINEAR_VELOCITY: '-3': must be above 0");
  EXPECT_REFUSED(replaced(10, "MAX_VELOCITY = 0"),
                 "^m.ini:10:[0-9]+: \\[AXIS_X\\] MAX_VELOCITY: '0': must be above 0");
  EXPECT_REFUSED(replaced(11, "MAX_ACCELERATION = 1e999"),
                 "^m.ini:11:[0-9]+: \\[AXIS_X\\] MAX_ACCELERATION: '1e999' is no number");
  EXPECT_REFUSED(replaced(18, "MOTOR = 5"),
                 "^m.ini:18:[0-9]+: \\[JOINT_0\\] MOTOR: '5': use a whole number 1..4");
  EXPECT_REFUSED(replaced(18, "MOTOR = 1.5"),
                 "^m.ini:18:[0-9]+: \\[JOINT_0\\] MOTOR: '1.5': use a whole number 1..4");
  EXPECT_REFUSED(replaced(19, "SCALE = 0"), "^m.ini:19:[0-9]+: \\[JOINT_0\\] SCALE: must not be 0");
  EXPECT_REFUSED(replaced(19, "SCALE = 800\nHOME_SEARCH_VEL = -5\nHOME_LATCH_VEL = 1\nHOME_INPUT = 6"),
                 "^m.ini:22:[0-9]+: \\[JOINT_0\\] HOME_INPUT: '6': use a whole number 1..5");
  EXPECT_REFUSED(
      replaced(19,
               "SCALE = 800\nHOME_SEARCH_VEL = -5\nHOME_LATCH_VEL = 1\nHOME_INPUT = 1\nHOME_SEQUENCE = -1"),
      "^m.ini:23:[0-9]+: \\[JOINT_0\\] HOME_SEQUENCE: '-1': use a whole number 0..9");
}

TEST(Machine, RefusesMissingSectionsAndKeys) {
  EXPECT_REFUSED(replaced(2, ""), "^m.ini:1:[0-9]+: \\[X4STEP\\] ARC_TOLERANCE: missing: give");
  EXPECT_REFUSED(replaced(3, ""), "^m.ini:1:[0-9]+: \\[X4STEP\\] JUNCTION_DEVIATION: missing");
  EXPECT_REFUSED(replaced(6, ""), "^m.ini:4:[0-9]+: \\[TRAJ\\] LINEAR_UNITS: missing: give mm or inch");
  EXPECT_REFUSED(replaced(5, ""), "^m.ini:4:[0-9]+: \\[TRAJ\\] COORDINATES: missing");
  EXPECT_REFUSED(replaced(8, ""), "^m.ini:7:[0-9]+: \\[AXIS_X\\] MIN_LIMIT: missing");
  EXPECT_REFUSED(replaced(9, ""), "^m.ini:7:[0-9]+: \\[AXIS_X\\] MAX_LIMIT: missing");
  EXPECT_REFUSED(replaced(15, ""), "^m.ini:12:[0-9]+: \\[AXIS_Z\\] MAX_VELOCITY: missing");
  EXPECT_REFUSED(replaced(16, ""), "^m.ini:12:[0-9]+: \\[AXIS_Z\\] MAX_ACCELERATION: missing");
  EXPECT_REFUSED(
      replaced(18, ""),
      "^m.ini:17:[0-9]+: \\[JOINT_0\\] MOTOR: missing: give the motor \\(1..4\\) that drives axis X");
  EXPECT_REFUSED(replaced(22, ""), "^m.ini:20:[0-9]+: \\[JOINT_1\\] SCALE: missing");
  EXPECT_REFUSED(replaced(5, "COORDINATES = XYZ"),
                 "^m.ini:5:[0-9]+: \\[TRAJ\\] COORDINATES: axis Y has no \\[AXIS_Y\\] section");
  // Without [JOINT_1]: Z is joint 1.
  std::string no_joint1 = replaced(20, "");
  no_joint1 = no_joint1.substr(0, no_joint1.find("MOTOR = 3"));
  EXPECT_REFUSED(
      no_joint1,
      "^m.ini:5:[0-9]+: \\[TRAJ\\] COORDINATES: axis Z is joint 1: it needs a \\[JOINT_1\\] section");
  const std::string b = base;
  EXPECT_REFUSED(b.substr(b.find("[TRAJ]")), "^m.ini: \\[X4STEP\\]: no \\[X4STEP\\] section");
  EXPECT_REFUSED(b.substr(0, b.find("[TRAJ]")), "^m.ini: \\[TRAJ\\]: no \\[TRAJ\\] section");
  EXPECT_REFUSED(replaced(19, "SCALE = 800\nHOME_SEARCH_VEL = -5\nHOME_INPUT = 1"),
                 "^m.ini:17:[0-9]+: \\[JOINT_0\\] HOME_LATCH_VEL: missing");
  EXPECT_REFUSED(replaced(19, "SCALE = 800\nHOME_SEARCH_VEL = -5\nHOME_LATCH_VEL = 1"),
                 "^m.ini:17:[0-9]+: \\[JOINT_0\\] HOME_INPUT: missing: give the home switch's input");
  EXPECT_THROW(m::read_file("/nonexistent/machine.ini"), m::error);
}

TEST(Machine, RefusesContradictions) {
  EXPECT_REFUSED(replaced(9, "MAX_LIMIT = -10"),
                 "^m.ini:9:13: \\[AXIS_X\\] MAX_LIMIT: MAX_LIMIT -10 must be above MIN_LIMIT -10$");
  EXPECT_REFUSED(replaced(21, "MOTOR = 1"),
                 "^m.ini:21:[0-9]+: \\[JOINT_1\\] MOTOR: motor 1 drives another axis already \\(line 18\\)");
  EXPECT_REFUSED(replaced(1, "[X4STEP]\nSPINDLE_PIN = 14\nFLOOD_PIN = 14"),
                 "^m.ini:3:[0-9]+: \\[X4STEP\\] FLOOD_PIN: pin 14 is the SPINDLE_PIN already");
  EXPECT_REFUSED(replaced(1, "[X4STEP]\nMIST_PIN = 1\nSPINDLE_PIN = 1"),
                 "^m.ini:3:[0-9]+: \\[X4STEP\\] SPINDLE_PIN: pin 1 is the MIST_PIN already");
  EXPECT_REFUSED(replaced(1, "[X4STEP]\nPROBE_NC = 1"),
                 "^m.ini:2:[0-9]+: \\[X4STEP\\] PROBE_NC: no PROBE_INPUT: give the probe's input 1..5 first");
  EXPECT_REFUSED(replaced(1, "[X4STEP]\nPROBE_INPUT = 6"), "^m.ini:2:[0-9]+: \\[X4STEP\\] PROBE_INPUT: ");
  {
    const m::machine probe = read(replaced(1, "[X4STEP]\nPROBE_INPUT = 4\nPROBE_NC = 1"));
    EXPECT_EQ(probe.probe_input, 4);
    EXPECT_TRUE(probe.probe_nc);
  }
  std::string smc = replaced(1, "[X4STEP]\nOUTPUT_MODE = smc-phase");
  smc.replace(smc.find("MOTOR = 3"), 9, "MOTOR = 4");
  EXPECT_REFUSED(smc,
                 "^m.ini:22:9: \\[JOINT_1\\] MOTOR: motor 4, but the SMC phase drive \\(OUTPUT_MODE\\) has "
                 "motors 1..3 only");
  EXPECT_REFUSED(
      replaced(19, "SCALE = 8000"),
      "^m.ini:19:9: \\[JOINT_0\\] SCALE: the axis' MAX_VELOCITY 20 would be 160000 steps/s at SCALE 8000: "
      "the port steps at most 100000$");
  EXPECT_REFUSED(
      replaced(11, "MAX_ACCELERATION = 2000"),
      "^m.ini:19:9: \\[JOINT_0\\] SCALE: the axis' MAX_ACCELERATION 2000 would be 1600000 steps/s\\^2 at "
      "SCALE 800: at most 1000000$");
  EXPECT_REFUSED(replaced(9, "MAX_LIMIT = 3000000"),
                 "^m.ini:19:[0-9]+: \\[JOINT_0\\] SCALE: the soft limits are beyond");
  EXPECT_REFUSED(replaced(19, "SCALE = 800\nHOME_INPUT = 1"),
                 "^m.ini:20:[0-9]+: \\[JOINT_0\\] HOME_INPUT: no homing without HOME_SEARCH_VEL");
  EXPECT_REFUSED(replaced(19, "SCALE = 800\nHOME_SEARCH_VEL = -5\nHOME_LATCH_VEL = 0\nHOME_INPUT = 1"),
                 "^m.ini:21:[0-9]+: \\[JOINT_0\\] HOME_LATCH_VEL: must not be 0");
  EXPECT_REFUSED(
      replaced(19, "SCALE = 800\nHOME_SEARCH_VEL = -5\nHOME_LATCH_VEL = -1\nHOME_INPUT = 1"),
      "^m.ini:21:18: \\[JOINT_0\\] HOME_LATCH_VEL: HOME_LATCH_VEL -1 has the sign of HOME_SEARCH_VEL -5: "
      "x4step latches "
      "where the switch releases while moving away from it, so give HOME_LATCH_VEL the opposite sign");
  EXPECT_REFUSED(replaced(19, "SCALE = 800\nHOME_SEARCH_VEL = -30\nHOME_LATCH_VEL = 1\nHOME_INPUT = 1"),
                 "^m.ini:20:19: \\[JOINT_0\\] HOME_SEARCH_VEL: HOME_SEARCH_VEL -30 is faster than the axis' "
                 "MAX_VELOCITY 20$");
  EXPECT_REFUSED(
      replaced(19, "SCALE = 800\nHOME_SEARCH_VEL = -5\nHOME_LATCH_VEL = 0.001\nHOME_INPUT = 1"),
      "^m.ini:21:18: \\[JOINT_0\\] HOME_LATCH_VEL: HOME_LATCH_VEL 0.001 is below 1 step/s at SCALE 800$");
  EXPECT_REFUSED(
      replaced(19, "SCALE = 800\nHOME_SEARCH_VEL = -5\nHOME_LATCH_VEL = 1\nHOME_INPUT = 1\nHOME = 200"),
      "^m.ini:23:8: \\[JOINT_0\\] HOME: HOME 200 is outside the axis' soft limits \\(MIN_LIMIT -10 .. "
      "MAX_LIMIT 100\\)$");
  EXPECT_REFUSED(
      replaced(19,
               "SCALE = 800\nHOME_SEARCH_VEL = -5\nHOME_LATCH_VEL = 1\nHOME_INPUT = 1\nHOME_OFFSET = -11"),
      "^m.ini:23:15: \\[JOINT_0\\] HOME_OFFSET: HOME_OFFSET -11 is outside the axis' soft limits "
      "\\(MIN_LIMIT -10 .. MAX_LIMIT 100\\)$");
  EXPECT_REFUSED(std::string(base) + "[AXIS_Y]\nMIN_LIMIT = 0\n",
                 "^m.ini:23:[0-9]+: \\[AXIS_Y\\]: axis Y is not in \\[TRAJ\\] COORDINATES \\(XZ\\)");
  EXPECT_REFUSED(std::string(base) + "[JOINT_2]\nMOTOR = 2\n",
                 "^m.ini:23:[0-9]+: \\[JOINT_2\\]: the machine has joints 0..1");
  EXPECT_REFUSED(replaced(5, "COORDINATES = XX"),
                 "^m.ini:5:[0-9]+: \\[TRAJ\\] COORDINATES: axis X given twice");
  // Two axes homing on one input at once: whose switch would it be?
  const std::string homes_x = "SCALE = 800\nHOME_SEARCH_VEL = -5\nHOME_LATCH_VEL = 1\nHOME_INPUT = 2";
  const std::string homes_z = "HOME_SEARCH_VEL = 5\nHOME_LATCH_VEL = -1\nHOME_INPUT = 2";
  EXPECT_REFUSED(replaced(19, homes_x) + homes_z + "\n",
                 "^m.ini:23:[0-9]+: \\[JOINT_1\\] HOME_SEQUENCE: joint 0 homes on input 2 in sequence 0 too");
  EXPECT_NO_THROW(read(replaced(19, homes_x) + homes_z + "\nHOME_SEQUENCE = 1\n"));
}
