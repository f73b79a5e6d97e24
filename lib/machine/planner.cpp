// SPDX-License-Identifier: LGPL-2.1-or-later
// The planner: interpreter motions in machine units to path segments in
// steps, each end rounded once from its absolute programmed point.
#include "planner.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace x4step::machine {

namespace {

constexpr double pi = 3.14159265358979323846;
constexpr double value_max = 2147483647.0;  // a segment's length, speed, accel
constexpr long steps_max = 16777216;        // per axis and segment

std::string number(double v) {
  std::ostringstream o;
  o << v;
  return o.str();
}

char letter_of(size_t a) { return "XYZABC"[a]; }

}  // namespace

double path_units_per_unit(gcode::units u) noexcept { return u == gcode::units::inch ? 254000.0 : 10000.0; }

planner::planner(const machine &m, planner_output &out, const gcode::pose &start)
    : m_(m), out_(out), ppu_(path_units_per_unit(m.units)), pos_(start), deviation_(m.junction_deviation) {
  for (size_t a = 0; a < gcode::n_axes; a++)
    if (m_.axes[a]) sum_.steps[size_t(m_.axes[a]->motor)] = std::lround(start[a] * m_.axes[a]->scale);
}

void planner::set_position(const gcode::pose &p) {
  pos_ = p;
  prev_dir_ = {};
  prev_top_ = 0;
  stop_next_ = true;
  for (size_t a = 0; a < gcode::n_axes; a++)
    if (m_.axes[a]) sum_.steps[size_t(m_.axes[a]->motor)] = std::lround(p[a] * m_.axes[a]->scale);
}

void planner::fail(const std::string &what) const { throw gcode::error(file_, line_, 1, what); }

void planner::check_limits(const gcode::pose &p) const {
  for (size_t a = 0; a < gcode::n_axes; a++) {
    const std::optional<axis> &ax = m_.axes[a];
    if (!ax) {
      if (std::fabs(p[a] - pos_[a]) > 1e-9)
        fail(std::string("the machine has no ") + letter_of(a) + " axis ([TRAJ] COORDINATES)");
      continue;
    }
    if (!within_soft_limits(*ax, p[a])) fail(beyond_soft_limit(m_, a, p[a]));
  }
}

