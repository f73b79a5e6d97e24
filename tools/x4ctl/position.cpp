// SPDX-License-Identifier: GPL-2.0
// x4ctl: the positioning subcommands.
#include "position.hpp"

#include <cstdint>
#include <optional>
#include <string>

#include "motion.hpp"
#include "show.hpp"

namespace x4ctl {
namespace {

std::string axis_name(x4step::axis a) { return "axis " + std::to_string(a.number()); }

// The coordinate pos + d: signed 32 bits, wrapping as the module's do.
long wrapped(long pos, long d) {
  return static_cast<int32_t>(static_cast<uint32_t>(pos + d));  // both are 32-bit values
}

// " halted (by what)": who stopped an axis short of its target.
std::string halted_text(const std::string &halted_by) {
  return " halted (" + (halted_by.empty() ? "braked elsewhere" : halted_by) + ")";
}

// What went wrong with an axis' own move, "" if nothing did.
std::string axis_problem(x4step::axis axis, const x4step::axis_status &a, std::optional<long> target,
                         const std::string &halted_by) {
  const std::string at =
      " at " + std::to_string(a.position) + (target ? " (target " + std::to_string(*target) + ")" : "");
  if (a.error) return axis_name(axis) + ": " + errors_text(a.error) + at;
  if (target && a.position != *target) return axis_name(axis) + halted_text(halted_by) + at;
  return "";
}

}  // namespace

void profile_command(port &p, const config &c, std::ostream &out) {
  x4step::profile pr = p.get_profile(c.axis);
  if (c.v0 || c.ve || c.vm || c.a0 || c.ae) {
    pr.start_speed(c.v0.value_or(pr.start_speed()))
        .end_speed(c.ve.value_or(pr.end_speed()))
        .top_speed(c.vm.value_or(pr.top_speed()))
        .accel(c.a0.value_or(pr.accel()))
        .decel(c.ae.value_or(pr.decel()));
    if (x4step::check(pr) != x4step::errc::ok)
      throw usage_error("profile: v0 " + std::to_string(pr.start_speed()) + ", ve " +
                        std::to_string(pr.end_speed()) + ", vm " + std::to_string(pr.top_speed()) + ", a0 " +
                        std::to_string(pr.accel()) + ", ae " + std::to_string(pr.decel()) +
                        " do not fit together: v0 and ve must not exceed vm, and a ramp from rest to vm "
                        "must last at most 3600 s (vm / a0 and vm / ae)");
    p.set_profile(c.axis, pr);
    pr = p.get_profile(c.axis);  // what the port took
  }
  out << (c.json ? profile_json(c.axis, pr, device_of(c)) + "\n" : profile_text(c.axis, pr));
}

void limits_command(port &p, const config &c, std::ostream &out) {
  x4step::switches s = p.get_switches();
  if (c.ref || c.plus || c.minus || c.nc) {
    const int i = c.axis.index();  // --ref, --plus and --minus come with an axis
    if (c.ref) s.ref.at(i) = *c.ref;
    if (c.plus) s.plus.at(i) = *c.plus;
    if (c.minus) s.minus.at(i) = *c.minus;
    if (c.nc) s.nc = *c.nc;
    p.set_switches(s);
    s = p.get_switches();
  }
  out << (c.json ? limits_json(s, p.get_axes(), device_of(c)) + "\n" : limits_text(s, p.get_axes()));
}

void zero_command(port &p, const config &c, std::ostream &out) {
  for (x4step::axis ax : c.axes) p.set_position(ax, c.at);
  const x4step::axes_status a = p.get_axes();
  for (x4step::axis ax : c.axes)
    out << axis_name(ax) << " at " << a[ax].position
        << (a[ax].synced ? ", synchronized" : ", not synchronized") << "\n";
}

coordinates start_goto_command(port &p, const config &c, std::ostream &out) {
  const x4step::axes_status now = p.get_axes();
  coordinates want{};
  std::string what;
  for (x4step::axis a : c.axes) {
    const int i = a.index();
    want[i] = c.relative ? wrapped(now[a].position, c.targets[i]) : c.targets[i];
    what += (what.empty() ? "" : ", ") + std::to_string(a.number()) +
            (c.relative ? " by " + std::to_string(c.targets[i]) : "") + " to " + std::to_string(want[i]);
  }
  out << "goto: " << what << "\n" << std::flush;
  start_goto(p, c.axes, c.targets, c.relative);
  return want;
}

void finish_goto_command(port &p, console &con, const config &c, const coordinates &want, std::ostream &out) {
  const axes_outcome o = follow_axes(p, con, c.axes);
  std::string problems;
  for (x4step::axis a : c.axes) {
    const std::string why = axis_problem(a, o.end[a], want[a.index()], o.halted_by);
    if (!why.empty()) problems += (problems.empty() ? "" : "; ") + why;
  }
  if (!problems.empty()) throw failure(problems + "; coordinates " + coordinates_text(o.end));
  out << "done: " << coordinates_text(o.end) << "\n";
}

void home_command(port &p, console &con, const config &c, std::ostream &out) {
  const x4step::homing &h = c.homing;
  const std::string name = axis_name(c.axis);
  start_home(p, c.axis, h);
  out << "home: " << name;
  if (h.phase1()) out << ", phase 1 at " << h.phase1_speed() << " steps/s";
  if (h.phase2()) out << ", phase 2 at " << h.phase2_speed() << " steps/s";
  out << ", at most " << h.max_travel() << " steps each\n" << std::flush;
  const axes_outcome o = follow_axes(p, con, c.axis);
  const x4step::axis_status &a = o.end[c.axis];
  const std::string at = " at " + std::to_string(a.position);
  if (a.error & x4step::axis_error::ref_travel)
    throw failure(name + ": reference travel exceeded" + at + ": the reference switch did not " +
                  (!h.phase2()  ? "become active"
                   : h.phase1() ? "become active (phase 1) or change again (phase 2)"
                                : "change") +
                  " within " + std::to_string(h.max_travel()) +
                  " steps (sref); check its input ('x4ctl limits') and the direction (sign) of the speed");
  if (a.error) throw failure(axis_problem(c.axis, a, std::nullopt, o.halted_by) + "; not referenced");
  const int ref = p.get_switches().ref.at(c.axis.index());
  const bool done = h.phase2() ? a.synced : ref && (o.end.switches_active >> (ref - 1) & 1u);
  if (!done) throw failure(name + halted_text(o.halted_by) + at + ": not referenced");
  if (h.phase2())
    out << "done: " << name << at << ", synchronized\n";
  else
    out << "done: " << name << at << ", reference switch active (phase 1; 'x4ctl home " << c.axis.number()
        << " --phase 2' completes it)\n";
}

}  // namespace x4ctl
