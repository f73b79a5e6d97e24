// SPDX-License-Identifier: GPL-2.0
// x4ctl: a machine file (lib/machine) on a port: loading it, opening its
// port, and converting between its units and the motors' steps. Shared by
// gcode, mdi, and the operator's commands (home, jog, panel).
#ifndef X4CTL_MACHINE_IO_HPP
#define X4CTL_MACHINE_IO_HPP

#include <string>

#include "cli.hpp"
#include "io.hpp"
#include "machine.hpp"

namespace x4ctl {

namespace m = x4step::machine;
namespace g = x4step::gcode;

/// "XYZABC": the letter of gcode::X ...
extern const char *const axis_letters;

std::string units_name(const m::machine &mc);
/// --machine, else $X4STEP_MACHINE, else /etc/x4step/machine.ini.
std::string machine_path(const config &c);
/// The machine file of c; a bad one is a usage_error "COMMAND: file:line:col: ...",
/// a line for each mistake. Its warnings go to stderr.
m::machine load_machine(const config &c, const std::string &command);
/// The mistakes of a machine file, a line each: "COMMAND: file:line:col: ...",
/// the lines after the first with "x4ctl: " (as x4ctl writes the first).
std::string machine_error_text(const m::error &e, const std::string &command);
/// The device of the machine's PORT (unless -d names one; --sim: sim:N).
std::string machine_device(const config &c, const m::machine &mc);

/// Checks that the port can step every axis at its MAX_VELOCITY with its
/// step timing (failure if not), then sets the machine's output mode.
void prepare_port(port &p, const m::machine &mc);

/// A number for people: at most 3 decimals (1 above 100), no trailing zeros.
std::string number(double v);

/// The motor of an axis.
inline x4step::axis motor_of(const m::axis &a) { return x4step::axis(a.motor + 1); }
/// Units to steps: rounded once, from the absolute position.
long steps_of(const m::axis &a, double units);
/// Where the motors stand, machine units.
g::pose pose_of(const m::machine &mc, const x4step::axes_status &at);

}  // namespace x4ctl

#endif  // X4CTL_MACHINE_IO_HPP
