// SPDX-License-Identifier: GPL-2.0
// The planner (lib/machine/planner.hpp): chords within the arc tolerance,
// ends rounded once (no accumulation), GRBL's junction speeds, speed and
// acceleration limits per axis, units, and soft limits with file:line.
#include "planner.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <optional>
#include <sstream>
#include <vector>

namespace m = x4step::machine;
namespace g = x4step::gcode;
using x4step::axis;

namespace {

constexpr double ppu = 10000;  // path units per mm

// X Y Z on motors 1 2 3; X 0..200, Y 0..100, Z -50..0.
std::string machine_text(double x_scale = 1000, double y_scale = 1000, double y_accel = 100) {
  std::ostringstream o;
  o << "[X4STEP]\nARC_TOLERANCE = 0.01\nJUNCTION_DEVIATION = 0.02\n"
    << "[TRAJ]\nCOORDINATES = XYZ\nLINEAR_UNITS = mm\n"
    << "[AXIS_X]\nMIN_LIMIT = 0\nMAX_LIMIT = 200\nMAX_VELOCITY = 100\nMAX_ACCELERATION = 100\n"
    << "[AXIS_Y]\nMIN_LIMIT = 0\nMAX_LIMIT = 100\nMAX_VELOCITY = 50\nMAX_ACCELERATION = " << y_accel << "\n"
    << "[AXIS_Z]\nMIN_LIMIT = -50\nMAX_LIMIT = 0\nMAX_VELOCITY = 10\nMAX_ACCELERATION = 50\n"
    << "[JOINT_0]\nMOTOR = 1\nSCALE = " << x_scale << "\n"
    << "[JOINT_1]\nMOTOR = 2\nSCALE = " << y_scale << "\n"
    << "[JOINT_2]\nMOTOR = 3\nSCALE = -400\n";
  return o.str();
}

// The machine with a touch probe on input 4 (G38.x needs one).
m::machine with_probe(m::machine mc) {
  mc.probe_input = 4;
  return mc;
}

m::machine machine_of(const std::string &text) {
  std::istringstream in(text);
  return m::read(in, "test.ini");
}

struct recorded {
  x4step::segment seg;
  m::segment_info info;
};

struct recorder : m::planner_output {
  std::vector<recorded> segs;
  int stops = 0;
  void segment(const x4step::segment &s, const m::segment_info &i) override { segs.push_back({s, i}); }
  void dwell(double) override { stops++; }
};

struct plan {
  recorder out;
  m::plan_summary sum;
};

plan run(const m::machine &mc, const std::string &program, const g::pose &start = {}) {
  plan p;
  std::istringstream in(program);
  p.sum = m::plan_program(mc, in, "prog.ngc", p.out, start);
  return p;
}

std::array<long, 4> steps_sum(const recorder &r) {
  std::array<long, 4> s{};
  for (const auto &x : r.segs)
    for (int a = 0; a < 4; a++) s[size_t(a)] += x.seg.steps(axis(a + 1));
  return s;
}

// The distance of point p from the segment a-b (2-D).
double distance_to_chord(double px, double py, double ax, double ay, double bx, double by) {
  const double dx = bx - ax, dy = by - ay, l2 = dx * dx + dy * dy;
  double t = l2 > 0 ? ((px - ax) * dx + (py - ay) * dy) / l2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  return std::hypot(px - ax - t * dx, py - ay - t * dy);
}

// The farthest the arc around (cx, cy) of radius r strays from the chords
// through the points (x, y), sampled finely along the arc between them.
double chord_error(const std::vector<std::pair<double, double>> &pts, double cx, double cy, double r) {
  double worst = 0;
  for (size_t i = 1; i < pts.size(); i++) {
    const double a0 = std::atan2(pts[i - 1].second - cy, pts[i - 1].first - cx);
    double a1 = std::atan2(pts[i].second - cy, pts[i].first - cx);
    if (a1 > a0) a1 -= 2 * M_PI;  // clockwise
    for (int k = 0; k <= 50; k++) {
      const double a = a0 + (a1 - a0) * k / 50;
      worst = std::max(worst, distance_to_chord(cx + r * std::cos(a), cy + r * std::sin(a), pts[i - 1].first,
                                                pts[i - 1].second, pts[i].first, pts[i].second));
    }
  }
  return worst;
}

}  // namespace

