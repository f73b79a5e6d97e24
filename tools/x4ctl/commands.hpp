// SPDX-License-Identifier: GPL-2.0
// x4ctl: the subcommands and the program's entry point.
#ifndef X4CTL_COMMANDS_HPP
#define X4CTL_COMMANDS_HPP

#include <ostream>
#include <string>
#include <vector>

#include "cli.hpp"
#include "io.hpp"

namespace x4ctl {

/// Runs x4ctl with args (args[0] is the program name): output on
/// std::cout, messages on std::cerr. Returns the exit status: 0 success,
/// 1 the port refused or a move did not reach its target, 2 bad usage.
int run_main(const std::vector<std::string> &args);

/// Opens the port as its controller; a refusal says who holds it and what
/// to do (throws failure).
x4step::controller open_controller(const std::string &dev);

/// `x4ctl timing` on an open port: changes the times c gives, keeping the
/// others (read, modify, write), and writes the timing the port then has.
void timing_command(port &p, const config &c, std::ostream &out);

/// `x4ctl mode` on an open port: sets c.mode if given, keeping the rest of
/// the port's configuration, and writes the mode the port then has.
void mode_command(port &p, const config &c, std::ostream &out);

}  // namespace x4ctl

#endif  // X4CTL_COMMANDS_HPP
