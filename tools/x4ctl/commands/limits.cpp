// SPDX-License-Identifier: GPL-2.0
// x4ctl limits: the reference and limit switch inputs (position.cpp).
#include "commands.hpp"
#include "options.hpp"
#include "position.hpp"
#include "subcommand.hpp"
#include "values.hpp"

namespace x4ctl {
namespace {

void operands(parse_state &s, const std::vector<std::string> &ops) {
  config &c = s.c;
  need_operands(ops, 0, 1, s.prefix);
  if (!ops.empty()) {
    c.axis = parse_axis(ops[0], s.prefix);
    c.axes = c.axis;
  }
  if (ops.empty() && (c.ref || c.plus || c.minus))
    throw usage_error(s.prefix + "--ref, --plus and --minus need an AXIS, e.g. 'x4ctl limits 1 --ref 3'");
}

int run(const config &c) { return with_port(c, limits_command, c.ref || c.plus || c.minus || c.nc); }

}  // namespace

const subcommand &limits_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "limits";
    c.usage = {"[OPTIONS] [AXIS]"};
    c.summary = "show or set the reference and limit switch inputs";
    c.prose =
        "Show which inputs are the reference and limit switches of each axis, and\n"
        "the state of the five inputs; or name the switch inputs of AXIS, or the\n"
        "normally closed inputs, and show the result. Inputs 1..5 are pins 15, 13,\n"
        "12, 10 and 11 (X4GetIn bits 0..4); 0 or 'none': no switch. An input may\n"
        "serve several axes and both directions (switches in parallel, as on the\n"
        "SMC1500): a hit is then given to the axis that moved toward it, and flagged\n"
        "ambiguous if more than one did. An axis moving toward an active limit is\n"
        "stopped by the module on that very step; moving away from it is allowed.\n"
        "The module keeps the settings after x4ctl exits. Only while nothing moves.\n";
    c.options = {
        {"ref", 0, "INPUT", "reference switch of AXIS (for 'home')",
         [](parse_state &s, const option_value &o) { s.c.ref = parse_input(o.value, s.prefix); }},
        {"plus", 0, "INPUT", "limit switch E+ of AXIS (end of the positive travel)",
         [](parse_state &s, const option_value &o) { s.c.plus = parse_input(o.value, s.prefix); }},
        {"minus", 0, "INPUT", "limit switch E- of AXIS",
         [](parse_state &s, const option_value &o) { s.c.minus = parse_input(o.value, s.prefix); }},
        {"nc", 0, "INPUTS",
         "the normally closed inputs (active while LOW): a list\n"
         "like 1,3, a mask like 0x05, or none; the others are\n"
         "normally open (active while HIGH)",
         [](parse_state &s, const option_value &o) { s.c.nc = parse_nc(o.value, s.prefix); }},
        json_option("one JSON object instead of text"),
    };
    c.epilogue =
        "Exit status: 0 done; 1 the port refused (a move runs), or another program\n"
        "holds it; 2 bad usage.\n"
        "Example: x4ctl limits 1 --ref 3 --plus 1 --minus 2 --nc 1,2\n";
    c.operands = operands;
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
