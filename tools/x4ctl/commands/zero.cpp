// SPDX-License-Identifier: GPL-2.0
// x4ctl zero: stop and zero axes (position.cpp).
#include "commands.hpp"
#include "position.hpp"
#include "subcommand.hpp"
#include "values.hpp"

namespace x4ctl {
namespace {

void operands(parse_state &s, const std::vector<std::string> &ops) {
  need_operands(ops, 1, x4step::axes, s.prefix);
  s.c.axes = parse_axes(ops, s.prefix);
}

int run(const config &c) { return with_port(c, zero_command, true); }

}  // namespace

const subcommand &zero_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "zero";
    c.usage = {"[OPTIONS] AXIS..."};
    c.synopsis = "AXIS...";
    c.summary = "stop the axes and set their coordinates (stop and zero)";
    c.prose =
        "Stop and zero (ProStep4 command bit 5): stop the axes at once if they move\n"
        "(with the axes moving interpolated with them), set their coordinates to 0, or\n"
        "to --at, and mark them synchronized.\n";
    c.options = {
        {"at", 0, "POSITION",
         "the coordinate to set, -2147483648..2147483647\n"
         "(default 0)",
         [](parse_state &s, const option_value &o) {
           s.c.at = parse_position(o.value, "position", s.prefix);
         }},
    };
    c.epilogue =
        "Exit status: 0 done; 1 the port refused, or another program holds it;\n"
        "2 bad usage.\n";
    c.operands = operands;
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
