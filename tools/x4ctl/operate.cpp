// SPDX-License-Identifier: GPL-2.0
// x4ctl: homing, jogs and go-tos in machine units.
#include "operate.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>
#include <iostream>
#include <utility>

#include "commands.hpp"
#include "show.hpp"
#include "term.hpp"

namespace x4ctl {
namespace {

std::string letter(size_t a) { return std::string(1, axis_letters[a]); }

// Sets axes' profiles for as long as it lives; then puts the old ones back
// (the module keeps profiles: a jog must not change what 'x4ctl goto' does).
class profiles_guard {
 public:
  explicit profiles_guard(port &p) : p_(p) {}
  ~profiles_guard() {
    for (const auto &[a, pr] : saved_) {
      try {
        p_.set_profile(a, pr);
      } catch (const x4step::error &) {
        // the axis still moves (an exception left it running): it keeps the jog's
      }
    }
  }
  profiles_guard(const profiles_guard &) = delete;
  profiles_guard &operator=(const profiles_guard &) = delete;

  void set(x4step::axis a, const x4step::profile &pr) {
    saved_.emplace_back(a, p_.get_profile(a));
    p_.set_profile(a, pr);
  }

 private:
  port &p_;
  std::vector<std::pair<x4step::axis, x4step::profile>> saved_;
};

// An axis' own moves at speed units/s (0: MAX_VELOCITY), ramps at MAX_ACCELERATION.
x4step::profile profile_for(const m::axis &ax, double speed) {
  const double v = speed > 0 ? std::min(speed, ax.max_velocity) : ax.max_velocity;
  const double s = std::fabs(ax.scale);
  const auto vm = static_cast<unsigned>(std::clamp(std::lround(v * s), 1L, long(x4step::vel_max)));
  const auto acc =
      static_cast<unsigned>(std::clamp(std::lround(ax.max_acceleration * s), 1L, long(x4step::acc_max)));
  return x4step::profile{}.top_speed(vm).accel(acc).decel(acc);
}

// Signed steps/s of a homing speed in units/s (the machine file keeps them within 1..100000).
int steps_per_s(const m::axis &ax, double units_per_s) { return int(std::lround(units_per_s * ax.scale)); }

// A homing phase travels at most 1.25 times the travel between the soft limits.
unsigned long max_travel(const m::axis &ax) {
  const double t = std::ceil((ax.max_limit - ax.min_limit) * std::fabs(ax.scale) * 1.25);
  return static_cast<unsigned long>(std::clamp(t, 1.0, double(INT32_MAX)));
}

// The axes of `axes` that home, by HOME_SEQUENCE (stable: the order given within one).
std::vector<size_t> homing_axes(const m::machine &mc, const std::vector<size_t> &axes) {
  std::vector<size_t> r;
  for (size_t a : axes)
    if (mc.axes[a]->home.enabled) r.push_back(a);
  if (r.empty())
    throw usage_error(
        "home: none of these axes homes: give HOME_SEARCH_VEL (and HOME_LATCH_VEL, HOME_INPUT) "
        "in its [JOINT_n]");
  std::stable_sort(r.begin(), r.end(),
                   [&](size_t x, size_t y) { return mc.axes[x]->home.sequence < mc.axes[y]->home.sequence; });
  return r;
}

/// " halted (WHO)": what braked an axis short of its target; nobody named: braked elsewhere.
std::string halted_text(const std::string &halted_by) {
  return " halted (" + (halted_by.empty() ? std::string("braked elsewhere") : halted_by) + ")";
}

// What went wrong with the reference run of axis a, "" if it homed.
std::string homing_problem(const m::machine &mc, size_t a, const x4step::axis_status &st,
                           const std::string &halted_by) {
  const m::axis &ax = *mc.axes[a];
  const std::string at = " at " + number(st.position / ax.scale) + " " + unit_of(mc, a);
  if (st.error & x4step::axis_error::ref_travel)
    return letter(a) + ": the home switch (input " + std::to_string(ax.home.input) +
           ") did not become active, or change again, within " +
           number(double(max_travel(ax)) / std::fabs(ax.scale)) + " " + unit_of(mc, a) + " (it stands" + at +
           "): check HOME_INPUT, the sign of HOME_SEARCH_VEL and the switch ('x4ctl limits')";
  if (st.error) return letter(a) + ": " + errors_text(st.error) + at;
  if (!st.synced) return letter(a) + halted_text(halted_by) + at;
  return "";
}

// " X1.5 Y2 (mm)": where the axes stand.
std::string where_text(const m::machine &mc, const std::vector<size_t> &axes, const x4step::axes_status &st) {
  const g::pose p = pose_of(mc, st);
  std::string s;
  for (size_t a : axes) s += " " + letter(a) + number(p[a]);
  return s + " (" + units_name(mc) + ")";
}

// Brakes the axes and waits until they stand: nothing started is left running.
void brake_axes(port &p, x4step::axis_set axes) {
  try {
    p.halt(axes, x4step::halt_mode::brake);
  } catch (const x4step::error &) {
    // none of them moves
  }
  p.wait_axes(axes, milliseconds(5000));
}

}  // namespace

std::string unit_of(const m::machine &mc, size_t a) { return a >= g::A ? "deg" : units_name(mc); }

std::vector<size_t> machine_axes(const m::machine &mc, const std::string &letters,
                                 const std::string &command) {
  std::vector<size_t> r;
  for (char ch : letters) {
    const char u = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    const char *at = std::strchr(axis_letters, u);
    if (!at || !u)
      throw usage_error(command + ": '" + std::string(1, ch) + "' is no axis: use X, Y, Z, A, B or C");
    const size_t a = size_t(at - axis_letters);
    if (!mc.axes[a])
      throw usage_error(command + ": the machine has no " + letter(a) + " axis ([TRAJ] COORDINATES)");
    if (std::find(r.begin(), r.end(), a) != r.end())
      throw usage_error(command + ": axis " + letter(a) + " given twice");
    r.push_back(a);
  }
  if (letters.empty())
    for (size_t a = 0; a < g::n_axes; a++)
      if (mc.axes[a]) r.push_back(a);
  return r;
}

double jog_limit(const m::axis &a, bool positive) { return positive ? a.max_limit : a.min_limit; }

std::string refused_by_limits(const m::machine &mc, size_t a, double from, double to) {
  const std::string why = m::beyond_soft_limit(mc, a, to);
  if (why.empty()) return why;
  // Beyond the same limit as it starts, and nearer to it: back toward the range.
  const m::axis &ax = *mc.axes[a];
  if (to > ax.max_limit && from > to) return "";
  if (to < ax.min_limit && from < to) return "";
  return why;
}

axes_outcome move_machine(port &p, console &con, const m::machine &mc, const machine_targets &to,
                          double speed) {
  std::array<long, x4step::axes> steps{};
  x4step::axis_set axes;
  const g::pose from = pose_of(mc, p.get_axes());
  for (size_t a = 0; a < g::n_axes; a++) {
    if (!to[a]) continue;
    if (!mc.axes[a]) throw usage_error("the machine has no " + letter(a) + " axis ([TRAJ] COORDINATES)");
    if (const std::string why = refused_by_limits(mc, a, from[a], *to[a]); !why.empty())
      throw usage_error(why);
    steps[size_t(mc.axes[a]->motor)] = steps_of(*mc.axes[a], *to[a]);
    axes |= motor_of(*mc.axes[a]);
  }
  if (axes.empty()) return {p.get_axes(), ""};
  profiles_guard guard(p);
  for (size_t a = 0; a < g::n_axes; a++)
    if (to[a]) guard.set(motor_of(*mc.axes[a]), profile_for(*mc.axes[a], speed));
  start_goto(p, axes, steps, false);
  return follow_axes(p, con, axes);
}

void home_machine(port &p, console &con, const m::machine &mc, const std::vector<size_t> &axes,
                  std::ostream &out) {
  const std::vector<size_t> homed = homing_axes(mc, axes);
  x4step::switches sw = p.get_switches();
  for (size_t a : homed) sw.ref.at(size_t(mc.axes[a]->motor)) = mc.axes[a]->home.input;
  p.set_switches(sw);
  for (size_t i = 0; i < homed.size();) {
    // The axes of one sequence, at once.
    const int seq = mc.axes[homed[i]]->home.sequence;
    std::vector<size_t> group;
    for (; i < homed.size() && mc.axes[homed[i]]->home.sequence == seq; i++) group.push_back(homed[i]);
    x4step::axis_set motors;
    try {
      for (size_t a : group) {
        const m::axis &ax = *mc.axes[a];
        const std::string u = unit_of(mc, a) + "/s";
        out << "home: " << letter(a) << " (sequence " << seq << "): search " << number(ax.home.search_vel)
            << " " << u << ", latch " << number(ax.home.latch_vel) << " " << u << ", input " << ax.home.input
            << "\n"
            << std::flush;
        start_home(p, motor_of(ax),
                   x4step::homing{}
                       .phase1_speed(steps_per_s(ax, ax.home.search_vel))
                       .phase2_speed(steps_per_s(ax, ax.home.latch_vel))
                       .max_travel(max_travel(ax)));
        motors |= motor_of(ax);
      }
    } catch (...) {
      brake_axes(p, motors);  // those of the sequence already started
      throw;
    }
    const axes_outcome o = follow_axes(p, con, motors);
    const std::string later = i < homed.size() ? "; the later sequences did not start" : "";
    std::string problems;
    for (size_t a : group) {
      const std::string why = homing_problem(mc, a, o.end[motor_of(*mc.axes[a])], o.halted_by);
      if (!why.empty()) problems += (problems.empty() ? "" : "; ") + why;
    }
    if (!problems.empty()) throw failure(problems + "; not homed" + later);
    // The switch is at HOME_OFFSET; then to HOME.
    machine_targets home;
    for (size_t a : group) {
      const m::axis &ax = *mc.axes[a];
      p.set_position(motor_of(ax), steps_of(ax, ax.home.offset));
      home[a] = ax.home.home;
      out << "home: " << letter(a) << " homed: the switch is at " << number(ax.home.offset) << " "
          << unit_of(mc, a) << " (HOME_OFFSET); to HOME " << number(ax.home.home) << "\n";
    }
    out << std::flush;
    const axes_outcome h = move_machine(p, con, mc, home, 0);
    for (size_t a : group)
      if (h.end[motor_of(*mc.axes[a])].position != steps_of(*mc.axes[a], mc.axes[a]->home.home))
        throw failure(letter(a) + halted_text(h.halted_by) + " on its way to HOME, at" +
                      where_text(mc, {a}, h.end) + later);
  }
  const x4step::axes_status end = p.get_axes();
  out << "home: done, at" << where_text(mc, homed, end) << work_text(mc, homed, pose_of(mc, end), "home")
      << "\n";
}

key any_key_brakes::read_key(milliseconds timeout) {
  if (each_read_) each_read_();
  const key k = inner_.read_key(timeout);
  switch (k) {
    case key::interrupt:
      interrupted_ = true;
      return k;
    case key::none:
    case key::brake_request:
    case key::stop_request:
      return k;
    default:
      return key::esc;
  }
}

int cmd_home_machine(const config &c) {
  const m::machine mc = load_machine(c, "home");
  const std::vector<size_t> axes = machine_axes(mc, c.letters, "home");
  homing_axes(mc, axes);  // none homes: refused before the port opens
  controller_port p(open_controller(machine_device(c, mc)));
  prepare_port(p, mc);
  std_console con(true);
  home_machine(p, con, mc, axes, std::cout);
  return 0;
}

int cmd_jog_machine(const config &c) {
  const m::machine mc = load_machine(c, "jog");
  const size_t a = machine_axes(mc, c.letters, "jog").at(0);
  const m::axis &ax = *mc.axes[a];
  const std::string unit = unit_of(mc, a);
  const double speed = std::min(c.feed ? *c.feed / 60 : ax.max_velocity / 4, ax.max_velocity);
  const bool positive = c.dir == x4step::direction::positive;
  controller_port p(open_controller(machine_device(c, mc)));
  prepare_port(p, mc);
  const double from = pose_of(mc, p.get_axes())[a];
  const std::string name = letter(a) + (positive ? "+" : "-");
  machine_targets to;
  if (c.distance) {
    to[a] = from + (positive ? *c.distance : -*c.distance);
    if (const std::string why = refused_by_limits(mc, a, from, *to[a]); !why.empty())
      throw usage_error("jog: " + why + ": nothing moved");
  } else {
    to[a] = jog_limit(ax, positive);
    if (positive ? from >= *to[a] : from <= *to[a])
      throw failure(letter(a) + " is at " + number(from) + " " + unit + ", at or beyond its soft limit " +
                    (positive ? "MAX_LIMIT " : "MIN_LIMIT ") + number(*to[a]) + ": jog the other way");
  }
  std::cout << "jog: " << name << " from " << number(from) << " to " << number(*to[a]) << " " << unit
            << (c.distance ? ""
                : positive ? " (MAX_LIMIT)"
                           : " (MIN_LIMIT)")
            << " at F" << number(speed * 60) << " " << unit << "/min; any key brakes\n"
            << std::flush;
  std_console con(true);
  any_key_brakes keys(con, false, [&] {
    if (con.live())
      draw_live(con, "jog: " + letter(a) + " " + number(pose_of(mc, p.get_axes())[a]) + " " + unit);
  });
  const axes_outcome o = move_machine(p, keys, mc, to, speed);
  if (con.live()) draw_live(con, "");
  const x4step::axis_status &st = o.end[motor_of(ax)];
  const std::string at =
      number(st.position / ax.scale) + " " + unit + " (" + std::to_string(st.position) + " steps)";
  if (st.error) throw failure(letter(a) + ": " + errors_text(st.error) + " at " + at);
  const bool arrived = st.position == steps_of(ax, *to[a]);
  if (!arrived && c.distance) throw failure(letter(a) + halted_text(o.halted_by) + " at " + at);
  std::cout << "jog: " << letter(a) << " at " << at << work_text(mc, {a}, pose_of(mc, o.end), "jog")
            << (arrived               ? ""
                : o.halted_by.empty() ? ", braked elsewhere"
                                      : ", braked (" + o.halted_by + ")")
            << "\n";
  return 0;
}

}  // namespace x4ctl
