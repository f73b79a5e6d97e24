// SPDX-License-Identifier: GPL-2.0
// x4ctl: the subcommands and the program's entry point.
#ifndef X4CTL_COMMANDS_HPP
#define X4CTL_COMMANDS_HPP

#include <string>
#include <vector>

namespace x4ctl {

/// Runs x4ctl with args (args[0] is the program name): output on
/// std::cout, messages on std::cerr. Returns the exit status: 0 success,
/// 1 the port refused or a move did not reach its target, 2 bad usage.
int run_main(const std::vector<std::string> &args);

}  // namespace x4ctl

#endif  // X4CTL_COMMANDS_HPP
