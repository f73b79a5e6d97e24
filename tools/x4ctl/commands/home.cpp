// SPDX-License-Identifier: GPL-2.0
// x4ctl home: the reference run of an axis, or of a machine's axes.
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <iostream>

#include "commands.hpp"
#include "holder.hpp"
#include "operate.hpp"
#include "options.hpp"
#include "position.hpp"
#include "subcommand.hpp"
#include "term.hpp"
#include "values.hpp"

namespace x4ctl {
namespace {

// AXIS (1..4) without --machine: steps; axis letters or --machine: machine units. Nothing
// given with $X4STEP_MACHINE set: all its axes (as panel and gcode take it without -m).
void operands(parse_state &s, const std::vector<std::string> &ops) {
  config &c = s.c;
  const std::string &prefix = s.prefix;
  if (c.machine.empty() && ops.empty())
    if (const char *env = std::getenv("X4STEP_MACHINE"); env && *env) c.machine = env;
  if (!c.machine.empty() || (!ops.empty() && std::isalpha(static_cast<unsigned char>(ops[0][0])))) {
    for (const std::string &o : ops)
      for (char ch : o) {
        if (!is_axis_letter(ch))
          throw usage_error(prefix + "'" + o + "': give axis letters (X Y Z A B C), or one AXIS 1..4");
        c.letters += upper(ch);
      }
    if (s.gave({"vref1", "vref2", "sref", "phase", "brake"}))
      throw usage_error(prefix +
                        "--vref1, --vref2, --sref, --phase and --brake are for AXIS in steps; the "
                        "machine file gives the homing of axis letters");
    return;
  }
  need_operands(ops, 1, 1, prefix);
  c.axis = parse_axis(ops[0], prefix);
}

int run_steps(const config &c) {
  controller_port p(open_controller(device_of(c)));
  std_console con(true);
  home_command(p, con, c, std::cout);
  return 0;
}

// AXIS in steps, or a machine's axes (operate.cpp).
int run(const config &c) { return c.machine_units() ? cmd_home_machine(c) : run_steps(c); }

}  // namespace

const subcommand &home_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    const std::string vel = std::to_string(x4step::vel_max);
    c.name = "home";
    c.usage = {"[OPTIONS] AXIS", "[--machine FILE] [LETTERS...]"};
    c.synopsis = "AXIS";
    c.summary =
        "reference run: find the reference switch, zero there;\n"
        "'home --machine FILE [LETTERS]': a machine's axes";
    c.prose =
        "Reference run of AXIS (ProStep4 section 3), without ramps: phase 1 runs at\n"
        "vref1 until the reference switch becomes active and stops there (--brake:\n"
        "brakes past it along the axis' profile deceleration, 'x4ctl profile AXIS\n"
        "--ae'); 50 ms later phase 2 runs from rest at vref2 until the switch changes\n"
        "again; there the coordinate becomes 0 and the axis synchronized. Each\n"
        "phase travels at most sref steps. Needs the axis' reference switch input\n"
        "('x4ctl limits AXIS --ref INPUT'). Waits until the run ends; ESC or Ctrl-C\n"
        "brakes it.\n"
        "\n"
        "With axis letters or --machine, or nothing with $X4STEP_MACHINE set, the axes\n"
        "of a machine file (all that home, or those named: 'home Z', 'home X Y')\n"
        "home as its [JOINT_n] HOME_* keys say (machines/README.md), in HOME_SEQUENCE\n"
        "order, those of one sequence at\n"
        "the same time: the reference run above on HOME_INPUT at HOME_SEARCH_VEL,\n"
        "then HOME_LATCH_VEL (units/s, times SCALE), each phase within 1.25 times\n"
        "the travel between the soft limits; there the axis' coordinate becomes\n"
        "HOME_OFFSET (the switch's place in machine coordinates), and it goes to\n"
        "HOME at MAX_VELOCITY before the next sequence starts. The inputs' polarity\n"
        "is the port's ('x4ctl limits --nc'). ESC or Ctrl-C brakes; an axis that\n"
        "does not home stops the later sequences.\n";
    c.options = {
        {"vref1", 0, "V",
         "phase 1 speed, signed: -" + vel + "..-1 or 1.." + vel +
             " steps/s,\n"
             "the sign is the direction (default -1000)",
         [](parse_state &s, const option_value &o) {
           s.c.homing.phase1_speed(parse_vref(o.value, "vref1", s.prefix));
         }},
        {"vref2", 0, "V", "phase 2 speed, the same way (default 100)",
         [](parse_state &s, const option_value &o) {
           s.c.homing.phase2_speed(parse_vref(o.value, "vref2", s.prefix));
         }},
        {"sref", 0, "N",
         "the longest travel of a phase, 1..2147483647 steps\n"
         "(default 100000)",
         [](parse_state &s, const option_value &o) {
           s.c.homing.max_travel(
               static_cast<unsigned long>(parse_range(o.value, "sref", 1, INT32_MAX, " steps", s.prefix)));
         }},
        {"phase", 0, "1|2", "only this phase (semi-automatic); default both",
         [](parse_state &s, const option_value &o) {
           const long ph = parse_number(o.value, s.prefix + "phase");
           if (ph != 1 && ph != 2)
             throw usage_error(s.prefix + "phase " + o.value + ": use 1 or 2 (both: no --phase)");
           s.c.homing.phase1(ph == 1).phase2(ph == 2);
         }},
        {"brake", 0, "",
         "phase 1 brakes past the switch (it must stay active\n"
         "over the brake distance, vref1^2 / 2 ae steps)",
         [](parse_state &s, const option_value &) { s.c.homing.brake(true); }},
        machine_option("the machine file of LETTERS (default: $X4STEP_MACHINE,\n"
                       "else /etc/x4step/machine.ini); its PORT is the port"),
    };
    c.epilogue =
        "Exit status: 0 done (both phases or phase 2: the axis is synchronized);\n"
        "1 the port refused, no reference switch, sref exceeded, a limit switch hit,\n"
        "or the run was halted; 2 bad usage.\n"
        "Examples: x4ctl home 1 --vref1 -2000 --vref2 200 --sref 50000\n"
        "          x4ctl home --machine machines/smc1500-mill.ini\n";
    c.operands = operands;
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
