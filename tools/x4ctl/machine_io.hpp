// SPDX-License-Identifier: GPL-2.0
// x4ctl: a machine file (lib/machine) on a port: loading it, opening its
// port, and converting between its units and the motors' steps. Shared by
// gcode, mdi, and the operator's commands (home, jog, panel).
#ifndef X4CTL_MACHINE_IO_HPP
#define X4CTL_MACHINE_IO_HPP

#include <string>
#include <vector>

#include "cli.hpp"
#include "io.hpp"
#include "machine.hpp"
#include "params.hpp"
#include "planner.hpp"
#include "x4step_path.hpp"

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

/// The offsets and stored positions of the machine's parameter file
/// ([RS274NGC] PARAMETER_FILE; none: all zero, G54). A bad file is a
/// failure "COMMAND: file:line: ...".
g::coordinate_state load_coordinates(const m::machine &mc, const std::string &command);
/// Puts what a command changed (before -> after) into the parameter file,
/// under its lock (nothing if it has none or nothing changed).
void save_coordinates(const m::machine &mc, const g::coordinate_state &before,
                      const g::coordinate_state &after, const std::string &command);

/// ", work X1 Z-2" for the axes given: where they stand (machine
/// position p) in the active work system of the parameter file; "" if
/// it has no offset for them.
std::string work_text(const m::machine &mc, const std::vector<size_t> &axes, const g::pose &p,
                      const std::string &command);

/// Every axis of the machine (gcode::X ...).
std::vector<size_t> machine_axes_of(const m::machine &mc);
/// The axes among `axes` that have a home switch (HOME_SEARCH_VEL) and are
/// not referenced on the port; none if [TRAJ] NO_FORCE_HOMING = 1.
std::vector<size_t> unhomed_axes(const m::machine &mc, const x4step::axes_status &st,
                                 const std::vector<size_t> &axes);
/// "X, Y and Z are not homed: home them first: x4ctl home --machine FILE
/// (or ...NO_FORCE_HOMING...)": why a program that moves them is refused.
std::string unhomed_text(const config &c, const m::machine &mc, const std::vector<size_t> &axes);

/// A number for people: at most 3 decimals (1 above 100), no trailing zeros.
std::string number(double v);

/// The motor of an axis.
inline x4step::axis motor_of(const m::axis &a) { return x4step::axis(a.motor + 1); }
/// Units to steps: rounded once, from the absolute position.
long steps_of(const m::axis &a, double units);
/// Where the motors stand, machine units.
g::pose pose_of(const m::machine &mc, const x4step::axes_status &at);
/// The same for motor steps (motor 1..4 at 0..3): a latch, a plan's end.
g::pose pose_of(const m::machine &mc, const std::array<long, x4step::axes> &steps);

/// G38.x run: the engine's probe mode of a kind (toward for G38.2/G38.3,
/// away for G38.4/G38.5), and the planner's answer once the probing
/// segment ended with the latch l and the motors at `at` (the trip is
/// where they stopped if it did not trip).
x4step::probe_mode probe_mode_of(g::probe_kind k);
m::probe_result probe_result_of(const x4step::probe_latch &l, const x4step::axes_status &at);

}  // namespace x4ctl

#endif  // X4CTL_MACHINE_IO_HPP
