// SPDX-License-Identifier: GPL-2.0
// x4ctl gcode: a G-code part program on a machine (gcode_cmd.cpp runs it).
#include "commands.hpp"
#include "gcode_cmd.hpp"
#include "options.hpp"
#include "subcommand.hpp"
#include "values.hpp"

namespace x4ctl {
namespace {

// Read twice (checked, then run): a file, not standard input.
void operands(parse_state &s, const std::vector<std::string> &ops) {
  need_operands(ops, 1, 1, s.prefix);
  s.c.file = ops[0];
}

}  // namespace

const subcommand &gcode_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "gcode";
    c.usage = {"[OPTIONS] FILE"};
    c.synopsis = "FILE";
    c.summary = "run a G-code part program on a machine (machine file)";
    c.prose =
        "Run a G-code part program (RS274/NGC as CAM post-processors for LinuxCNC\n"
        "and GRBL write it) on a machine described by a machine file (axes, steps\n"
        "per unit, speeds, soft limits, port: machines/README.md). The whole program\n"
        "is checked first, from where the machine stands: a bad line, or a point\n"
        "beyond a soft limit, is named as FILE:LINE:COLUMN and nothing moves; so is\n"
        "a program that moves an axis with a home switch that is not homed ('x4ctl\n"
        "home', unless the machine file says [TRAJ] NO_FORCE_HOMING = 1). Then it\n"
        "runs on the module's path queue, with its progress on one line that fits\n"
        "the terminal: state, percent of the path length, line, feed, elapsed and\n"
        "remaining time, the keys that work (on a narrow terminal the least needed\n"
        "go first); at the end the machine time and the estimate (\"done in 2:18,\n"
        "estimated 2:11\"), on the port's clock (a simulated port's virtual time).\n"
        "Work offsets (G54..G59.3 and the active one), G28/G30 positions and G92\n"
        "come from the machine file's [RS274NGC] PARAMETER_FILE (LinuxCNC's .var\n"
        "numbering; 'x4ctl touch-off' and the panel's zero set them); what a program\n"
        "that runs to its end changes (G10 L2/L20, G28.1, G30.1, G92) is written back.\n"
        "Keys on a terminal: space holds and resumes, ESC aborts (hold, then flush),\n"
        "+ and - change the feed override by 10 %. Ctrl-C aborts too; 'x4ctl stop'\n"
        "stops at once. M0, M1 and M6 wait for space (or ESC) with the path at\n"
        "rest: such a program needs a terminal, or --no-pause. Outputs the machine\n"
        "file names for spindle and coolant follow M3/M4/M5 and M7/M8/M9, and are\n"
        "switched off at the end. The machine file's PORT is the port unless -d is\n"
        "given.\n";
    c.options = {
        machine_option(machine_file_help),
        check_option("check the program and stop there: a summary (lines,\n"
                     "segments, path length, estimated time, extents in\n"
                     "work and machine coordinates), as if the machine\n"
                     "stood at machine zero; nothing moves"),
        override_option(),
        no_pause_option("M0, M1 and M6 stop the path, say so and go on without\n"
                        "waiting (a preview on the simulated port, a script)"),
        {"svg", 0, "FILE",
         "draw the planned toolpath (cuts solid, rapids dashed)\n"
         "and what the motors did (positions read during the\n"
         "run; planned but not done in orange), top view X Y\n"
         "and side view X Z (Z scaled up on a flat part), in\n"
         "work coordinates, with a grid, a legend and the\n"
         "largest deviation; with --check the planned path only",
         [](parse_state &s, const option_value &o) {
           if (o.value.empty()) throw usage_error(s.prefix + "--svg needs a file");
           s.c.svg = o.value;
         }},
        json_option("the summary, progress and result as JSON lines\n"
                    "(times in seconds on the port's clock)"),
    };
    c.epilogue =
        "Exit status: 0 the program ran to its end (or --check found it good); 1 it\n"
        "was aborted or the port refused; 2 bad usage, a bad machine file or program.\n"
        "Example: x4ctl gcode --machine machines/smc1500-mill.ini --check part.ngc\n";
    c.operands = operands;
    c.run = cmd_gcode;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
