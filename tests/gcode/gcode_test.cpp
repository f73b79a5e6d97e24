// SPDX-License-Identifier: GPL-2.0
// The G-code interpreter's refusals (issue 20): each names
// file:line:column and what is wrong, and nothing of a refused line
// reaches the sink. Modal group conflicts, bad arcs, words out of place.
#include "gcode.hpp"

#include <gtest/gtest.h>

#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace g = x4step::gcode;

namespace {

struct recorder : g::sink {
  std::vector<std::string> log;
  void straight_traverse(const g::straight &s) override { log.push_back("G0 " + pose(s.end)); }
  void straight_feed(const g::straight &s) override { log.push_back("G1 " + pose(s.end)); }
  void arc_feed(const g::arc &a) override {
    log.push_back("ARC " + pose(a.end) + " c " + num(a.centre_first) + " " + num(a.centre_second) + " t " +
                  std::to_string(a.turns));
  }
  void message(std::string_view m) override { log.push_back("MSG " + std::string(m)); }
  void debug(std::string_view m) override { log.push_back("DEBUG " + std::string(m)); }
  void dwell(double s) override { log.push_back("DWELL " + num(s)); }
  void warning(const g::error &w) override { log.push_back(std::string("WARN ") + w.what()); }
  void program_end(bool m30) override { log.push_back(m30 ? "M30" : "M2"); }
  static std::string num(double v) {
    std::ostringstream o;
    o << v;
    return o.str();
  }
  static std::string pose(const g::pose &p) { return num(p[0]) + " " + num(p[1]) + " " + num(p[2]); }
};

// Runs a program; returns the error's text ("" when accepted).
std::string run(const std::string &text, recorder *r = nullptr) {
  recorder local;
  g::interpreter in(r ? *r : local);
  std::istringstream s(text);
  try {
    in.run(s, "t.ngc");
  } catch (const g::error &e) {
    return e.what();
  }
  return "";
}

TEST(Gcode, AcceptsAndEnds) {
  recorder r;
  EXPECT_EQ(run("G21 G90\nG0 X1 Y2\nG1 X3 F100\nM2\nG0 X99\n", &r), "");
  ASSERT_EQ(r.log.size(), 3u);
  EXPECT_EQ(r.log[0], "G0 1 2 0");
  EXPECT_EQ(r.log[1], "G1 3 2 0");
  EXPECT_EQ(r.log[2], "M2");
}

TEST(Gcode, ErrorsNameFileLineColumn) {
  EXPECT_EQ(run("G21\nG0 X1 Y2 X3\nM2\n"), "t.ngc:2:10: multiple X words on one line");
  EXPECT_EQ(run("G21\n  G84 X1\nM2\n"),
            "t.ngc:2:3: G84 is not supported by this interpreter: expand canned cycles in your post processor"
            " (of the cycles, G73 G81 G82 G83 G85 G89 are)");
  EXPECT_EQ(
      run("G41 D1\nM2\n"),
      "t.ngc:1:1: G41 is not supported by this interpreter: let the CAM system compensate the tool radius"
      " (compensation \"in computer\")");
  EXPECT_EQ(run("G21\nG12.7\nM2\n"), "t.ngc:2:1: unknown G code G12.7");
  EXPECT_EQ(run("G0 X#1\nM2\n"), "t.ngc:1:5: numbered parameters (#) are not supported");
  EXPECT_EQ(run("G0 X[1+2]\nM2\n"), "t.ngc:1:5: expressions ([ ]) are not supported");
  EXPECT_EQ(run("o100 sub\nM2\n"),
            "t.ngc:1:1: O-word subroutines and control flow are not supported: have the post processor write "
            "plain moves");
  EXPECT_EQ(run("G0 U1\nM2\n"), "t.ngc:1:4: U words are not supported (axes are X Y Z A B C)");
  EXPECT_EQ(run("G0 X1 (open\nM2\n"), "t.ngc:1:7: comment not closed: ')' missing");
  EXPECT_EQ(run("G0 X1 (a (b) c)\nM2\n"), "t.ngc:1:10: nested comment: '(' inside a comment");
  EXPECT_EQ(run("G0 X1 N5\nM2\n"), "t.ngc:1:7: N word (line number) must begin the line");
  EXPECT_EQ(run("G0 X\nM2\n"), "t.ngc:1:4: bad number after X (a value must follow the letter)");
  EXPECT_EQ(run("G0 X1 $\nM2\n"), "t.ngc:1:7: unexpected character '$'");
  EXPECT_EQ(run("M62 P1\nM2\n"), "t.ngc:1:1: M62 is not supported by this interpreter");
  EXPECT_EQ(run("G0 X1\n"), "t.ngc:2:1: file ended without M2, M30 or '%'");
  EXPECT_EQ(run("%\nG0 X1\n"), "t.ngc:3:1: file ended without its closing '%'");
}

TEST(Gcode, ModalGroupConflicts) {
  EXPECT_EQ(run("G0 G1 X1\nM2\n"), "t.ngc:1:4: G1 and G0 are in the same modal group (group 1)");
  EXPECT_EQ(run("G20 G21\nM2\n"), "t.ngc:1:5: G21 and G20 are in the same modal group (group 6)");
  EXPECT_EQ(run("G17 G18\nM2\n"), "t.ngc:1:5: G18 and G17 are in the same modal group (group 2)");
  EXPECT_EQ(run("G90 G91\nM2\n"), "t.ngc:1:5: G91 and G90 are in the same modal group (group 3)");
  EXPECT_EQ(run("G54 G55\nM2\n"), "t.ngc:1:5: G55 and G54 are in the same modal group (group 12)");
  EXPECT_EQ(run("G92 X0 G28\nM2\n"), "t.ngc:1:8: G28 and G92 are in the same modal group (group 0)");
  EXPECT_EQ(run("M3 M4\nM2\n"), "t.ngc:1:4: M4 and M3 are in the same modal group");
  EXPECT_EQ(run("M0 M2\n"), "t.ngc:1:4: M2 and M0 are in the same modal group");
  EXPECT_EQ(run("M7 M8\nM2\n"), "");  // mist and flood together: LinuxCNC allows it
  EXPECT_EQ(run("G1 F1 G92 X0\nM2\n"), "t.ngc:1:1: G1 and G92 both use axis values: one of them per line");
  EXPECT_EQ(run("X1\nM2\n"),
            "t.ngc:1:1: axis values without a G code that uses them (no motion mode is active: G80)");
  EXPECT_EQ(run("G0 X1\nG80 X2\nM2\n"), "t.ngc:2:5: axis values with G80: G80 takes none");
  EXPECT_EQ(run("G1 G53 X1 F1\nG91\nG53 G1 X1\nM2\n"),
            "t.ngc:3:1: G53 with G91: G53 takes absolute values only");
  EXPECT_EQ(run("G2 G53 X1 I1\nM2\n"), "t.ngc:1:4: G53 needs G0 or G1");
}

TEST(Gcode, WordsWithoutAUser) {
  EXPECT_EQ(run("G0 X1 I2\nM2\n"), "t.ngc:1:7: I word with no G2 or G3 to use it");
  EXPECT_EQ(run("G1 X1 R2 F1\nM2\n"), "t.ngc:1:7: R word with no G2, G3 or canned cycle to use it");
  EXPECT_EQ(run("G0 X1 L2\nM2\n"), "t.ngc:1:7: L word with no G10 or canned cycle to use it");
  EXPECT_EQ(run("G0 X1 P2\nM2\n"), "t.ngc:1:7: P word with no G4, G10, G2/G3, G82/G89 or G64 to use it");
  EXPECT_EQ(run("G0 X1 Q2\nM2\n"), "t.ngc:1:7: Q word with no G64, G73 or G83 to use it");
  EXPECT_EQ(run("G81 X1 Z-1 R1 Q2 F9\nM2\n"), "t.ngc:1:15: Q word with no G64, G73 or G83 to use it");
  EXPECT_EQ(run("G83 X1 Z-1 R1 Q2 P1 F9\nM2\n"),
            "t.ngc:1:18: P word with no G4, G10, G2/G3, G82/G89 or G64 to use it");
  // A cycle in force but no axis word: the line drills nothing, R is unused.
  EXPECT_EQ(run("G81 X1 Z-1 R1 F9\nR2\nM2\n"), "t.ngc:2:1: R word with no G2, G3 or canned cycle to use it");
  EXPECT_EQ(run("G0 X1 H2\nM2\n"), "t.ngc:1:7: H word with no G43 to use it");
  EXPECT_EQ(run("G4\nM2\n"), "t.ngc:1:1: G4 needs P (the dwell time, seconds)");
  EXPECT_EQ(run("G10 L1 P1 X0\nM2\n"), "t.ngc:1:5: only G10 L2 and G10 L20 are supported");
  EXPECT_EQ(run("G1 X1\nM2\n"), "t.ngc:1:1: G1 with a feed rate of zero (no F given)");
  EXPECT_EQ(run("G93 G1 X1 F10\nX2\nM2\n"),
            "t.ngc:2:1: G1 in inverse time mode (G93) needs an F word on its line");
}

// Runs a program with a tool table of tool 1 only (length 2 mm).
std::string run_with_table(const std::string &text, recorder &r) {
  g::interpreter in(r);
  std::map<int, g::tool> table;
  table[1].offset[2] = 2;
  in.set_tool_table(table);
  std::istringstream s(text);
  try {
    in.run(s, "t.ngc");
  } catch (const g::error &e) {
    return e.what();
  }
  return "";
}

TEST(Gcode, ToolLengthWithoutATable) {
  // No table: length 0, and a warning with the line, before its motion.
  recorder r;
  EXPECT_EQ(run("G0 Z5\nT7 M6\nG43 H7 G0 Z5\nM2\n", &r), "");
  ASSERT_EQ(r.log.size(), 4u);
  EXPECT_EQ(r.log[1],
            "WARN t.ngc:3:5: warning: G43 H7: no tool table, so tool length 0 (add [EMCIO] TOOL_TABLE to the "
            "machine file for the tools' lengths)");
  EXPECT_EQ(r.log[2], "G0 0 0 5");
  EXPECT_EQ(r.log[3], "M2");
  // A table without the tool: refused, saying how to add it; a tool in it has its length.
  recorder t;
  EXPECT_EQ(run_with_table("G43 H7\nM2\n", t),
            "t.ngc:1:5: tool 7 is not in the tool table: add a line \"T7 P7 Z<length>\" to it");
  recorder u;
  EXPECT_EQ(run_with_table("G43 H1 G0 Z5\nM2\n", u), "");
  ASSERT_EQ(u.log.size(), 2u);
  EXPECT_EQ(u.log[0], "G0 0 0 7");
  // A refused line gives no warning.
  recorder v;
  EXPECT_NE(run("G43 H7 G0 X1 Q1\nM2\n", &v), "");
  EXPECT_TRUE(v.log.empty());
}

TEST(Gcode, ByteOrderMarkAndNonAscii) {
  recorder r;
  EXPECT_EQ(run("\xEF\xBB\xBFG21 G0 X1\nM2\n", &r), "");
  ASSERT_EQ(r.log.size(), 2u);
  EXPECT_EQ(r.log[0], "G0 1 0 0");
  // Columns count from after the mark, as an editor shows the line.
  EXPECT_EQ(run("\xEF\xBB\xBFG0 X1 $\nM2\n"), "t.ngc:1:7: unexpected character '$'");
  // Anywhere else it is a character that has no place, named whole.
  EXPECT_EQ(run("G0 X1\n\xEF\xBB\xBFG0 X2\nM2\n"), "t.ngc:2:1: unexpected character '\xEF\xBB\xBF'");
  EXPECT_EQ(run("G0 X1 \xC2\xB0\nM2\n"), "t.ngc:1:7: unexpected character '\xC2\xB0'");
  EXPECT_EQ(run("G0 X1 \xB0\nM2\n"), "t.ngc:1:7: unexpected byte 0xb0 (not ASCII nor UTF-8)");
}

TEST(Gcode, MessagesInTheirPlace) {
  recorder r;
  EXPECT_EQ(run("G0 X1\n(MSG,first)\nG0 X2 (DEBUG, second)\n(debug,third)\n(PRINT, not shown)\nM2\n", &r),
            "");
  ASSERT_EQ(r.log.size(), 6u);
  EXPECT_EQ(r.log[0], "G0 1 0 0");
  EXPECT_EQ(r.log[1], "MSG first");
  EXPECT_EQ(r.log[2], "DEBUG  second");
  EXPECT_EQ(r.log[3], "G0 2 0 0");
  EXPECT_EQ(r.log[4], "DEBUG third");
  EXPECT_EQ(r.log[5], "M2");
  EXPECT_EQ(run("(MSG,a) (DEBUG,b)\nM2\n"), "t.ngc:1:9: more than one (MSG,...) or (DEBUG,...) on one line");
}

// The cycles' motions are held to rs274's by the oracle (cam/cycles.ngc);
// here what a cycle refuses, and one cycle's moves spelled out.
TEST(Gcode, DrillingCycles) {
  recorder r;
  EXPECT_EQ(run("G21 G0 Z10\nG98 G82 X1 Y2 Z-3 R2 P0.5 F60\nX4\nM2\n", &r), "");
  const std::vector<std::string> want = {"G0 0 0 10", "G0 1 2 10", "G0 1 2 2",  "G1 1 2 -3",
                                         "DWELL 0.5", "G0 1 2 10", "G0 4 2 10", "G0 4 2 2",
                                         "G1 4 2 -3", "DWELL 0.5", "G0 4 2 10", "M2"};
  EXPECT_EQ(r.log, want);
  EXPECT_EQ(run("G81 X1 Z-1 F9\nM2\n"), "t.ngc:1:1: G81 needs R (the retract plane)");
  EXPECT_EQ(run("G81 X1 R1 F9\nM2\n"), "t.ngc:1:1: G81 needs Z (the bottom of the hole)");
  EXPECT_EQ(run("G82 X1 Z-1 R1 F9\nM2\n"), "t.ngc:1:1: G82 needs P (the dwell at the bottom, seconds)");
  EXPECT_EQ(run("G83 X1 Z-1 R1 F9\nM2\n"), "t.ngc:1:1: G83 needs Q (the depth of each peck)");
  EXPECT_EQ(run("G73 X1 Z-1 R1 Q0 F9\nM2\n"), "t.ngc:1:15: G73 Q (the depth of each peck) must be above 0");
  EXPECT_EQ(run("G81 X1 Z-1 R-2 F9\nM2\n"),
            "t.ngc:1:12: G81: the retract plane R is below the bottom Z (R -2.000000, Z -1.000000)");
  EXPECT_EQ(run("G81 X1 Z-1 R1\nM2\n"), "t.ngc:1:1: G81 with a feed rate of zero (no F given)");
  EXPECT_EQ(run("G93 G81 X1 Z-1 R1 F9\nM2\n"),
            "t.ngc:1:5: G81 in inverse time mode (G93): canned cycles need G94");
  EXPECT_EQ(run("G18 G81 X1 Z-1 R1 F9\nM2\n"),
            "t.ngc:1:5: G81 in the XZ (G18) plane: canned cycles run in the XY plane (G17) only here");
  EXPECT_EQ(run("G81 X1 Z-1 R1 L0 F9\nM2\n"), "t.ngc:1:15: G81 L (repeats) must be a whole number 1..10000");
  EXPECT_EQ(run("G81 X1 Z-1 R1 A5 F9\nM2\n"),
            "t.ngc:1:15: A word in a canned cycle: rotary axes stay put in cycles");
  // A repeat of the cycle in force may leave R, Z, P and Q out; another cycle may not.
  EXPECT_EQ(run("G83 X1 Z-1 R1 Q1 F9\nX2\nG73 X3\nM2\n"), "t.ngc:3:1: G73 needs R (the retract plane)");
}

TEST(Gcode, BadArcs) {
  // IJK: the end is not on the circle (LinuxCNC's spiral tolerance).
  EXPECT_EQ(run("G21 G1 F100 X0 Y0\nG2 X10 Y0 I4 J0\nM2\n"),
            "t.ngc:2:11: radius to the end of the arc (6) differs from the radius to its start (4)");
  // Within it: a rounded centre is accepted.
  EXPECT_EQ(run("G21 G1 F100 X0 Y0\nG2 X10 Y0 I5.001 J0\nM2\n"), "");
  EXPECT_EQ(run("G1 F100 X0\nG2 X0 Y0 I0 J0\nM2\n"), "t.ngc:2:10: zero-radius arc");
  EXPECT_EQ(
      run("G1 F100 X0\nG2 X10 Y0 R4\nM2\n"),
      "t.ngc:2:11: arc radius too small to reach the end point (half the chord is 5.000000, R 4.000000)");
  EXPECT_EQ(run("G1 F100 X0\nG2 X0 Y0 R4\nM2\n"),
            "t.ngc:2:10: R arc whose end point is its start point (the centre is undefined: use I J K)");
  EXPECT_EQ(run("G1 F100 X0\nG2 X10 R5 I5\nM2\n"), "t.ngc:2:8: mixed R and I J K forms for an arc: use one");
  EXPECT_EQ(run("G1 F100 X0\nG2 X10 K5\nM2\n"), "t.ngc:2:8: K word for an arc in the XY (G17) plane");
  EXPECT_EQ(run("G1 F100 X0\nG2 X10\nM2\n"), "t.ngc:2:1: G2 needs R or the centre (I J K)");
  EXPECT_EQ(run("G1 F100 X0\nG2 Z1 R5\nM2\n"),
            "t.ngc:2:1: X and Y words missing for an R arc in the XY (G17) plane");
  EXPECT_EQ(run("G1 F100 X0\nG90.1 G2 X10 I5\nM2\n"),
            "t.ngc:2:7: J word missing for an arc with absolute centre (G90.1)");
  EXPECT_EQ(run("G1 F100 X0\nG2 X10 I5 P1.5\nM2\n"),
            "t.ngc:2:11: G2 P (turns) must be a whole number 1..10000");
  EXPECT_EQ(run("G1 F100 X0\nG2 X10 I5 P1000000000\nM2\n"),
            "t.ngc:2:11: G2 P (turns) must be a whole number 1..10000");
  // R 0 with an end within the radius tolerance: no centre (not NaN).
  EXPECT_EQ(run("G21 G1 F100 X0 Y0\nG2 X0.001 Y0 R0\nM2\n"), "t.ngc:2:14: zero-radius arc (R 0.000000)");
}

// Numbers that do not fit the words' meaning are refused, not converted.
TEST(Gcode, HugeNumbers) {
  EXPECT_EQ(run("T3000000000\nM2\n"), "t.ngc:1:1: T must be a tool number (a whole number 0..99999)");
  EXPECT_EQ(run("G1 F1 X0\nG43 H3000000000\nM2\n"),
            "t.ngc:2:5: H must be a tool number (a whole number 0..99999)");
  EXPECT_EQ(run("G1234567890123456789\nM2\n"), "t.ngc:1:1: unknown G code");
  EXPECT_EQ(run("M99999999999999999999\nM2\n"), "t.ngc:1:1: unknown M code");
}

TEST(Gcode, RefusedLineReachesNothing) {
  recorder r;
  g::interpreter in(r);
  EXPECT_TRUE(in.execute_line("G1 X1 F100", "mdi", 1));
  EXPECT_THROW(in.execute_line("G0 X5 Y1 Y2", "mdi", 2), g::error);
  EXPECT_THROW(in.execute_line("M3 G2 X3 I9", "mdi", 3), g::error);  // spindle before the bad arc
  ASSERT_EQ(r.log.size(), 1u);
  EXPECT_EQ(in.position()[0], 1.0);
  // Nor does it change the state: units, distance mode, feed.
  in.set_tool_table({});
  EXPECT_THROW(in.execute_line("G20 G91 F7 G43 H7 X1", "mdi", 4), g::error);  // no tool 7
  EXPECT_EQ(in.program_units(), g::units::mm);
  EXPECT_TRUE(in.execute_line("G1 X2", "mdi", 5));
  ASSERT_EQ(r.log.size(), 2u);
  EXPECT_EQ(r.log[1], "G1 2 0 0");
  EXPECT_EQ(in.position()[0], 2.0);
}

TEST(Gcode, CheckBeforeMotion) {
  recorder r;
  g::interpreter in(r);
  std::istringstream s("G0 X1\nG1 X2 F1\nG2 X3 I9\nM2\n");
  try {
    in.check(s, "p.ngc");
    FAIL() << "accepted";
  } catch (const g::error &e) {
    EXPECT_EQ(e.line(), 3);
    EXPECT_EQ(e.column(), 7);
  }
  EXPECT_TRUE(r.log.empty());
}

TEST(Gcode, UnitsOffsetsAndArcs) {
  recorder r;
  EXPECT_EQ(
      run("G20 G0 X1 (MSG, hello)\nG92 X0\nG0 X1\nG91 G1 X-1 F10\nG90 G3 X1 Y1 R1\nG2 X1 Y1 I-1 J0 P2\nM30\n",
          &r),
      "");
  ASSERT_EQ(r.log.size(), 7u);
  EXPECT_EQ(r.log[0], "MSG  hello");  // the message first: NIST's order of execution
  EXPECT_EQ(r.log[1], "G0 25.4 0 0");
  EXPECT_EQ(r.log[2], "G0 50.8 0 0");
  EXPECT_EQ(r.log[3], "G1 25.4 0 0");
  EXPECT_EQ(r.log[4], "ARC 50.8 25.4 0 c 25.4 25.4 t 1");  // G3 R > 0: centre left of the chord
  EXPECT_EQ(r.log[5], "ARC 50.8 25.4 0 c 25.4 25.4 t -2");
}

}  // namespace

