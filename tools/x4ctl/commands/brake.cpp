// SPDX-License-Identifier: GPL-2.0
// x4ctl brake and stop: the module's emergency halt of the running move.
#include <iostream>

#include "commands.hpp"
#include "holder.hpp"
#include "show.hpp"
#include "subcommand.hpp"
#include "term.hpp"

namespace x4ctl {
namespace {

int run(const config &c) { return halt_moves(c, false); }

}  // namespace

const subcommand &brake_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "brake";
    c.usage = {"[OPTIONS]"};
    c.summary = "brake the running move along its ramp";
    c.prose =
        "Brake the running move along its ramp (X4Brake).\n"
        "It reaches every move on the port, whichever program controls it (an x4ctl\n"
        "in the background or in another shell, any other program, or the module\n"
        "braking the moves of a program that exited): the module's emergency halt\n"
        "is allowed to anyone who may read the port (group lp). The event stream\n"
        "('x4ctl watch') shows it as an emergency brake. Waits until the motors stand and\n"
        "shows the steps made.\n";
    c.epilogue = "Exit status: 0 done; 1 no move was running, or the port is missing.\n";
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
