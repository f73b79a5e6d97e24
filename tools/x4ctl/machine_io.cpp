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
  g::pose p{};
  for (size_t a = 0; a < g::n_axes; a++)
    if (mc.axes[a]) p[a] = double(at[motor_of(*mc.axes[a])].position) / mc.axes[a]->scale;
  return p;
}

}  // namespace x4ctl