// One straight segment to end: feed_per_s (units/s) for feeds, seconds
// for inverse time, neither for rapids.
bool planner::line_to(const gcode::pose &end, const speed &sp, bool checked, const gcode::probe_kind *probe,
                      probe_result *result) {
  if (!checked) check_limits(end);
  std::array<long, x4step::axes> delta{};
  std::array<double, x4step::axes> d{};  // the executed move per motor, machine units
  std::array<double, x4step::axes> vmax{}, amax{};
  double lin2 = 0, rot2 = 0;
  bool any = false;
  for (size_t a = 0; a < gcode::n_axes; a++) {
    if (!m_.axes[a]) continue;
    const axis &ax = *m_.axes[a];
    const size_t mo = size_t(ax.motor);
    delta[mo] = std::lround(end[a] * ax.scale) - sum_.steps[mo];
    if (std::labs(delta[mo]) > steps_max)
      fail(std::string("a move of ") + std::to_string(std::labs(delta[mo])) + " steps on " + letter_of(a) +
           ": at most 16777216 in one move; split it");
    d[mo] = double(delta[mo]) / ax.scale;
    (a < 3 ? lin2 : rot2) += d[mo] * d[mo];
    vmax[mo] = ax.max_velocity;
    amax[mo] = ax.max_acceleration;
    any = any || delta[mo];
  }
  const gcode::pose start = pos_;
  pos_ = end;
  if (!any) return false;  // less than a step: the next point's rounding takes it up

  // LinuxCNC's length: along X Y Z, or along A B C for a rotary-only move.
  const double len = std::sqrt(lin2 > 0 ? lin2 : rot2);
  double v_axes = std::numeric_limits<double>::infinity(), a_axes = v_axes;
  for (size_t mo = 0; mo < x4step::axes; mo++) {
    const double u = std::fabs(d[mo]) / len;
    if (u <= 0) continue;
    v_axes = std::min(v_axes, vmax[mo] / u);
    a_axes = std::min(a_axes, amax[mo] / u);
  }
  if (lin2 > 0 && m_.max_linear_velocity > 0) v_axes = std::min(v_axes, m_.max_linear_velocity);
  const double asked = sp.rapid ? v_axes : sp.seconds > 0 ? len / sp.seconds : sp.feed_per_s;
  if (!(asked > 0)) fail("a feed move without a feed rate: give F");
  const double v = std::min(asked, v_axes);

  // Rounded so that the kernel's leader rate never exceeds what the axes allow.
  const double length_u = std::max(1.0, std::ceil(len * ppu_ - 1e-6));
  if (length_u > value_max) fail("a move of " + number(len) + " units is too long for one segment; split it");
  const double top_u = std::min(std::floor(v * ppu_), value_max);
  if (top_u < 1) fail("feed " + number(v * 60) + " units/min is too low: at least " + number(60 / ppu_));
  const double acc_u = std::clamp(std::floor(a_axes * ppu_), 1.0, value_max);
  if (top_u / acc_u > 1800) fail("this feed takes over 1800 s to reach at the axes' accelerations");

  std::uint32_t entry = 0;
  if (!stop_next_ && !exact_stop_) {
    // GRBL: the acceleration along the change of direction, limited by every axis.
    double n_in = 0, n_out = 0;
    for (size_t mo = 0; mo < x4step::axes; mo++)
      n_in += prev_dir_[mo] * prev_dir_[mo], n_out += d[mo] * d[mo];
    std::array<double, x4step::axes> ju{};
    double n_ju = 0;
    for (size_t mo = 0; mo < x4step::axes; mo++) {
      ju[mo] = d[mo] / std::sqrt(n_out) - prev_dir_[mo] / std::sqrt(n_in);
      n_ju += ju[mo] * ju[mo];
    }
    double a_junction = std::numeric_limits<double>::infinity();
    for (size_t mo = 0; mo < x4step::axes; mo++)
      if (ju[mo] != 0)
        a_junction = std::min(a_junction, amax[mo] > 0 ? amax[mo] * std::sqrt(n_ju) / std::fabs(ju[mo]) : 0);
    if (!std::isfinite(a_junction)) a_junction = a_axes;  // straight on
    const std::uint32_t corner = x4step::junction_speed(prev_dir_, d, a_junction * ppu_, deviation_ * ppu_);
    entry = std::min({corner, prev_top_, static_cast<std::uint32_t>(top_u)});
  }

  x4step::segment s;
  for (size_t mo = 0; mo < x4step::axes; mo++) s.steps(x4step::axis(int(mo) + 1), delta[mo]);
  s.length(static_cast<std::uint32_t>(length_u))
      .top_speed(static_cast<std::uint32_t>(top_u))
      .accel(static_cast<std::uint32_t>(acc_u))
      .entry_speed(entry)
      .tag(static_cast<std::uint64_t>(line_));
  const x4step::errc e = x4step::check(s);
  if (e != x4step::errc::ok)
    fail("the kernel would refuse this segment: " + x4step::make_error_code(e).message());

  segment_info info;
  info.line = line_;
  info.rapid = sp.rapid;
  info.length = len;
  info.speed = v;
  info.feed = asked;
  info.end = end;
  if (probe)
    *result = out_.probe(s, info, *probe);
  else
    out_.segment(s, info);

  for (size_t mo = 0; mo < x4step::axes; mo++) sum_.steps[mo] += delta[mo];
  prev_dir_ = d;
  prev_top_ = static_cast<std::uint32_t>(top_u);
  stop_next_ = false;
  sum_.segments++;
  sum_.length += len;
  sum_.seconds += len / v;
  const gcode::pose off = work_offset_ ? work_offset_() : gcode::pose{};
  for (size_t a = 0; a < gcode::n_axes; a++) {
    if (!m_.axes[a]) continue;
    if (!sum_.moved) {  // from where the motion begins
      sum_.min[a] = sum_.max[a] = start[a];
      sum_.work_min[a] = sum_.work_max[a] = start[a] - off[a];
    }
    sum_.min[a] = std::min(sum_.min[a], end[a]);
    sum_.max[a] = std::max(sum_.max[a], end[a]);
    sum_.work_min[a] = std::min(sum_.work_min[a], end[a] - off[a]);
    sum_.work_max[a] = std::max(sum_.work_max[a], end[a] - off[a]);
  }
  sum_.moved = true;
  return true;
}

