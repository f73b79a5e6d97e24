// SPDX-License-Identifier: GPL-2.0
// x4ctl help: the help of a command.
#include <iostream>

#include "commands.hpp"
#include "subcommand.hpp"

namespace x4ctl {
namespace {

void operands(parse_state &s, const std::vector<std::string> &ops) {
  need_operands(ops, 0, 1, s.prefix);
  if (!ops.empty()) {
    const subcommand *t = find_command(ops[0]);
    if (!t) throw usage_error(s.prefix + "no command '" + ops[0] + "'");
    s.c.topic = t;
  }
}

int run(const config &c) {
  std::cout << help_text(*c.topic);
  return 0;
}

}  // namespace

const subcommand &help_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "help";
    c.synopsis = "[COMMAND]";
    c.summary = "show the help of a command";
    c.operands = operands;
    c.run = run;
    c.overview = true;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
