// SPDX-License-Identifier: GPL-2.0
// x4ctl panel: the full-screen operator panel of a machine (panel.cpp).
#include "panel.hpp"

#include "commands.hpp"
#include "options.hpp"
#include "subcommand.hpp"

namespace x4ctl {

const subcommand &panel_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "panel";
    c.usage = {"[OPTIONS]"};
    c.summary =
        "full-screen operator panel of a machine: positions, jog,\n"
        "set zero, go to, home, open and run a G-code program";
    c.prose =
        "A full-screen operator panel for a machine file's machine, as the SMC1500\n"
        "program's screen: each axis' position in work coordinates (the parameter\n"
        "file's offsets) and machine coordinates (updated while it moves), homed or\n"
        "not, the jog feed and step, the program opened, the state.\n"
        "Keys:\n"
        "  Right/Left  jog X+/X-        Up/Down  jog Y+/Y-     PgUp/PgDn  jog Z+/Z-\n"
        "  ] / [       jog A+/A-\n"
        "  i           jog step: while held, or 1, 0.1, 0.01 units. A terminal reports\n"
        "              no key release: a jog while held goes on while the key repeats\n"
        "              and brakes 0.1 s after its repeats stop (0.7 s after one press)\n"
        "  c           the next jog runs to the soft limit, until a key brakes it\n"
        "  + / -       jog and go-to feed up/down (1-2-5 steps, at most MAX_VELOCITY)\n"
        "  z or 0      set the work zero of every axis where it stands: the active\n"
        "              work system's offset (G54 ...), kept in the machine file's\n"
        "              [RS274NGC] PARAMETER_FILE (as 'x4ctl touch-off'; without\n"
        "              one, for this session only); machine coordinates and soft\n"
        "              limits stay, nothing is written to the port\n"
        "  g           go to a position in work coordinates (typed: X10 Y-5; Enter\n"
        "              goes, ESC cancels); each axis on its own at the feed\n"
        "  h           home (as 'x4ctl home --machine FILE')\n"
        "  o           open a G-code program (its file typed; Enter opens, ESC\n"
        "              cancels) and check it at once as 'x4ctl gcode --check' from\n"
        "              where the machine stands, with the parameter file's offsets\n"
        "              and homed first: lines, time, work extents, or the refusal\n"
        "              (FILE:LINE:COLUMN) on the message line\n"
        "  r           cycle start: check the program again from where the machine\n"
        "              stands now and run it as 'x4ctl gcode' does; the state line\n"
        "              shows running or held, the line, percent and time left.\n"
        "              While it runs: space holds and resumes, ESC aborts (hold,\n"
        "              then flush), + / - feed override by 10 %; M0, M1, M6 wait\n"
        "              for space with the path at rest. At its end: done or aborted,\n"
        "              the machine time and the estimate; offsets a program that\n"
        "              ran to its end changed (G10, G92 ...) are kept\n"
        "  space, ESC  stop: while anything moves, every key brakes it\n"
        "  q           quit (also Ctrl-C)\n"
        "Moves keep to the soft limits. Nothing is left running when the panel ends:\n"
        "a move is braked first, a program aborted along its path (also at SIGINT,\n"
        "SIGTERM or a hang-up). Needs a terminal; the machine file's PORT is the\n"
        "port unless -d is given.\n";
    c.options = {
        machine_option(machine_file_help),
        feed_option("the feed to start with, units/min, at most the fastest\n"
                    "axis' MAX_VELOCITY (default: a quarter of that)"),
    };
    c.epilogue =
        "Exit status: 0 quit; 1 the port refused, or no terminal; 2 bad usage or\n"
        "machine file.\n"
        "Example: x4ctl panel --machine machines/smc1500-mill.ini\n";
    c.run = cmd_panel;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