void planner::straight_traverse(const gcode::straight &s) { line_to(s.end, speed{true, 0, 0}); }

void planner::straight_feed(const gcode::straight &s) {
  if (s.mode == gcode::feed_mode::inverse_time)
    line_to(s.end, speed{false, 0, s.feed > 0 ? 60 / s.feed : 0});
  else
    line_to(s.end, speed{false, s.feed / 60, 0});
}

gcode::probe_outcome planner::straight_probe(const gcode::straight &s, gcode::probe_kind k) {
  const char *name = k == gcode::probe_kind::toward_or_error ? "G38.2"
                     : k == gcode::probe_kind::toward        ? "G38.3"
                     : k == gcode::probe_kind::away_or_error ? "G38.4"
                                                             : "G38.5";
  if (!m_.probe_input)
    fail(std::string(name) +
         " needs a touch probe: give its input in the machine file ([X4STEP] PROBE_INPUT)");
  const gcode::pose start = pos_;
  const std::array<long, x4step::axes> start_steps = sum_.steps;
  stop_next_ = true;  // from rest: nothing blends into it
  speed sp{false, s.feed / 60, 0};
  if (s.mode == gcode::feed_mode::inverse_time) sp = speed{false, 0, s.feed > 0 ? 60 / s.feed : 0};
  probe_result r;
  const bool moves = line_to(s.end, sp, false, &k, &r);
  stop_next_ = true;  // to rest: nothing blends out of it
  if (!moves) {
    // Less than a step: no motor can move, so the input cannot be watched.
    if (k == gcode::probe_kind::toward_or_error || k == gcode::probe_kind::away_or_error)
      fail(std::string(name) + " moves less than one step: no probing");
    return {s.end, false, s.end};
  }
  if (!r.ran) return {s.end, true, s.end};
  // Steps back to machine units: an axis whose motor stands at the start's
  // or the end's step is exactly there (nothing drifts by rounding).
  auto to_pose = [&](const std::array<long, x4step::axes> &st) {
    gcode::pose p = s.end;
    for (size_t a = 0; a < gcode::n_axes; a++) {
      if (!m_.axes[a]) continue;
      const axis &ax = *m_.axes[a];
      const size_t mo = size_t(ax.motor);
      if (st[mo] == start_steps[mo])
        p[a] = start[a];
      else if (st[mo] != std::lround(s.end[a] * ax.scale))
        p[a] = double(st[mo]) / ax.scale;
    }
    return p;
  };
  gcode::probe_outcome o;
  o.stop = to_pose(r.stop);
  o.tripped = r.tripped;
  o.trip = r.tripped ? to_pose(r.trip) : o.stop;
  pos_ = o.stop;
  for (const std::optional<axis> &ax : m_.axes)
    if (ax) sum_.steps[size_t(ax->motor)] = r.stop[size_t(ax->motor)];
  return o;
}

