// SPDX-License-Identifier: GPL-2.0
// x4ctl goto: axes on their own to coordinates (position.cpp).
#include <iostream>

#include "commands.hpp"
#include "holder.hpp"
#include "motion.hpp"
#include "position.hpp"
#include "subcommand.hpp"
#include "term.hpp"
#include "values.hpp"

namespace x4ctl {
namespace {

void operands(parse_state &s, const std::vector<std::string> &ops) {
  config &c = s.c;
  const std::string &prefix = s.prefix;
  need_operands(ops, 1, x4step::axes, prefix);
  const std::string what = c.relative ? "distance" : "position";
  std::vector<std::string> names;  // AXIS of each AXIS=VALUE
  for (const auto &o : ops) {
    const size_t eq = o.find('=');
    if (eq == std::string::npos)
      throw usage_error(prefix + "'" + o + "': use AXIS=" + (c.relative ? "DISTANCE" : "POSITION") +
                        ", e.g. 1=1000");
    names.push_back(o.substr(0, eq));
  }
  c.axes = parse_axes(names, prefix);
  for (size_t i = 0; i < ops.size(); i++)
    c.targets[parse_axis(names[i], prefix).index()] =
        parse_position(ops[i].substr(names[i].size() + 1), what, prefix);
}

int run(const config &c) {
  controller_port p(open_controller(device_of(c)));
  std_console con(!c.no_wait);
  const coordinates want = start_goto_command(p, c, std::cout);
  if (c.no_wait) {
    hold_in_background(p, [&](console &bg) { follow_axes(p, bg, c.axes); });
    return 0;  // the background process, after the moves
  }
  finish_goto_command(p, con, c, want, std::cout);
  return 0;
}

}  // namespace

const subcommand &goto_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "goto";
    c.usage = {"[OPTIONS] AXIS=POSITION [AXIS=POSITION...]"};
    c.synopsis = "AXIS=POS...";
    c.summary = "move axes on their own to coordinates";
    c.prose =
        "Move each axis named on its own, with its profile ('x4ctl profile'), to the\n"
        "machine coordinate POSITION (-2147483648..2147483647); all start at once, each\n"
        "ends at its own time. Waits until they end and shows the coordinates of the\n"
        "four axes. An axis moving toward an active limit switch is stopped there by\n"
        "the module. ESC or Ctrl-C brakes, a second Ctrl-C stops.\n";
    c.options = {
        {"relative", 0, "", "the numbers are distances from where the axes are",
         [](parse_state &s, const option_value &) { s.c.relative = true; }},
        {"no-wait", 0, "",
         "return once the axes run: a background x4ctl holds the\n"
         "port until they end (the module brakes the moves of a\n"
         "program that exits); 'x4ctl halt' or 'x4ctl brake'\n"
         "ends them early",
         [](parse_state &s, const option_value &) { s.c.no_wait = true; }},
    };
    c.epilogue =
        "Exit status: 0 every axis reached its target (without waiting: they run);\n"
        "1 the port refused, or an axis was halted or stopped at a limit switch;\n"
        "2 bad usage (nothing moved).\n"
        "Examples: x4ctl goto 1=12000 2=-500\n"
        "          x4ctl goto 3=100 --relative\n";
    c.operands = operands;
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
