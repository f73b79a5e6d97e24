// SPDX-License-Identifier: GPL-2.0
// What the motors did against what the program says (issue 20): reads the
// VCD of a run on the simulated port (x4ctl --sim gcode, X4STEP_SIM_VCD),
// counts every motor's steps from its clock and direction pins, and checks
//  (a) the end: every axis stands at exactly round(programmed end x SCALE);
//  (b) the path: after every step, the position lies within ARC_TOLERANCE
//      + 1 step of the ideal programmed path (the interpreter's lines, and
//      its arcs and helices as true curves, not chords): some point of the
//      path is within 1 step on each axis, and then within ARC_TOLERANCE
//      in space.
// The ideal path comes from the interpreter alone (gcode.oracle holds it to
// LinuxCNC's rs274), never from the planner under test.
//   sim_check MACHINE PROGRAM VCD   (machine units, from machine zero)
// Prints one line of figures; exit 0 good, 1 a check failed, 2 bad usage.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "gcode.hpp"
#include "machine.hpp"

namespace g = x4step::gcode;
namespace m = x4step::machine;

namespace {

constexpr double pi = 3.14159265358979323846;

// One programmed motion: a line, or an arc (helix, spiral) as LinuxCNC
// describes it: angle and radius linear in t, the other axes linear.
struct motion {
  int line = 0;
  g::pose from{}, to{};
  bool is_arc = false;
  size_t i1 = 0, i2 = 0;  // the arc's plane axes
  double c1 = 0, c2 = 0, a0 = 0, sweep = 0, r0 = 0, r1 = 0;

  g::pose at(double t) const {
    g::pose p;
    for (size_t i = 0; i < g::n_axes; i++) p[i] = from[i] + (to[i] - from[i]) * t;
    if (is_arc) {
      const double ang = a0 + sweep * t, r = r0 + (r1 - r0) * t;
      p[i1] = c1 + r * std::cos(ang);
      p[i2] = c2 + r * std::sin(ang);
    }
    return p;
  }
};

// How far p lies from q beyond 1 step on every axis (machine units): the
// motors stand on whole steps, and a step rounds each axis on its own,
// while the arc tolerance is a distance in space.
struct metric {
  g::pose step{};  // 1 step per axis, machine units (0: no such axis)

  double excess(const g::pose &p, const g::pose &q) const {
    double s = 0;
    for (size_t i = 0; i < g::n_axes; i++) {
      const double d = std::max(0.0, std::fabs(p[i] - q[i]) - step[i]);
      s += d * d;
    }
    return std::sqrt(s);
  }

  // The least excess over the motion's t in [lo, hi] (golden section: the
  // excess is convex along a line, and near its minimum along an arc).
  double search(const g::pose &p, const motion &mo, double lo, double hi) const {
    for (int k = 0; k < 50; k++) {
      const double m1 = lo + (hi - lo) * 0.382, m2 = lo + (hi - lo) * 0.618;
      if (excess(p, mo.at(m1)) < excess(p, mo.at(m2)))
        hi = m2;
      else
        lo = m1;
    }
    return excess(p, mo.at((lo + hi) / 2));
  }

  // Excess of p over the motion, evaluated at points of it: never less
  // than the true least, so the check errs strict. First at the nearest
  // point (a line's projection, an arc's points at p's angle, every turn),
  // searched further only when that is beyond the tolerance.
  double excess(const g::pose &p, const motion &mo, double tolerance) const {
    if (!mo.is_arc) {
      double dd = 0, dp = 0;
      for (size_t i = 0; i < g::n_axes; i++) {
        const double d = mo.to[i] - mo.from[i];
        dd += d * d;
        dp += d * (p[i] - mo.from[i]);
      }
      const double e = excess(p, mo.at(dd > 0 ? std::min(1.0, std::max(0.0, dp / dd)) : 0));
      return e <= tolerance ? e : std::min(e, search(p, mo, 0, 1));
    }
    double best = std::min(excess(p, mo.from), excess(p, mo.to));
    const double theta = std::atan2(p[mo.i2] - mo.c2, p[mo.i1] - mo.c1);
    const double per_turn = 2 * pi / std::fabs(mo.sweep);  // t per full turn
    double t = (theta - mo.a0) / mo.sweep;
    t -= std::floor(t / per_turn) * per_turn;  // the first t >= 0 at p's angle
    for (; t <= 1 && best > tolerance; t += per_turn) {
      best = std::min(best, excess(p, mo.at(t)));
      if (best > tolerance)
        best =
            std::min(best, search(p, mo, std::max(0.0, t - per_turn / 20), std::min(1.0, t + per_turn / 20)));
    }
    return best;
  }
};

// The interpreter's motions, in machine units, as the planner receives them.
class recorder : public g::sink {
 public:
  explicit recorder(const g::pose &start) : pos_(start) {}
  std::vector<motion> motions;
  const g::pose &end() const { return pos_; }