void planner::arc_feed(const gcode::arc &a) {
  size_t i1 = gcode::X, i2 = gcode::Y;  // the plane's first and second axes
  if (a.in == gcode::plane::zx) i1 = gcode::Z, i2 = gcode::X;
  if (a.in == gcode::plane::yz) i1 = gcode::Y, i2 = gcode::Z;
  const gcode::pose start = pos_;
  const double c1 = a.centre_first, c2 = a.centre_second;
  const double r0 = std::hypot(start[i1] - c1, start[i2] - c2),
               r1 = std::hypot(a.end[i1] - c1, a.end[i2] - c2);
  const double a0 = std::atan2(start[i2] - c2, start[i1] - c1);
  double sweep = std::atan2(a.end[i2] - c2, a.end[i1] - c1) - a0;
  if (a.turns > 0) {
    if (sweep <= 1e-12) sweep += 2 * pi;  // end == start: a full circle
    sweep += 2 * pi * (a.turns - 1);
  } else {
    if (sweep >= -1e-12) sweep -= 2 * pi;
    sweep -= 2 * pi * (-a.turns - 1);
  }
  // The sagitta of a chord of angle t is r (1 - cos(t / 2)): at most the tolerance.
  const double r = std::max(r0, r1);
  double step = pi / 2;
  if (r > m_.arc_tolerance) step = std::min(step, 2 * std::acos(1 - m_.arc_tolerance / r));
  const double n_real = std::ceil(std::fabs(sweep) / step - 1e-9);
  if (n_real > 1e7) fail("this arc needs over 10 million chords: raise [X4STEP] ARC_TOLERANCE");
  const long n = std::max(1L, static_cast<long>(n_real));
  auto point = [&](long k) {
    if (k == n) return a.end;  // the programmed end itself: nothing accumulates
    const double t = double(k) / double(n), ang = a0 + sweep * t, rad = r0 + (r1 - r0) * t;
    gcode::pose p;
    for (size_t i = 0; i < gcode::n_axes; i++) p[i] = start[i] + (a.end[i] - start[i]) * t;
    p[i1] = c1 + rad * std::cos(ang);
    p[i2] = c2 + rad * std::sin(ang);
    return p;
  };
  for (long k = 1; k <= n; k++) check_limits(point(k));  // the whole arc before its first chord
  speed sp{false, a.feed / 60, 0};
  if (a.mode == gcode::feed_mode::inverse_time)
    sp = speed{false, 0, a.feed > 0 ? 60 / a.feed / double(n) : 0};
  for (long k = 1; k <= n; k++) line_to(point(k), sp, true);
}

void planner::dwell(double seconds) {
  stop_next_ = true;
  sum_.seconds += seconds;
  out_.dwell(seconds);
}

void planner::set_path_mode(gcode::path_mode mode, double p_tolerance, double) {
  exact_stop_ = mode == gcode::path_mode::exact_stop;
  deviation_ = mode == gcode::path_mode::blend && p_tolerance > 0 ? p_tolerance : m_.junction_deviation;
}

void planner::spindle(gcode::spindle_dir d, double) {
  stop_next_ = true;
  out_.spindle(d != gcode::spindle_dir::off);
}

void planner::coolant(bool mist, bool flood) {
  stop_next_ = true;
  out_.coolant(mist, flood);
}

void planner::change_tool(int tool) {
  stop_next_ = true;
  out_.pause(false, tool);
}

void planner::pause(bool optional) {
  stop_next_ = true;
  out_.pause(optional, -1);
}

void planner::message(std::string_view text) {
  out_.message_at(text, message_info{line_, false, static_cast<std::uint64_t>(sum_.segments)});
}

void planner::debug(std::string_view text) {
  out_.message_at(text, message_info{line_, true, static_cast<std::uint64_t>(sum_.segments)});
}

void planner::warning(const gcode::error &w) { out_.warning(w); }

void planner::source_line(const std::string &file, int line) {
  file_ = file;
  line_ = line;
  sum_.lines = line;
}

namespace {

// The interpreter in the machine's units, with its tool table, from start.
void interpret(const machine &m, std::istream &in, const std::string &name, gcode::sink &out,
               const gcode::pose &start, const gcode::coordinate_state &coords = {},
               gcode::coordinate_state *coords_after = nullptr, planner *p = nullptr) {
  gcode::options o;
  o.machine_units = m.units;
  o.initial_units = m.units;
  o.start = start;
  o.coordinates = coords;
  gcode::interpreter interp(out, o);
  if (!m.tool_table.empty()) interp.set_tool_table(gcode::read_tool_table(m.tool_table, m.units, m.units));
  if (p) p->work_offset_from([&interp] { return interp.work_offset(); });
  interp.run(in, name);
  if (p) p->work_offset_from({});
  if (coords_after) *coords_after = interp.coordinates();
}

}  // namespace

plan_summary plan_program(const machine &m, std::istream &in, const std::string &name, planner_output &out,
                          const gcode::pose &start, const gcode::coordinate_state &coords,
                          gcode::coordinate_state *coords_after) {
  planner p(m, out, start);
  interpret(m, in, name, p, start, coords, coords_after, &p);
  return p.summary();
}

void check_program(const machine &m, std::istream &in, const std::string &name) {
  gcode::sink none;
  interpret(m, in, name, none, {});
}

}  // namespace x4step::machine
