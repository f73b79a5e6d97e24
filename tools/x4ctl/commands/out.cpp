// SPDX-License-Identifier: GPL-2.0
// x4ctl out: an output signal held high or low.
#include <algorithm>
#include <iostream>

#include "commands.hpp"
#include "holder.hpp"
#include "motion.hpp"
#include "options.hpp"
#include "subcommand.hpp"
#include "term.hpp"

namespace x4ctl {
namespace {

void operands(parse_state &s, const std::vector<std::string> &ops) {
  config &c = s.c;
  const std::string &prefix = s.prefix;
  need_operands(ops, 2, 2, prefix);
  const long sig = parse_number(ops[0], prefix + "signal");
  if (sig != 1 && sig != 2) throw usage_error(prefix + "signal " + ops[0] + ": use 1 (pin 1) or 2 (pin 14)");
  c.signal = sig == 1 ? x4step::signal::one : x4step::signal::two;
  const std::string &v = ops[1];
  if (v == "on" || v == "1" || v == "high")
    c.level = true;
  else if (v == "off" || v == "0" || v == "low")
    c.level = false;
  else
    throw usage_error(prefix + "level '" + v + "': use on or off");
}

int run(const config &c) {
  controller_port p(open_controller(device_of(c)));
  std_console con(false);
  p.set_output(c.signal, c.level);
  std::cout << "signal " << (c.signal == x4step::signal::one ? "1 (pin 1) " : "2 (pin 14) ")
            << (c.level ? "on" : "off") << "; holding the port "
            << (c.time ? "for " + std::to_string(c.time->count()) + " ms" : std::string("until Ctrl-C"))
            << "\n"
            << std::flush;
  // On the port's clock: a simulated port in virtual time holds the level
  // for --time of its own time at once; without --time, as the wall clock.
  const deadline until = deadline_of(c, p);
  for (auto now = p.now(); !(until && now >= *until); now = p.now()) {
    const milliseconds step =
        until ? std::min(std::chrono::ceil<milliseconds>(*until - now), milliseconds(50)) : milliseconds(50);
    if (pause(p, con, step, !until) != key::none) break;
  }
  std::cout << "released the port: the module drives the outputs low\n";
  return 0;
}

}  // namespace

const subcommand &out_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "out";
    c.usage = {"[OPTIONS] SIGNAL on|off"};
    c.synopsis = "SIGNAL on|off";
    c.summary = "set output signal 1 (pin 1) or 2 (pin 14)";
    c.prose =
        "Set output signal 1 (pin 1) or 2 (pin 14) high (on) or low (off) (X4SetOut).\n"
        "The module drives every output low when its controller lets go of the port,\n"
        "so x4ctl holds the port, and the level, until Ctrl-C or SIGTERM, or for\n"
        "--time; no move can run meanwhile. To switch outputs around moves, use the\n"
        "O command in 'x4ctl run'.\n";
    c.options = {
        time_option("let go of the port after MS milliseconds"),
    };
    c.operands = operands;
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