// A sink whose probe stops where the test says: `stop_at` (machine
// coordinates) with `tripped`; without it, contact at the end.
struct prober : recorder {
  bool have_stop = false, tripped = true;
  g::pose stop_at{}, trip_at{};
  std::vector<g::probe_kind> kinds;
  std::vector<double> feeds;
  g::probe_outcome straight_probe(const g::straight &s, g::probe_kind k) override {
    log.push_back("PROBE " + pose(s.end));
    kinds.push_back(k);
    feeds.push_back(s.feed);
    if (!have_stop) return {s.end, true, s.end};
    return {stop_at, tripped, trip_at};
  }
};

TEST(Gcode, ProbeGoesOnFromWhereItStopped) {
  prober p;
  p.have_stop = true;
  p.stop_at = {0, 0, -3.5, 0, 0, 0};
  p.trip_at = {0, 0, -3.25, 0, 0, 0};
  g::interpreter in(p);
  EXPECT_TRUE(in.execute_line("G21 G90 G38.2 Z-10 F120", "mdi", 1));
  EXPECT_EQ(in.position()[g::Z], -3.5);
  // Incremental moves count from the stop, absolute ones are where they were.
  EXPECT_TRUE(in.execute_line("G91 G0 Z1", "mdi", 2));
  EXPECT_TRUE(in.execute_line("G90 G1 X2", "mdi", 3));
  // G38.3 without contact is no error: the program goes on from the stop.
  p.tripped = false;
  p.stop_at = {2, 0, -8, 0, 0, 0};
  EXPECT_TRUE(in.execute_line("G38.3 Z-8", "mdi", 4));
  EXPECT_TRUE(in.execute_line("G91 G1 X1", "mdi", 5));
  const std::vector<std::string> want = {"PROBE 0 0 -10", "G0 0 0 -2.5", "G1 2 0 -2.5", "PROBE 2 0 -8",
                                         "G1 3 0 -8"};
  EXPECT_EQ(p.log, want);
  const std::vector<g::probe_kind> kinds = {g::probe_kind::toward_or_error, g::probe_kind::toward};
  EXPECT_EQ(p.kinds, kinds);
  EXPECT_EQ(p.feeds, std::vector<double>({120, 120}));
}

