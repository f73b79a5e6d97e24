// SPDX-License-Identifier: GPL-2.0
// x4ctl stop: the module's emergency stop of the running move.
#include "commands.hpp"
#include "subcommand.hpp"

namespace x4ctl {
namespace {

int run(const config &c) { return halt_moves(c, true); }

}  // namespace

const subcommand &stop_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "stop";
    c.usage = {"[OPTIONS]"};
    c.summary = "stop the running move at once (emergency stop)";
    c.prose =
        "Stop the running move at once, without ramp (X4Stop): an emergency stop,\n"
        "the motors may lose steps.\n"
        "It reaches every move on the port, whichever program controls it (an x4ctl\n"
        "in the background or in another shell, any other program, or the module\n"
        "braking the moves of a program that exited): the module's emergency halt\n"
        "is allowed to anyone who may read the port (group lp). The event stream\n"
        "('x4ctl watch') shows it as an emergency stop. Waits until the motors stand and\n"
        "shows the steps made.\n";
    c.epilogue = "Exit status: 0 done; 1 no move was running, or the port is missing.\n";
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
