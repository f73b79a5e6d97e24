// SPDX-License-Identifier: GPL-2.0
// x4ctl: stepper motors on the parallel port from the shell, and X4Step's
// test program. See `x4ctl --help`.
#include <string>
#include <vector>

#include "commands.hpp"

int main(int argc, char **argv) { return x4ctl::run_main(std::vector<std::string>(argv, argv + argc)); }
