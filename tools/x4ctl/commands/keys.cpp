// SPDX-License-Identifier: GPL-2.0
// x4ctl keys: the keys that brake a move.
#include <iostream>

#include "commands.hpp"
#include "holder.hpp"
#include "subcommand.hpp"

namespace x4ctl {
namespace {

void operands(parse_state &s, const std::vector<std::string> &ops) {
  const std::string &prefix = s.prefix;
  need_operands(ops, 0, 20, prefix);
  for (const auto &o : ops) {
    const long k = parse_number(o, prefix + "key code");
    if (k < 1 || k > 255 || k == 128)
      throw usage_error(prefix + "key code " + o + " out of range: use 1..127 (press) or 129..255 (release)");
    s.c.codes.push_back(static_cast<int>(k));
  }
}

int run(const config &c) {
  controller_port p(open_controller(device_of(c)));
  note_sim_setting(device_of(c));
  p.set_brake_codes(c.codes);
  std::string list;
  for (int k : c.codes) list += " " + std::to_string(k);
  std::cout << (c.codes.empty() ? "brake keys: ESC only\n" : "brake keys:" + list + " and ESC\n");
  return 0;
}

}  // namespace

const subcommand &keys_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "keys";
    c.usage = {"[OPTIONS] [CODE...]"};
    c.synopsis = "[CODE...]";
    c.summary = "set the keys that brake a move (ESC always does)";
    c.prose =
        "Set up to 20 keys that brake a running move (X4BrakeCodes), as PC/AT set-1\n"
        "scan codes: CODE (1..127) brakes when the key is pressed, CODE+128 when it\n"
        "is released; e.g. 28 Enter, 57 Space, 72/75/77/80 the cursor keys. ESC (1)\n"
        "always brakes; without codes only ESC does. The module keeps the codes\n"
        "after x4ctl exits, until they are set again.\n";
    c.epilogue = "Example: x4ctl keys 28 156   (Enter pressed or released)\n";
    c.operands = operands;
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