TEST(Gcode, ProbeKindsAndUnits) {
  prober p;
  g::options o;
  o.machine_units = g::units::inch;  // a program in mm on an inch machine
  g::interpreter in(p, o);
  EXPECT_TRUE(in.execute_line("G21 G38.2 X25.4 F254", "mdi", 1));
  EXPECT_TRUE(in.execute_line("G38.3 X50.8", "mdi", 2));
  EXPECT_TRUE(in.execute_line("G38.4 X0", "mdi", 3));
  EXPECT_TRUE(in.execute_line("G38.5 X25.4", "mdi", 4));
  EXPECT_TRUE(in.execute_line("X0", "mdi", 5));  // modal: G38.5 again
  const std::vector<g::probe_kind> kinds = {g::probe_kind::toward_or_error, g::probe_kind::toward,
                                            g::probe_kind::away_or_error, g::probe_kind::away,
                                            g::probe_kind::away};
  EXPECT_EQ(p.kinds, kinds);
  EXPECT_EQ(p.log.front(), "PROBE 1 0 0");
  EXPECT_EQ(p.log.back(), "PROBE 0 0 0");
  EXPECT_EQ(p.feeds.front(), 10);  // inches per minute
}

TEST(Gcode, ProbeWithoutContactIsAnErrorAtItsLine) {
  prober p;
  p.have_stop = true;
  p.tripped = false;
  p.stop_at = {0, 0, -10, 0, 0, 0};
  p.trip_at = p.stop_at;
  EXPECT_EQ(run("G21 F100\nG0 Z1\n  G38.2 Z-10 M2\nG0 X5\nM2\n", &p),
            "t.ngc:3:3: G38.2 move finished without making contact");
  // The stop is where the interpreter stands, and the M2 behind it never came.
  EXPECT_EQ(p.log.back(), "PROBE 0 0 -10");
  p.log.clear();
  EXPECT_EQ(run("G21 F100\nG38.4 Z-10\nM2\n", &p), "t.ngc:2:1: G38.4 move finished without breaking contact");
  // G38.3 and G38.5 go on.
  EXPECT_EQ(run("G21 F100\nG38.3 Z-10\nG38.5 Z-12\nM2\n", &p), "");

  // Tripped before the first step (the trip is the start): LinuxCNC's
  // "probe is already tripped" for G38.2 and G38.4, not for G38.3/G38.5.
  p.tripped = true;
  p.stop_at = p.trip_at = {0, 0, 1, 0, 0, 0};
  EXPECT_EQ(run("G21 F100\nG0 Z1\nX0 G38.2 Z-10\nM2\n", &p),
            "t.ngc:3:4: probe is already tripped when starting the G38.2 move");
  EXPECT_EQ(run("G21 F100\nG0 Z1\nG38.4 Z5\nM2\n", &p),
            "t.ngc:3:1: probe is already clear when starting the G38.4 move");
  EXPECT_EQ(run("G21 F100\nG0 Z1\nG38.3 Z-10\nG38.5 Z5\nM2\n", &p), "");

  // MDI: after the error the interpreter stands where the machine stopped.
  prober q;
  q.have_stop = true;
  q.tripped = false;
  q.stop_at = q.trip_at = {0, 0, -10, 0, 0, 0};
  g::interpreter in(q);
  EXPECT_THROW(in.execute_line("G21 G38.2 Z-10 F50", "mdi", 1), g::error);
  EXPECT_EQ(in.position()[g::Z], -10);
  EXPECT_TRUE(in.execute_line("G91 G1 Z2", "mdi", 2));
  EXPECT_EQ(q.log.back(), "G1 0 0 -8");
  // An M2 behind a failed probe never came: the program has not ended, and
  // its modes (G91 here) are not reset.
  EXPECT_THROW(in.execute_line("G38.2 Z-2 M2", "mdi", 3), g::error);
  EXPECT_TRUE(in.execute_line("G1 Z1", "mdi", 4));
  EXPECT_EQ(q.log.back(), "G1 0 0 -9");
}

