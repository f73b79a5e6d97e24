// SPDX-License-Identifier: GPL-2.0
// x4ctl jog: an endless move of one axis until braked, or an axis of a machine in its units.
#include <iostream>

#include "commands.hpp"
#include "holder.hpp"
#include "motion.hpp"
#include "operate.hpp"
#include "options.hpp"
#include "subcommand.hpp"
#include "term.hpp"
#include "values.hpp"

namespace x4ctl {
namespace {

void operands(parse_state &s, const std::vector<std::string> &ops) {
  config &c = s.c;
  const std::string &prefix = s.prefix;
  need_operands(ops, 1, 2, prefix);
  if (ops.size() == 1) {  // X+: machine units
    const std::string &o = ops[0];
    if (o.size() != 2 || !is_axis_letter(o[0]) || (o[1] != '+' && o[1] != '-'))
      throw usage_error(prefix + "'" + o +
                        "': give an axis letter and a sign (X+, Z-), or AXIS +|- in steps");
    if (s.gave({"freq", "ramp", "time", "wait"}))
      throw usage_error(prefix + "--freq, --ramp, --time and --wait are for AXIS +|- in steps; " + o +
                        " takes --machine, --feed and --distance");
    c.letters = std::string(1, upper(o[0]));
    c.dir = o[1] == '+' ? x4step::direction::positive : x4step::direction::negative;
    return;
  }
  if (c.machine_units() || c.feed || c.distance)
    throw usage_error(prefix +
                      "--machine, --feed and --distance jog an axis letter, e.g. 'jog X+ --machine FILE'");
  c.axis = parse_axis(ops[0], prefix);
  if (ops[1] == "+" || ops[1] == "pos")
    c.dir = x4step::direction::positive;
  else if (ops[1] == "-" || ops[1] == "neg")
    c.dir = x4step::direction::negative;
  else
    throw usage_error(prefix + "direction '" + ops[1] + "': use + or -");
  if (const auto e = x4step::check_endless(c.move.freq_hz, c.move.ramp); e != x4step::errc::ok)
    throw usage_error(prefix + message(e));
}

int run_steps(const config &c) {
  controller_port p(open_controller(device_of(c)));
  std_console con(c.wait);
  if (c.wait) check_endless_ends(p, con, c.time.has_value(), "jog", std::make_pair(c.axis, c.dir));
  std::cout << "jog: axis " << c.axis.number() << (c.dir == x4step::direction::positive ? " +" : " -")
            << " at " << c.move.freq_hz << " Hz, ramp " << c.move.ramp.count() << " ms"
            << (c.time ? ", for " + std::to_string(c.time->count()) + " ms" : "") << "\n"
            << std::flush;
  if (!c.wait) {
    start_endless(p, c.axis, c.dir, c.move.freq_hz, c.move.ramp);
    const deadline until = deadline_of(c, p);
    hold_in_background(p, [&](console &bg) { follow(p, bg, std::nullopt, until); });
    return 0;
  }
  const outcome o = run_endless(p, con, c.axis, c.dir, c.move.freq_hz, c.move.ramp, deadline_of(c, p));
  std::cout << describe(o, std::nullopt) << "\n";
  return 0;
}

// AXIS +|- in steps, or LETTER+|- in a machine's units (operate.cpp).
int run(const config &c) { return c.machine_units() ? cmd_jog_machine(c) : run_steps(c); }

}  // namespace

const subcommand &jog_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "jog";
    c.usage = {"[OPTIONS] AXIS +|-", "[--machine FILE] [--feed F] [--distance D] LETTER+|LETTER-"};
    c.synopsis = "AXIS +|-";
    c.summary =
        "endless move of one axis until braked; 'jog X+' (a\n"
        "letter): an axis of a machine file, in its units";
    c.prose =
        "Move AXIS (1..4) endlessly in the positive (+) or negative (-) direction\n"
        "(X4MovePos, X4MoveNeg) until it is braked: by ESC or a brake key on the\n"
        "console keyboard, by 'x4ctl brake' or 'x4ctl stop', or after --time.\n"
        "\n"
        "With an axis letter and a sign (X+, Z-), the axis of a machine file\n"
        "(machines/README.md) moves in its units, in machine coordinates: by the\n"
        "distance D, ending exactly at round(position x SCALE) steps (a target\n"
        "beyond a soft limit is refused, nothing moves, unless the axis stands\n"
        "beyond that limit already and the jog goes back toward the range); without\n"
        "it toward its soft limit (MAX_LIMIT for +, MIN_LIMIT for -) until any key,\n"
        "Ctrl-C or 'x4ctl brake' brakes it, or it stops there. Soft limits apply\n"
        "whether the axis is homed or not. At --feed, ramps at the axis'\n"
        "MAX_ACCELERATION (the axis' own move: 'x4ctl profile' is put back\n"
        "afterwards). Where the axis ends is also given in work coordinates when\n"
        "the parameter file has an offset for it ('x4ctl touch-off').\n";
    c.options = {
        freq_option(),
        ramp_option(),
        time_option("brake after MS milliseconds"),
        wait_option("stay until the move ends, showing the steps; Ctrl-C\n"
                    "brakes, a second Ctrl-C stops"),
        machine_option("the machine file of LETTER+|- (default: $X4STEP_MACHINE,\n"
                       "else /etc/x4step/machine.ini); its PORT is the port"),
        feed_option("units/min (degrees for A B C); at most MAX_VELOCITY\n"
                    "(default: a quarter of it)"),
        {"distance", 0, "D", "jog by D units (> 0) in the sign's direction",
         [](parse_state &s, const option_value &o) {
           s.c.distance = parse_positive(o.value, "distance", " units", s.prefix);
         }},
    };
    c.epilogue =
        "Without --wait, x4ctl returns once the motors run, and a background x4ctl\n"
        "holds the port until the move ends (the module brakes a move whose program\n"
        "exits). 'x4ctl brake', 'x4ctl stop' or ESC on the console keyboard end it\n"
        "early; 'x4ctl monitor' follows it.\n"
        "\n"
        "Exit status: 0 the axis ran (and, with --wait, was braked; LETTER+|-: the jog\n"
        "ended or was braked); 1 the port refused, a --distance jog was braked, or a\n"
        "continuous one stood at its soft limit already; 2 bad usage or machine file,\n"
        "or a target beyond a soft limit (nothing moved).\n"
        "Examples: x4ctl jog 1 + --time 2000\n"
        "          x4ctl jog X+ --machine machines/smc1500-mill.ini --distance 0.5\n"
        "          x4ctl jog Z- --machine machines/smc1500-mill.ini --feed 60\n";
    c.operands = operands;
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
