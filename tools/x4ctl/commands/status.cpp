// SPDX-License-Identifier: GPL-2.0
// x4ctl status: the state of the port, read-only.
#include <iostream>

#include "commands.hpp"
#include "json.hpp"
#include "options.hpp"
#include "show.hpp"
#include "sim.hpp"
#include "subcommand.hpp"

namespace x4ctl {
namespace {

int run(const config &c) {
  const std::string dev = device_of(c);
  const x4step::monitor mon = open_monitor(dev);
  const x4step::status s = mon.get_status();
  const x4step::axes_status a = mon.get_axes();
  std::cout << (c.json ? status_json(s, a, dev) + "\n" : status_text(s, a, dev));
  if (is_sim_device(dev) && !c.json && sim_state_file().empty())
    std::cerr << "x4ctl: note: " << dev
              << " is a simulated port of this x4ctl alone: a fresh one, not that of another x4ctl --sim\n";
  else if (is_sim_device(dev) && !c.json)
    std::cerr << "x4ctl: note: " << dev << " is a simulated port of this x4ctl alone: the coordinates and "
              << "synchronization are those X4STEP_SIM_STATE=" << sim_state_file()
              << " kept, the rest is fresh\n";
  return 0;
}

}  // namespace

const subcommand &status_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "status";
    c.usage = {"[OPTIONS]"};
    c.summary = "show the state of the port";
    c.prose =
        "Show the state of the port, read-only (also while another program moves the\n"
        "motors): running, loaded, controlled, the steps of the last move, inputs,\n"
        "outputs, the key that braked the last move, the number of moves ended; and\n"
        "per axis its coordinate, whether it is synchronized (referenced by 'home' or\n"
        "'zero'), its state and its errors (a limit switch hit, reference travel\n"
        "exceeded). 'x4ctl limits' shows the switches.\n";
    c.options = {
        json_option("one JSON object instead of text"),
    };
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