TEST(Planner, ArcChordsStayWithinTheTolerance) {
  const m::machine mc = machine_of(machine_text());
  // A full clockwise circle of radius 30 around (100, 50).
  const plan p = run(mc, "G0 X130 Y50\nG2 X130 Y50 I-30 J0 F600\nM2\n");
  std::vector<std::pair<double, double>> programmed{{130, 50}}, executed{{130, 50}};
  std::array<long, 4> at{130000, 50000, 0, 0};
  for (size_t i = 1; i < p.out.segs.size(); i++) {
    const auto &s = p.out.segs[i];
    EXPECT_EQ(s.info.line, 2);
    EXPECT_EQ(s.seg.tag(), 2u);
    programmed.push_back({s.info.end[0], s.info.end[1]});
    at[0] += s.seg.steps(axis::x);
    at[1] += s.seg.steps(axis::y);
    executed.push_back({at[0] / 1000.0, at[1] / 1000.0});
  }
  // As few chords as keep within 0.01 mm: 2 acos(1 - 0.01 / 30) per chord.
  const double most = 2 * std::acos(1 - 0.01 / 30);
  EXPECT_EQ(long(programmed.size() - 1), long(std::ceil(2 * M_PI / most)));
  EXPECT_LE(chord_error(programmed, 100, 50, 30), 0.01 + 1e-9);
  EXPECT_GT(chord_error(programmed, 100, 50, 30), 0.009);  // not needlessly fine
  // What the motors do: within the tolerance and one step (0.001 mm).
  EXPECT_LE(chord_error(executed, 100, 50, 30), 0.011);
  EXPECT_EQ(at[0], 130000);
  EXPECT_EQ(at[1], 50000);
}

TEST(Planner, HelixMovesTheNormalAxisLinearly) {
  const m::machine mc = machine_of(machine_text());
  const plan p = run(mc, "G0 X110 Y50\nG17 G3 X90 Y50 Z-10 I-10 J0 F300\nM2\n");
  ASSERT_GT(p.out.segs.size(), 3u);
  const size_t n = p.out.segs.size() - 1;
  for (size_t i = 1; i <= n; i++) EXPECT_NEAR(p.out.segs[i].info.end[2], -10.0 * double(i) / double(n), 1e-9);
  EXPECT_EQ(p.sum.steps[2], 4000);  // Z -10 mm at SCALE -400
  EXPECT_GT(p.sum.max[1], 59.99);   // counter-clockwise from (110, 50): over the top
}

TEST(Planner, EndsAreRoundedOnceNeverAccumulated) {
  // 320 steps/mm: 0.0003 mm is 0.096 steps. Rounded move by move, every
  // move would be 0 steps; rounded once from the absolute point, the
  // 10 000 moves end at round(3.0 * 320) = 960 and round(1.7 * 333) = 566.
  const m::machine mc = machine_of(machine_text(320, 333));
  std::string moves;
  for (int i = 0; i < 10000; i++) moves += "X0.0003 Y0.00017\n";
  const plan q = run(mc, "G0 X10 Y10\nG91 G1 F100\n" + moves + "M2\n");
  EXPECT_EQ(q.sum.steps[0], std::lround(13.0 * 320));
  EXPECT_EQ(q.sum.steps[1], std::lround(11.7 * 333));
  EXPECT_EQ(steps_sum(q.out), q.sum.steps);
  // Then 1000 small full circles and a line: still exact.
  std::string circles;
  for (int i = 0; i < 1000; i++) circles += "G2 X20 Y10 I-0.0071 J0.0033\n";
  const plan p =
      run(mc, "G0 X10 Y10\nG91 G1 F100\n" + moves + "G90 G1 X20 Y10\n" + circles + "G1 X20.7 Y3.3\nM2\n");
  EXPECT_EQ(steps_sum(p.out)[0], std::lround(20.7 * 320));
  EXPECT_EQ(steps_sum(p.out)[1], std::lround(3.3 * 333));
  EXPECT_EQ(p.sum.steps, steps_sum(p.out));
  EXPECT_GT(p.out.segs.size(), 4000u);
  EXPECT_LT(q.out.segs.size(), 10000u);  // moves below a step make no segment of their own
}