  void straight_traverse(const g::straight &s) override { add_line(s.end); }
  void straight_feed(const g::straight &s) override { add_line(s.end); }
  void arc_feed(const g::arc &a) override {
    motion mo = start_motion(a.end);
    mo.is_arc = true;
    mo.i1 = g::X, mo.i2 = g::Y;
    if (a.in == g::plane::zx) mo.i1 = g::Z, mo.i2 = g::X;
    if (a.in == g::plane::yz) mo.i1 = g::Y, mo.i2 = g::Z;
    mo.c1 = a.centre_first, mo.c2 = a.centre_second;
    mo.r0 = std::hypot(mo.from[mo.i1] - mo.c1, mo.from[mo.i2] - mo.c2);
    mo.r1 = std::hypot(a.end[mo.i1] - mo.c1, a.end[mo.i2] - mo.c2);
    mo.a0 = std::atan2(mo.from[mo.i2] - mo.c2, mo.from[mo.i1] - mo.c1);
    // LinuxCNC's turns: the sign is the direction, |turns| - 1 extra circles.
    double sweep = std::atan2(a.end[mo.i2] - mo.c2, a.end[mo.i1] - mo.c1) - mo.a0;
    if (a.turns > 0) {
      while (sweep <= 1e-12) sweep += 2 * pi;
      sweep += 2 * pi * (a.turns - 1);
    } else {
      while (sweep >= -1e-12) sweep -= 2 * pi;
      sweep -= 2 * pi * (-a.turns - 1);
    }
    mo.sweep = sweep;
    motions.push_back(mo);
  }
  void source_line(const std::string &, int line) override { line_ = line; }

 private:
  motion start_motion(const g::pose &end) {
    motion mo;
    mo.line = line_;
    mo.from = pos_;
    mo.to = end;
    pos_ = end;
    return mo;
  }
  void add_line(const g::pose &end) { motions.push_back(start_motion(end)); }
  g::pose pos_;
  int line_ = 0;
};

char letter(size_t a) { return "XYZABC"[a]; }

}  // namespace

