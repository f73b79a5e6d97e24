// SPDX-License-Identifier: GPL-2.0
// x4ctl mode: how the port drives its motors.
#include <iostream>

#include "commands.hpp"
#include "json.hpp"
#include "options.hpp"
#include "show.hpp"
#include "subcommand.hpp"
#include "values.hpp"

namespace x4ctl {

void mode_command(port &p, const config &c, std::ostream &out) {
  x4step::config k = p.get_config();
  if (c.mode) {
    k.mode(*c.mode);  // the inversions and key settings stay
    p.set_config(k);
    k = p.get_config();
  }
  out << (c.json ? mode_json(k.mode(), device_of(c)) : mode_text(k.mode())) << "\n";
}

namespace {
void operands(parse_state &s, const std::vector<std::string> &ops) {
  need_operands(ops, 0, 1, s.prefix);
  if (!ops.empty()) s.c.mode = parse_mode(ops[0], s.prefix);
}

int run(const config &c) { return with_port(c, mode_command, c.mode.has_value()); }

}  // namespace

const subcommand &mode_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "mode";
    c.usage = {"[OPTIONS] [clock-dir|smc-phase|smc-hold]"};
    c.synopsis = "[MODE]";
    c.summary =
        "show or set the output mode: clock-dir, or smc-phase and\n"
        "smc-hold for SMC800/SMC1500 boards";
    c.prose =
        "Show or set how the port drives its motors. The module keeps the mode for\n"
        "the port after x4ctl exits, until it is set again.\n"
        "  clock-dir   a clock and a direction signal per axis (X4Step, the default;\n"
        "              step-dir is taken for it too, as in machine files)\n"
        "  smc-phase   half-step phase patterns for SMC800/SMC1500 boards, which have\n"
        "              no clock and direction inputs; motors off at rest\n"
        "  smc-hold    the same, with reduced holding current at rest\n"
        "The SMC boards drive three motors: in smc-phase and smc-hold, moves of axis 4\n"
        "are refused, and the pulse and space of 'x4ctl timing' do not apply.\n";
    c.options = {
        json_option("one JSON object instead of text"),
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