TEST(Planner, StartsWhereTheMachineStands) {
  const m::machine mc = machine_of(machine_text());
  const plan p = run(mc, "G1 X50.0004 F600\nM2\n", g::pose{50, 20, -1, 0, 0, 0});
  ASSERT_EQ(p.out.segs.size(), 0u);  // 0.4 steps: nothing to do
  EXPECT_EQ(p.sum.steps[0], 50000);
  EXPECT_EQ(p.sum.steps[1], 20000);
  EXPECT_EQ(p.sum.steps[2], 400);
}

TEST(Planner, JunctionSpeedIsGrblsForTheAngle) {
  // 90 degrees, X and Y at 100 mm/s^2, junction deviation 0.02 mm. By
  // hand, as GRBL's planner.c: cos(theta) = -(in . out) = 0; sin(theta/2)
  // = sqrt(0.5 (1 - 0)) = 0.707107; the junction vector (-1, 1)/sqrt 2
  // limits the acceleration to 100 / 0.707107 = 141.421 mm/s^2;
  // v^2 = 141.421 * 0.02 * 0.707107 / (1 - 0.707107) = 6.828427,
  // v = 2.613126 mm/s = 26131 path units/s.
  const m::machine mc = machine_of(machine_text());
  plan p = run(mc, "G1 X10 F3000\nY10\nM2\n");
  ASSERT_EQ(p.out.segs.size(), 2u);
  EXPECT_EQ(p.out.segs[0].seg.entry_speed(), 0u);  // from rest
  EXPECT_NEAR(p.out.segs[1].seg.entry_speed(), 26131, 1);
  EXPECT_EQ(p.out.segs[1].info.line, 2);
  // Y at 50 mm/s^2: the junction's acceleration 50 / 0.707107 = 70.711,
  // v^2 = 70.711 * 0.02 * 2.414214 = 3.414214, v = 1.847759 mm/s.
  p = run(machine_of(machine_text(1000, 1000, 50)), "G1 X10 F3000\nY10\nM2\n");
  EXPECT_NEAR(p.out.segs[1].seg.entry_speed(), 18477, 1);
  // 45 degrees off straight: cos(theta) = -cos(45) = -0.707107;
  // sin(theta/2) = sqrt(0.5 * 1.707107) = 0.923880; the junction vector
  // (0.7071 - 1, 0.7071) normalized = (-0.382683, 0.923880): X allows
  // 100 / 0.382683, Y 100 / 0.923880 = 108.239 mm/s^2;
  // v^2 = 108.239 * 0.02 * 0.923880 / 0.076120 = 26.27414, v = 5.125831 mm/s.
  p = run(mc, "G1 X10 F3000\nX20 Y10\nM2\n");
  EXPECT_NEAR(p.out.segs[1].seg.entry_speed(), 51258, 1);
  // Straight on: only the segments' speeds limit it (50 mm/s).
  p = run(mc, "G1 X10 F3000\nX20\nM2\n");
  EXPECT_EQ(p.out.segs[1].seg.entry_speed(), 500000u);
  // A reversal stops, as do G61.1 and a dwell.
  EXPECT_EQ(run(mc, "G1 X10 F3000\nX5\nM2\n").out.segs[1].seg.entry_speed(), 0u);
  EXPECT_EQ(run(mc, "G61.1 G1 X10 F3000\nY10\nM2\n").out.segs[1].seg.entry_speed(), 0u);
  EXPECT_EQ(run(mc, "G1 X10 F3000\nG4 P0.1\nY10\nM2\n").out.segs[1].seg.entry_speed(), 0u);
  // G64 P0.5 as the deviation: v^2 = 141.421 * 0.5 * 2.414214, v = 13.065630 mm/s.
  EXPECT_NEAR(run(mc, "G64 P0.5 G1 X10 F3000\nY10\nM2\n").out.segs[1].seg.entry_speed(), 130656, 1);
}

