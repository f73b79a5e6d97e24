// SPDX-License-Identifier: GPL-2.0
// x4ctl mdi: G-code blocks given as arguments (gcode_cmd.cpp runs them).
#include "commands.hpp"
#include "gcode_cmd.hpp"
#include "options.hpp"
#include "subcommand.hpp"

namespace x4ctl {
namespace {

void operands(parse_state &s, const std::vector<std::string> &ops) {
  need_operands(ops, 1, ops.size(), s.prefix);
  for (const std::string &b : ops)
    if (b.find_first_of("\n\r") != std::string::npos)
      throw usage_error(s.prefix + "a block holds no line break: give each line as its own argument");
  s.c.blocks = ops;
}

}  // namespace

const subcommand &mdi_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "mdi";
    c.usage = {"[OPTIONS] BLOCK..."};
    c.synopsis = "BLOCK...";
    c.summary = "run G-code blocks given as arguments (\"G1 X10 F300\")";
    c.prose =
        "Run G-code blocks typed on the command line (manual data input), each\n"
        "argument one line, as a program of those lines followed by M2: checked\n"
        "whole first (a bad word is named as mdi:LINE:COLUMN and nothing moves),\n"
        "then run as 'x4ctl gcode' runs a file, from where the machine stands, with\n"
        "its keys and options, axes with a home switch homed first. The modal state\n"
        "does not persist between invocations: each starts in the machine file's\n"
        "units, G90, G17, G94, G54, no tool length offset and no feed rate (give\n"
        "G91, G20 or F again in the blocks that need them), and ends with M2, which\n"
        "makes G54 the active system again. The work offsets (G10 L2/L20), the\n"
        "G28/G30 positions (G28.1/G30.1) and G92 persist: read from and written to\n"
        "the machine file's [RS274NGC] PARAMETER_FILE, as 'x4ctl gcode' does.\n";
    c.options = {
        machine_option(machine_file_help),
        check_option("check the blocks and stop there; nothing moves"),
        override_option(),
        no_pause_option("M0, M1 and M6 stop the path, say so and go on"),
        json_option("the summary, progress and result as JSON lines\n"
                    "(times in seconds on the port's clock)"),
    };
    c.epilogue =
        "Exit status: 0 the blocks ran to their end (or --check found them good);\n"
        "1 aborted or the port refused; 2 bad usage, a bad machine file or block.\n"
        "Example: x4ctl mdi --machine machines/smc1500-mill.ini \"G0 Z-1\" \"G1 X10 Y5 F300\"\n";
    c.operands = operands;
    c.run = cmd_mdi;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
