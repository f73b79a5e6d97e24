// SPDX-License-Identifier: GPL-2.0
// x4ctl: a machine file on a port.
#include "machine_io.hpp"

#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "show.hpp"

namespace x4ctl {

const char *const axis_letters = "XYZABC";

std::string units_name(const m::machine &mc) { return mc.units == g::units::inch ? "inch" : "mm"; }

std::string machine_path(const config &c) {
  if (!c.machine.empty()) return c.machine;
  const char *env = std::getenv("X4STEP_MACHINE");
  return env && *env ? env : "/etc/x4step/machine.ini";
}

m::machine load_machine(const config &c, const std::string &command) {
  try {
    m::machine mc = m::read_file(machine_path(c));
    for (const std::string &w : mc.warnings) std::cerr << "x4ctl: " << command << ": warning: " << w << "\n";
    return mc;
  } catch (const m::error &e) {
    throw usage_error(machine_error_text(e, command));
  }
}

std::string machine_error_text(const m::error &e, const std::string &command) {
  std::string out;
  for (const std::string &l : e.lines()) out += (out.empty() ? "" : "\nx4ctl: ") + command + ": " + l;
  return out;
}

std::string machine_device(const config &c, const m::machine &mc) {
  config port_config = c;
  port_config.lpt = mc.port[3] - '0';
  return device_of(port_config);
}

namespace {

x4step::output_mode mode_of(m::output_mode o) {
  switch (o) {
    case m::output_mode::smc_phase:
      return x4step::output_mode::smc_phase;
    case m::output_mode::smc_hold:
      return x4step::output_mode::smc_phase_hold;
    case m::output_mode::clock_dir:
      break;
  }
  return x4step::output_mode::clock_dir;
}

}  // namespace

void prepare_port(port &p, const m::machine &mc) {
  const x4step::output_mode mode = mode_of(mc.mode);
  // The axes' top speeds within what the port's step timing allows in that mode.
  const int fmax = max_freq_hz(p.get_step_timing(), mode, x4step::vel_max);
  for (size_t a = 0; a < g::n_axes; a++)
    if (mc.axes[a] && std::fabs(mc.axes[a]->scale) * mc.axes[a]->max_velocity > fmax)
      throw failure(std::string("[AXIS_") + axis_letters[a] + "] MAX_VELOCITY needs " +
                    std::to_string(std::lround(std::fabs(mc.axes[a]->scale) * mc.axes[a]->max_velocity)) +
                    " steps/s; the port's step timing allows " + std::to_string(fmax) + ": lower it");
  if (p.get_config().mode() != mode) p.set_config(p.get_config().mode(mode));
}

g::coordinate_state load_coordinates(const m::machine &mc, const std::string &command) {
  if (mc.parameter_file.empty()) return {};
  try {
    return m::parameter_file(mc.parameter_file).read();
  } catch (const m::parameter_error &e) {
    throw failure(command + ": " + e.what());
  }
}

void save_coordinates(const m::machine &mc, const g::coordinate_state &before,
                      const g::coordinate_state &after, const std::string &command) {
  if (mc.parameter_file.empty() || before == after) return;
  try {
    m::parameter_file(mc.parameter_file).update([&](g::coordinate_state &now) {
      m::apply_changes(now, before, after);
    });
  } catch (const m::parameter_error &e) {
    throw failure(command + ": " + e.what());
  }
}

std::string work_text(const m::machine &mc, const std::vector<size_t> &axes, const g::pose &p,
                      const std::string &command) {
  const g::pose off = load_coordinates(mc, command).work_offset();
  std::string s;
  bool any = false;
  for (size_t a : axes) {
    s += " " + std::string(1, axis_letters[a]) + number(p[a] - off[a]);
    any = any || off[a] != 0;
  }
  return any ? ", work" + s : "";
}

std::vector<size_t> machine_axes_of(const m::machine &mc) {
  std::vector<size_t> r;
  for (size_t a = 0; a < g::n_axes; a++)
    if (mc.axes[a]) r.push_back(a);
  return r;
}

std::vector<size_t> unhomed_axes(const m::machine &mc, const x4step::axes_status &st,
                                 const std::vector<size_t> &axes) {
  std::vector<size_t> r;
  if (mc.no_force_homing) return r;
  for (size_t a : axes)
    if (mc.axes[a] && mc.axes[a]->home.enabled && !st[motor_of(*mc.axes[a])].synced) r.push_back(a);
  return r;
}

std::string unhomed_text(const config &c, const m::machine &mc, const std::vector<size_t> &axes) {
  std::string names;
  for (size_t i = 0; i < axes.size(); i++)
    names += (i == 0 ? "" : i + 1 == axes.size() ? " and " : ", ") + std::string(1, axis_letters[axes[i]]);
  const std::string file = machine_path(c);
  const bool all = unhomed_axes(mc, x4step::axes_status{}, machine_axes_of(mc)).size() == axes.size();
  std::string letters;
  for (size_t a : axes) letters += axis_letters[a];
  return names + (axes.size() == 1 ? " is" : " are") + " not homed: home first: x4ctl" +
         (c.sim ? " --sim" : "") + " home --machine " + file + (all ? "" : " " + letters) +
         " (a machine without home switches may set [TRAJ] NO_FORCE_HOMING = 1)";
}

std::string number(double v) {
  std::ostringstream o;
  o << std::fixed << std::setprecision(std::fabs(v) < 100 ? 3 : 1) << v;
  std::string s = o.str();
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s == "-0" ? "0" : s;
}

long steps_of(const m::axis &a, double units) { return std::lround(units * a.scale); }

g::pose pose_of(const m::machine &mc, const x4step::axes_status &at) {
  std::array<long, x4step::axes> steps{};
  for (x4step::axis a : x4step::axis_set::all()) steps[size_t(a.index())] = at[a].position;
  return pose_of(mc, steps);
}

g::pose pose_of(const m::machine &mc, const std::array<long, x4step::axes> &steps) {
  g::pose p{};
  for (size_t a = 0; a < g::n_axes; a++)
    if (mc.axes[a]) p[a] = double(steps[size_t(mc.axes[a]->motor)]) / mc.axes[a]->scale;
  return p;
}

x4step::probe_mode probe_mode_of(g::probe_kind k) {
  return k == g::probe_kind::toward_or_error || k == g::probe_kind::toward ? x4step::probe_mode::toward
                                                                           : x4step::probe_mode::away;
}

m::probe_result probe_result_of(const x4step::probe_latch &l, const x4step::axes_status &at) {
  m::probe_result r;
  r.ran = true;
  r.tripped = l.tripped;
  for (x4step::axis a : x4step::axis_set::all()) {
    r.stop[size_t(a.index())] = at[a].position;
    r.trip[size_t(a.index())] = l.tripped ? l.steps[size_t(a.index())] : at[a].position;
  }
  return r;
}

}  // namespace x4ctl