TEST(Planner, SpeedsAndAccelerationsStayWithinEveryAxis) {
  const m::machine mc = machine_of(machine_text());
  // Rapids at the axes' limits: X alone at 100 mm/s, 100 mm/s^2.
  plan p = run(mc, "G0 X10\nM2\n");
  EXPECT_EQ(p.out.segs[0].seg.top_speed(), 100 * ppu);
  EXPECT_EQ(p.out.segs[0].seg.accel(), 100 * ppu);
  EXPECT_EQ(p.out.segs[0].seg.length(), 10 * ppu);
  // Diagonal: Y (50 mm/s) limits, 50 / cos 45 = 70.7107 mm/s.
  p = run(mc, "G0 X10 Y10\nM2\n");
  EXPECT_EQ(p.out.segs[0].seg.top_speed(), std::uint32_t(std::floor(50 * std::sqrt(2.0) * ppu)));
  EXPECT_EQ(p.out.segs[0].seg.accel(), std::uint32_t(std::floor(100 * std::sqrt(2.0) * ppu)));
  // A feed below the limits is taken as it is (1200 mm/min = 20 mm/s)...
  p = run(mc, "G1 X10 Y10 F1200\nM2\n");
  EXPECT_EQ(p.out.segs[0].seg.top_speed(), 20 * ppu);
  // ...one above them clamped; Z alone: 10 mm/s.
  p = run(mc, "G1 Z-5 F100000\nM2\n");
  EXPECT_EQ(p.out.segs[0].seg.top_speed(), 10 * ppu);
  EXPECT_EQ(p.out.segs[0].seg.steps(axis::z), 2000);  // SCALE -400: reversed
  // Inverse time: G93 F6 is a move of 1/6 min = 10 s; 10 mm: 1 mm/s.
  p = run(mc, "G93 G1 X10 F6\nG94\nM2\n");
  EXPECT_EQ(p.out.segs[0].seg.top_speed(), 1 * ppu);
  EXPECT_NEAR(p.sum.seconds, 10, 1e-9);
}

TEST(Planner, ConvertsProgramUnitsToTheMachines) {
  // A mm machine: G20 X1 is 25.4 mm.
  plan p = run(machine_of(machine_text()), "G20 G1 X1 Y0.5 F60\nM2\n");
  EXPECT_EQ(p.sum.steps[0], 25400);
  EXPECT_EQ(p.sum.steps[1], 12700);
  EXPECT_EQ(p.out.segs[0].seg.top_speed(), std::uint32_t(std::floor(25.4 * ppu)));  // 60 in/min
  // An inch machine: G21 X25.4 is 1 inch; it starts in inches (no G20/G21).
  std::string t = machine_text(800, 800);
  t.replace(t.find("LINEAR_UNITS = mm"), 17, "LINEAR_UNITS = inch");
  const m::machine inch = machine_of(t);
  p = run(inch, "G21 G1 X25.4 F254\nG20 X2\nM2\n");
  EXPECT_EQ(p.out.segs[0].seg.steps(axis::x), 800);
  EXPECT_EQ(p.out.segs[0].seg.length(), 254000u);  // 1 inch in path units
  EXPECT_EQ(p.sum.steps[0], 1600);
}

