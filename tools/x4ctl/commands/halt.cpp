// SPDX-License-Identifier: GPL-2.0
// x4ctl halt: brake or stop the moves of some axes.
#include <iostream>

#include "commands.hpp"
#include "motion.hpp"
#include "position.hpp"
#include "show.hpp"
#include "subcommand.hpp"
#include "term.hpp"
#include "values.hpp"

namespace x4ctl {
namespace {

void operands(parse_state &s, const std::vector<std::string> &ops) {
  need_operands(ops, 1, x4step::axes, s.prefix);
  s.c.axes = parse_axes(ops, s.prefix);
}

int run(const config &c) {
  const std::string dev = device_of(c);
  refuse_sim(dev, "halt");
  const x4step::monitor mon = open_monitor(dev);
  const x4step::axes_status a = mon.get_axes();
  bool running = false;
  std::string named;
  for (x4step::axis ax : c.axes) {
    running |= a[ax].running;
    named += (named.empty() ? "" : ", ") + std::to_string(ax.number());
  }
  if (!running)
    throw failure((named.size() == 1 ? "axis " + named + " is" : "axes " + named + " are") + " not moving");
  ask_holder(dev, c.halt_stop, c.axes);
  // An axis' own ramp may be long: wait for it, until Ctrl-C.
  while (!mon.wait_axes(c.axes, tick))
    if (quit_requested()) throw failure("gave up waiting: the axes still move");
  std::cout << (c.halt_stop ? "stopped: " : "braked: ") << positions_text(mon.get_axes(), c.axes) << "\n";
  return 0;
}

}  // namespace

const subcommand &halt_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "halt";
    c.usage = {"[OPTIONS] AXIS..."};
    c.synopsis = "AXIS...";
    c.summary = "brake (or stop) the moves of some axes";
    c.prose =
        "Brake the moves of the axes along their ramps, or with --stop stop them at\n"
        "once (they lose their synchronization); the axes moving interpolated with\n"
        "them halt too, other axes go on. The moves belong to the x4ctl that started\n"
        "them ('goto --no-wait', 'move' in the background, ...): it is asked to halt\n"
        "them, and this command waits until they stand and shows their coordinates.\n";
    c.options = {
        {"stop", 's', "", "stop at once rather than brake",
         [](parse_state &s, const option_value &) { s.c.halt_stop = true; }},
    };
    c.epilogue =
        "Exit status: 0 done; 1 none of the axes moves, or another program holds the\n"
        "port; 2 bad usage.\n";
    c.operands = operands;
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