TEST(Gcode, ProbeRefusals) {
  // Positions LinuxCNC's rs274 refuses too (tests/gcode/probe/refusals.txt).
  EXPECT_EQ(run("G21 F100\nG38.2 F50\nM2\n"),
            "t.ngc:2:1: G38.2 needs an axis word (where the probe move ends)");
  EXPECT_EQ(run("G21\n G38.2 Z-10\nM2\n"), "t.ngc:2:2: G38.2 with a feed rate of zero (no F given)");
  EXPECT_EQ(run("G21 F100\nZ-3 G38.3\nG0 Z1\nZ-10\nM2\n"), "");
  EXPECT_EQ(
      run("G21 F100\nG38.3 Z-3\nG0 Z-3\nG38.2 Z-3\nM2\n"),
      "t.ngc:4:1: G38.2 ends where it starts: the probe move needs a length (LinuxCNC: \"start point too "
      "close to probe point\")");
  EXPECT_EQ(
      run("G21 F100\nG91 Z0 G38.4\nM2\n"),
      "t.ngc:2:8: G38.4 ends where it starts: the probe move needs a length (LinuxCNC: \"start point too "
      "close to probe point\")");
  EXPECT_EQ(run("G21 F100\nG38.3 Z0\nG38.5 Z0\nM2\n"), "");  // allowed, as in LinuxCNC
  EXPECT_EQ(run("G21 G93\nG38.2 Z-10 F2\nM2\n"),
            "t.ngc:2:1: G38.2 in inverse time mode (G93): probing needs G94 and a feed rate (F)");
  // LinuxCNC would probe at the F100 of G94 here: refused.
  EXPECT_EQ(run("G21 F100\nG93\nG38.3 Z-10 F2\nM2\n"),
            "t.ngc:3:1: G38.3 in inverse time mode (G93): probing needs G94 and a feed rate (F)");
  EXPECT_EQ(run("G21 F100\nG53 G38.2 Z-10\nM2\n"), "t.ngc:2:1: G53 needs G0 or G1");
  EXPECT_EQ(run("G21 F100\nG38.2 Z-10 R3\nM2\n"),
            "t.ngc:2:12: R word with no G2, G3 or canned cycle to use it");
  EXPECT_EQ(run("G21 F100\nG28 G38.2 Z-10\nM2\n"),
            "t.ngc:2:5: G38.2 and G28 both use axis values: one of them per line");
  // A refused probe line probes nothing, and what came before it on the line neither.
  prober p;
  EXPECT_EQ(
      run("G21 F100\nM3 S100 G38.2 Z0\nM2\n", &p),
      "t.ngc:2:9: G38.2 ends where it starts: the probe move needs a length (LinuxCNC: \"start point too "
      "close to probe point\")");
  EXPECT_TRUE(p.log.empty());
}