TEST(Planner, SoftLimitsNameTheLine) {
  const m::machine mc = machine_of(machine_text());
  auto refusal = [&](const std::string &prog, size_t *segments = nullptr) {
    recorder out;
    std::istringstream in(prog);
    try {
      m::plan_program(mc, in, "prog.ngc", out);
    } catch (const g::error &e) {
      if (segments) *segments = out.segs.size();
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(refusal("G1 X10 F100\nX20\nG0 X250\nM2\n"),
            "prog.ngc:3:1: X 250 is beyond the soft limit [AXIS_X] MAX_LIMIT 200");
  EXPECT_EQ(refusal("G0 Z1\nM2\n"), "prog.ngc:1:1: Z 1 is beyond the soft limit [AXIS_Z] MAX_LIMIT 0");
  EXPECT_EQ(refusal("G0 X10 Y10\nG0 Y-0.5\nM2\n"),
            "prog.ngc:2:1: Y -0.5 is beyond the soft limit [AXIS_Y] MIN_LIMIT 0");
  // An arc whose ends are inside but whose bulge is not: around (195, 50),
  // radius 10, it would reach X 205. Refused before its first chord.
  size_t before = 0;
  const std::string arc = refusal("G0 X195 Y60\nG2 X195 Y40 I0 J-10 F100\nM2\n", &before);
  EXPECT_EQ(arc.substr(0, 18), "prog.ngc:2:1: X 20") << arc;
  EXPECT_NE(arc.find(" is beyond the soft limit [AXIS_X] MAX_LIMIT 200"), std::string::npos) << arc;
  EXPECT_EQ(before, 1u);  // the rapid only
  // The other way round it stays inside.
  EXPECT_EQ(refusal("G0 X195 Y60\nG3 X195 Y40 I0 J-10 F100\nM2\n"), "accepted");
  // Inch programs are checked in the machine's units: 8 in = 203.2 mm.
  EXPECT_EQ(refusal("G20\nG0 X8\nM2\n"),
            "prog.ngc:2:1: X 203.2 is beyond the soft limit [AXIS_X] MAX_LIMIT 200");
  // An axis the machine does not have.
  std::string t = machine_text();
  t = t.substr(0, t.find("[AXIS_Z]")) +
      "[JOINT_0]\nMOTOR = 1\nSCALE = 1000\n[JOINT_1]\nMOTOR = 2\nSCALE = 1000\n";
  t.replace(t.find("COORDINATES = XYZ"), 17, "COORDINATES = XY");
  const m::machine xy = machine_of(t);
  recorder out;
  std::istringstream in("G0 X1\nG0 Z-1\nM2\n");
  try {
    m::plan_program(xy, in, "prog.ngc", out);
    ADD_FAILURE() << "a Z move on an XY machine was accepted";
  } catch (const g::error &e) {
    EXPECT_STREQ(e.what(), "prog.ngc:2:1: the machine has no Z axis ([TRAJ] COORDINATES)");
  }
}

// (MSG,...) and (DEBUG,...) come with their place in the path: the
// segments before them. A runner holding them in a message_queue shows
// each once those are done, not when the line is planned.
struct message_recorder : m::planner_output {
  long segments = 0;
  std::vector<std::string> log;
  void segment(const x4step::segment &, const m::segment_info &) override { segments++; }
  void message_at(std::string_view text, const m::message_info &i) override {
    log.push_back(std::string(i.debug ? "DEBUG" : "MSG") + " line " + std::to_string(i.line) + " after " +
                  std::to_string(i.after) + ":" + std::string(text));
  }
  void warning(const g::error &w) override { log.push_back(w.what()); }
};

TEST(Planner, MessagesKnowTheirPlace) {
  const m::machine mc = machine_of(machine_text());
  message_recorder out;
  std::istringstream in(
      "G21 (MSG,start)\nG1 X10 F600\nG1 X20\n(MSG,two done)\nG2 X30 Y10 I10 J0 (DEBUG,arc done)\nG43 "
      "H3\nM2\n");
  m::plan_program(mc, in, "prog.ngc", out);
  ASSERT_EQ(out.log.size(), 4u);
  EXPECT_EQ(out.log[0], "MSG line 1 after 0:start");
  EXPECT_EQ(out.log[1], "MSG line 4 after 2:two done");
  // The message of a line comes before its motion: due when the arc starts.
  EXPECT_EQ(out.log[2], "DEBUG line 5 after 2:arc done");
  EXPECT_EQ(out.log[3],
            "prog.ngc:6:5: warning: G43 H3: no tool table, so tool length 0 (add [EMCIO] TOOL_TABLE to the "
            "machine file for the tools' lengths)");
  EXPECT_GT(out.segments, 3);

  m::message_queue q;
  q.add("a", m::message_info{1, false, 0});
  q.add("b", m::message_info{4, false, 2});
  q.add("c", m::message_info{5, true, 2});
  q.add("d", m::message_info{9, false, 7});
  std::string shown;
  auto show = [&](const std::string &t, const m::message_info &) { shown += t; };
  EXPECT_EQ(q.due(0, show), 1u);
  EXPECT_EQ(shown, "a");
  EXPECT_EQ(q.due(1, show), 0u);
  EXPECT_EQ(q.due(2, show), 2u);
  EXPECT_EQ(shown, "abc");
  EXPECT_FALSE(q.empty());
  q.clear();
  EXPECT_TRUE(q.empty());
}

// A runner's probe: the input changes once the probing motor reaches
// `trip_step` (absolute, as the planner counts), the motors stop
// `overrun` steps beyond it along the move (the braking); without a
// trip_step the move runs to its end untripped.
struct probe_runner : recorder {
  std::optional<long> trip_step;
  long overrun = 0;
  size_t motor = 2;  // Z
  std::array<long, 4> at{};
  std::vector<size_t> probes;  // their indices in segs
  std::vector<g::probe_kind> kinds;
  void segment(const x4step::segment &s, const m::segment_info &i) override {
    recorder::segment(s, i);
    for (int a = 0; a < 4; a++) at[size_t(a)] += s.steps(axis(a + 1));
  }
  m::probe_result probe(const x4step::segment &s, const m::segment_info &i, g::probe_kind k) override {
    probes.push_back(segs.size());
    kinds.push_back(k);
    recorder::segment(s, i);
    m::probe_result r;
    r.ran = true;
    std::array<long, 4> end = at;
    for (int a = 0; a < 4; a++) end[size_t(a)] += s.steps(axis(a + 1));
    const long d = s.steps(axis(int(motor) + 1));
    if (!trip_step) {
      r.stop = end;
      r.trip = end;
    } else {
      // Every motor at the same fraction of the move (a straight line).
      auto along = [&](long on_motor) {
        std::array<long, 4> p = at;
        const double t = double(on_motor - at[motor]) / double(d);
        for (int a = 0; a < 4; a++) p[size_t(a)] += std::lround(t * double(s.steps(axis(a + 1))));
        return p;
      };
      r.tripped = true;
      r.trip = along(*trip_step);
      r.stop = along(*trip_step + (d > 0 ? overrun : -overrun));
    }
    at = r.stop;
    return r;
  }
};

TEST(Planner, ProbeStopsWhereTheRunnerSaysAndThePlanGoesOnFromThere) {
  const m::machine mc = with_probe(machine_of(machine_text()));  // Z: -400 steps/mm
  probe_runner out;
  out.trip_step = 1500;  // Z -3.75
  out.overrun = 100;     // stops at Z -4
  std::istringstream in("G0 X10 Y10\nG38.2 Z-10 F60\nG91 G0 Z1\nG90 G1 X20 F600\nM2\n");
  const m::plan_summary sum = m::plan_program(mc, in, "prog.ngc", out);
  ASSERT_EQ(out.probes.size(), 1u);
  ASSERT_EQ(out.segs.size(), 4u);
  const recorded &pr = out.segs[out.probes[0]];
  EXPECT_EQ(pr.seg.steps(axis::z), 4000);  // the whole programmed move
  EXPECT_EQ(pr.seg.steps(axis::x), 0);
  EXPECT_EQ(pr.info.line, 2);
  EXPECT_EQ(pr.seg.tag(), 2u);
  EXPECT_EQ(pr.info.end[2], -10);
  EXPECT_DOUBLE_EQ(pr.info.feed, 1);  // 60 mm/min
  EXPECT_EQ(pr.seg.entry_speed(), 0u);
  EXPECT_EQ(out.kinds, std::vector<g::probe_kind>{g::probe_kind::toward_or_error});
  // G91 Z1 from the stop (Z -4): to Z -3, 400 steps back.
  EXPECT_EQ(out.segs[2].seg.steps(axis::z), -400);
  EXPECT_EQ(out.segs[2].info.end[2], -3);
  EXPECT_EQ(out.segs[2].seg.entry_speed(), 0u);  // nothing blends out of a probe
  EXPECT_EQ(out.segs[3].seg.steps(axis::x), 10000);
  EXPECT_EQ(out.segs[3].seg.steps(axis::z), 0);
  EXPECT_EQ(sum.steps, out.at);
  EXPECT_EQ(sum.steps[2], 1200);
  // Extents and totals as for a feed to the programmed end.
  EXPECT_EQ(sum.min[2], -10);
  EXPECT_EQ(sum.segments, 4);
  EXPECT_NEAR(sum.length, 14.142135623730951 + 10 + 1 + 10, 1e-9);
}

TEST(Planner, ProbeOutcomeInMachineUnits) {
  // The planner as the interpreter's sink: stop and trip from the
  // runner's steps, an axis whose motor did not step exactly where it was.
  const m::machine mc = with_probe(machine_of(machine_text(320, 333)));
  probe_runner out;
  out.motor = 0;
  out.trip_step = 3200 + 961;  // X 13.003125
  out.overrun = 7;
  m::planner p(mc, out, g::pose{10.0001, 20.0002, -1.00003, 0, 0, 0});
  out.at = p.summary().steps;
  const g::probe_outcome o =
      p.straight_probe(g::straight{{30, 20.0002, -1.00003, 0, 0, 0}, 120, g::feed_mode::units_per_minute},
                       g::probe_kind::toward);
  EXPECT_TRUE(o.tripped);
  EXPECT_EQ(o.trip[0], 4161 / 320.0);
  EXPECT_EQ(o.stop[0], 4168 / 320.0);
  EXPECT_EQ(o.trip[1], 20.0002);  // Y and Z did not step: exactly where they were
  EXPECT_EQ(o.stop[2], -1.00003);
  EXPECT_EQ(p.summary().steps[0], 4168);
  // Untripped: the stop is the programmed end itself, the trip there too.
  out.trip_step.reset();
  const g::probe_outcome u = p.straight_probe(
      g::straight{{40.0001, 20.0002, -1.00003, 0, 0, 0}, 120, g::feed_mode::units_per_minute},
      g::probe_kind::away);
  EXPECT_FALSE(u.tripped);
  EXPECT_EQ(u.stop[0], 40.0001);
  EXPECT_EQ(u.trip, u.stop);
  EXPECT_EQ(p.summary().steps[0], std::lround(40.0001 * 320));
  EXPECT_EQ(out.kinds, (std::vector<g::probe_kind>{g::probe_kind::toward, g::probe_kind::away}));
}

TEST(Planner, ProbeStartsAndEndsAtRest) {
  // Straight on: G1 segments would blend at full speed; a probe does not.
  const m::machine mc = with_probe(machine_of(machine_text()));
  probe_runner out;
  out.motor = 0;
  std::istringstream in("G1 X10 F600\nG38.3 X20\nG1 X30\nM2\n");
  m::plan_program(mc, in, "prog.ngc", out);
  ASSERT_EQ(out.segs.size(), 3u);
  EXPECT_EQ(out.segs[1].seg.entry_speed(), 0u);
  EXPECT_EQ(out.segs[2].seg.entry_speed(), 0u);
  const plan g1 = run(mc, "G1 X10 F600\nG1 X20\nG1 X30\nM2\n");
  ASSERT_EQ(g1.out.segs.size(), 3u);
  EXPECT_GT(g1.out.segs[1].seg.entry_speed(), 0u);  // the same moves without a probe
  EXPECT_GT(g1.out.segs[2].seg.entry_speed(), 0u);
}

TEST(Planner, ProbeThatDoesNotRunAnswersContactAtTheEnd) {
  // The default planner_output::probe (a check, a plan that does not
  // move): ran == false, the plan goes on from the programmed end.
  const m::machine mc = with_probe(machine_of(machine_text()));
  const plan p = run(mc, "G0 X10\nG38.2 Z-10 F60\nG91 G0 Z1\nM2\n");
  ASSERT_EQ(p.out.segs.size(), 2u);  // the probe went to probe(), not segment()
  EXPECT_EQ(p.out.segs[1].seg.steps(axis::z), -400);
  EXPECT_EQ(p.sum.steps[2], 3600);  // Z -9
  EXPECT_EQ(p.sum.segments, 3);
  EXPECT_EQ(p.sum.min[2], -10);
}

TEST(Planner, ProbeNeedsAProbeInput) {
  const m::machine mc = machine_of(machine_text());
  recorder out;
  std::istringstream in("G38.2 Z-10 F60\nM2\n");
  try {
    m::plan_program(mc, in, "prog.ngc", out);
    ADD_FAILURE() << "G38.2 planned without a probe input";
  } catch (const g::error &e) {
    EXPECT_NE(std::string(e.what()).find("G38.2 needs a touch probe"), std::string::npos) << e.what();
  }
}

TEST(Planner, ProbeRefusals) {
  const m::machine mc = with_probe(machine_of(machine_text()));
  auto refusal = [&](const std::string &prog, probe_runner &out) {
    std::istringstream in(prog);
    try {
      m::plan_program(mc, in, "prog.ngc", out);
    } catch (const g::error &e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  probe_runner out;
  EXPECT_EQ(refusal("G0 X10\nG38.2 Z-60 F60\nM2\n", out),
            "prog.ngc:2:1: Z -60 is beyond the soft limit [AXIS_Z] MIN_LIMIT -50");
  EXPECT_TRUE(out.probes.empty());
  // Less than a step (Z: 0.0025 mm a step): G38.2 cannot probe; G38.3 goes on.
  EXPECT_EQ(refusal("G38.2 Z-0.001 F60\nM2\n", out),
            "prog.ngc:1:1: G38.2 moves less than one step: no probing");
  EXPECT_EQ(refusal("G38.3 Z-0.001 F60\nG38.5 Z-0.0011\nM2\n", out), "accepted");
  EXPECT_TRUE(out.probes.empty());
  // The runner's answers the interpreter refuses, with the probe's place.
  EXPECT_EQ(refusal("G0 X10\n  G38.2 Z-10 F60\nM2\n", out),
            "prog.ngc:2:3: G38.2 move finished without making contact");
  probe_runner at_once;
  at_once.trip_step = 400;  // Z -1 where it starts: tripped before the first step
  EXPECT_EQ(refusal("G0 Z-1\nG38.2 Z-10 F60\nM2\n", at_once),
            "prog.ngc:2:1: probe is already tripped when starting the G38.2 move");
  probe_runner at_once3;
  at_once3.trip_step = 400;
  EXPECT_EQ(refusal("G0 Z-1.0001\nG38.3 Z-10 F60\nM2\n", at_once3), "accepted");
}
