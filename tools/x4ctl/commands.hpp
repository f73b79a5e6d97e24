// SPDX-License-Identifier: GPL-2.0
// x4ctl: what the commands share, and the program's entry point.
#ifndef X4CTL_COMMANDS_HPP
#define X4CTL_COMMANDS_HPP

#include <exception>
#include <ostream>
#include <string>
#include <vector>

#include "cli.hpp"
#include "io.hpp"
#include "motion.hpp"

namespace x4ctl {

/// Runs x4ctl with args (args[0] is the program name): output on
/// std::cout, messages on std::cerr. Returns the exit status: 0 success,
/// 1 the port refused or a move did not reach its target, 2 bad usage.
int run_main(const std::vector<std::string> &args);

/// Opens the port as its controller; a refusal says who holds it and what
/// to do (throws failure).
x4step::controller open_controller(const std::string &dev);

/// The message of any exception, the X4Step ones in the library's words.
std::string what_of(const std::exception &e);

/// Opens the port read-only; a refusal says what to do (throws failure).
x4step::monitor open_monitor(const std::string &dev);

/// When --time ends, on the port's clock (none: no --time).
deadline deadline_of(const config &c, const port &p);

/// brake, stop, halt, monitor and watch act on another program's moves: a
/// simulated port has none (it lives in this x4ctl alone): throws failure.
void refuse_sim(const std::string &dev, const char *command);

/// A one-shot setting on a simulated port: say that it ends with x4ctl.
void note_sim_setting(const std::string &dev);

/// brake, stop and halt: the moves belong to the process that holds the
/// port; when that is an x4ctl, ask it to brake (or stop) the axes.
void ask_holder(const std::string &dev, bool stop, x4step::axis_set axes);

/// brake and stop: the module's emergency halt of the running move, any
/// program's; waits until the motors stand and shows the steps.
int halt_moves(const config &c, bool stop);

/// timing, mode, profile, limits, zero: a setting of an open port; changes:
/// it set something (a simulated port forgets it: say so).
int with_port(const config &c, void (*command)(port &, const config &, std::ostream &), bool changes);

/// `x4ctl timing` on an open port: changes the times c gives, keeping the
/// others (read, modify, write), and writes the timing the port then has.
void timing_command(port &p, const config &c, std::ostream &out);

/// `x4ctl mode` on an open port: sets c.mode if given, keeping the rest of
/// the port's configuration, and writes the mode the port then has.
void mode_command(port &p, const config &c, std::ostream &out);

}  // namespace x4ctl

#endif  // X4CTL_COMMANDS_HPP