TEST(Gcode, ProbeInACheckAndSetPosition) {
  // check(): no sink, contact at the programmed end.
  prober p;
  g::interpreter in(p);
  std::istringstream prog("G21 F100\nG38.2 Z-10\nG91 G1 Z1\nG38.3 Z-1\nM2\n");
  EXPECT_NO_THROW(in.check(prog, "t.ngc"));
  EXPECT_TRUE(p.log.empty());
  // set_position: the machine stands elsewhere (after a hold, an abort).
  EXPECT_TRUE(in.execute_line("G21 G91 G1 X1 F100", "mdi", 1));
  in.set_position({5, 6, 7, 8, 0, 0});
  EXPECT_EQ(in.position(), (g::pose{5, 6, 7, 8, 0, 0}));
  EXPECT_TRUE(in.execute_line("X1 A1", "mdi", 2));
  EXPECT_EQ(p.log.back(), "G1 6 6 7");
  EXPECT_EQ(in.position()[g::A], 9);
  // In inches: set_position takes machine units.
  g::options o;
  o.machine_units = g::units::inch;
  g::interpreter inch(p, o);
  inch.set_position({1, 0, 0, 0, 0, 0});
  EXPECT_TRUE(inch.execute_line("G21 G91 G1 X25.4 F100", "mdi", 1));
  EXPECT_EQ(p.log.back(), "G1 2 0 0");
}