int main(int argc, char **argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: sim_check MACHINE PROGRAM VCD\n");
    return 2;
  }
  const std::string program = argv[2], vcd_name = argv[3];
  m::machine mc;
  std::vector<motion> path;
  g::pose end{};
  try {
    mc = m::read_file(argv[1]);
    recorder rec(g::pose{});
    g::options o;
    o.machine_units = o.initial_units = mc.units;
    g::interpreter in(rec, o);
    if (!mc.tool_table.empty()) in.set_tool_table(g::read_tool_table(mc.tool_table, mc.units, mc.units));
    in.run_file(program);
    path = std::move(rec.motions);
    end = rec.end();
  } catch (const std::exception &e) {
    std::fprintf(stderr, "FAIL %s: %s\n", program.c_str(), e.what());
    return 1;
  }

  metric dist;
  for (size_t a = 0; a < g::n_axes; a++)
    if (mc.axes[a]) dist.step[a] = 1 / std::fabs(mc.axes[a]->scale);
  const double tolerance = mc.arc_tolerance;

  std::ifstream vcd(vcd_name);
  if (!vcd) {
    std::fprintf(stderr, "FAIL %s: cannot read %s\n", program.c_str(), vcd_name.c_str());
    return 1;
  }
  // VCD identifiers (one character) to motor clocks and directions.
  std::array<int, 128> clk_motor, dir_motor;
  clk_motor.fill(-1);
  dir_motor.fill(-1);
  std::array<long, 4> pos{};
  std::array<int, 4> clk{-1, -1, -1, -1}, dir{-1, -1, -1, -1};
  std::string w;
  std::string text;
  while (std::getline(vcd, text) && text.find("$enddefinitions") == std::string::npos) {
    std::istringstream l(text);
    std::string var, type, size, id, name;
    if (!(l >> var >> type >> size >> id >> name) || var != "$var" || id.size() != 1) continue;
    int n = 0;
    if (std::sscanf(name.c_str(), "pin%*d_clk%d", &n) == 1 && n >= 1 && n <= 4)
      clk_motor[size_t(id[0])] = n - 1;
    if (std::sscanf(name.c_str(), "pin%*d_dir%d", &n) == 1 && n >= 1 && n <= 4)
      dir_motor[size_t(id[0])] = n - 1;
  }

  size_t cursor = 0;
  const size_t window = 400;  // motions ahead where the position may be
  long steps = 0, points = 0, bad_dir = 0;
  double worst = 0;
  bool stepped = false, failed = false;
  unsigned long long now = 0;
  auto check_point = [&]() {
    g::pose p{};
    for (size_t a = 0; a < g::n_axes; a++)
      if (mc.axes[a]) p[a] = double(pos[size_t(mc.axes[a]->motor)]) / mc.axes[a]->scale;
    points++;
    double d_min = std::numeric_limits<double>::infinity();
    size_t at = cursor;
    for (size_t j = cursor; j < path.size() && j < cursor + window; j++) {
      const double d = dist.excess(p, path[j], tolerance);
      if (d < d_min) d_min = d, at = j;
      if (d <= tolerance) {
        // The position is on motion j: the motions before it are done.
        // The figure: the nearest of j and the next two (a corner's).
        cursor = j;
        for (size_t k = j + 1; k < path.size() && k <= j + 2; k++)
          d_min = std::min(d_min, dist.excess(p, path[k], 0));
        worst = std::max(worst, d_min);
        return;
      }
    }
    worst = std::max(worst, d_min);
    if (!failed) {
      std::ostringstream o;
      for (size_t a = 0; a < g::n_axes; a++)
        if (mc.axes[a]) o << " " << letter(a) << p[a];
      std::printf(
          "FAIL %s: at %.6f s the motors stood at%s, %.6g beyond 1 step per axis from the path "
          "(nearest: line %d), more than ARC_TOLERANCE %.6g\n",
          program.c_str(), double(now) * 1e-9, o.str().c_str(), d_min, at < path.size() ? path[at].line : 0,
          tolerance);
    }
    failed = true;
  };
  while (vcd >> w) {
    if (w[0] == '#') {
      if (stepped) check_point();
      stepped = false;
      now = std::stoull(w.substr(1));
      continue;
    }
    if (w[0] != '0' && w[0] != '1') continue;  // x (unknown), $dumpvars, $end
    const int level = w[0] - '0';
    const size_t id = size_t(static_cast<unsigned char>(w[1])) & 127;
    if (dir_motor[id] >= 0) dir[size_t(dir_motor[id])] = level;
    if (clk_motor[id] >= 0) {
      const size_t mo = size_t(clk_motor[id]);
      if (clk[mo] == 0 && level == 1) {  // rising edge: a step (the first level set is none)
        if (dir[mo] < 0) bad_dir++;
        pos[mo] += dir[mo] == 1 ? 1 : -1;  // direction HIGH: positive
        steps++;
        stepped = true;
      }
      clk[mo] = level;
    }
  }
  if (stepped) check_point();

  // (a) The end, exactly.
  std::ostringstream ends;
  for (size_t a = 0; a < g::n_axes; a++) {
    if (!mc.axes[a]) continue;
    const long want = std::lround(end[a] * mc.axes[a]->scale), got = pos[size_t(mc.axes[a]->motor)];
    ends << " " << letter(a) << " " << got;
    if (want != got) {
      std::printf("FAIL %s: %c ends at step %ld, the programmed end %.9g x SCALE rounds to %ld\n",
                  program.c_str(), letter(a), got, end[a], want);
      failed = true;
    }
  }
  if (bad_dir) {
    std::printf("FAIL %s: %ld steps before their direction pin was set\n", program.c_str(), bad_dir);
    failed = true;
  }
  if (steps == 0) {
    std::printf("FAIL %s: no step in %s\n", program.c_str(), vcd_name.c_str());
    failed = true;
  }
  std::printf(
      "%s %s: %zu motions, %ld steps at %ld instants, end at steps%s; worst distance from the path "
      "beyond 1 step per axis %.3g (%.1f %% of ARC_TOLERANCE %g)\n",
      failed ? "FAIL" : "PASS", program.c_str(), path.size(), steps, points, ends.str().c_str(), worst,
      100 * worst / tolerance, tolerance);
  return failed ? 1 : 0;
}
