// SPDX-License-Identifier: GPL-2.0
// x4ctl list: the ports, their module's version, who holds them.
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <iostream>

#include "commands.hpp"
#include "holder.hpp"
#include "json.hpp"
#include "options.hpp"
#include "ports.hpp"
#include "show.hpp"
#include "sim.hpp"
#include "subcommand.hpp"

namespace x4ctl {
namespace {

// The simulated ports: in this library, a fresh one in each program.
int list_sim(const config &c) {
  std::vector<port_entry> ports;
  for (int n = 0; n < 4; n++) {
    port_entry p;
    p.device = "sim:" + std::to_string(n);
    p.parport = n;
    p.simulated = true;
    try {
      p.abi = open_monitor(p.device).abi_version();
    } catch (const failure &e) {
      p.error = e.what();
      p.err = e.err();
    }
    ports.push_back(p);
  }
  std::cout << (c.json ? list_json(ports) + "\n" : list_text(ports));
  return 0;
}

// Every port: its module's version and who holds it.
int run(const config &c) {
  if (is_sim_device(device_of(c))) return list_sim(c);
  std::vector<port_entry> ports;
  for (const std::string &dev : x4step_devices()) {
    port_entry p;
    p.device = dev;
    p.parport = std::atoi(dev.c_str() + std::strlen("/dev/x4step"));
    p.claimant = parport_claimant(p.parport);
    try {
      const x4step::monitor mon = open_monitor(dev);
      p.abi = mon.abi_version();
      p.controlled = mon.get_status().controlled;
      if (p.controlled) p.controller = find_controller(dev);
    } catch (const failure &e) {
      p.error = e.what();
      p.err = e.err();
    }
    ports.push_back(p);
  }
  if (ports.empty())
    throw failure(
        "no /dev/x4stepN: load the module ('sudo modprobe x4step'; a parallel port and parport_pc needed)",
        ENOENT);
  std::cout << (c.json ? list_json(ports) + "\n" : list_text(ports));
  return 0;
}

}  // namespace

const subcommand &list_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "list";
    c.usage = {"[OPTIONS]"};
    c.summary = "the ports, their module's version, who holds them";
    c.prose =
        "List the ports x4step serves (/dev/x4stepN for parportN), read-only: the\n"
        "interface (ABI) version of the module, and who holds each port: a\n"
        "controller (its PID and name, where this user may see its process), another\n"
        "parport driver that has claimed it (lp, or ppdevN for a program using\n"
        "/dev/parportN), or nobody. The first line is the library's version.\n"
        "With --sim (or X4STEP_SIM=1): the simulated ports sim:0..3 instead, which\n"
        "live in the program that opens them (a fresh one in each).\n";
    c.options = {
        {"port", 'p', "LPT", "", common_option("port").apply},
        {"device", 'd', "PATH", "", common_option("device").apply},
        json_option("one JSON object instead of text"),
        {"sim", 0, "", "the simulated ports", common_option("sim").apply},
    };
    c.epilogue =
        "JSON, of every command with --json: each object (one per line) starts with\n"
        "\"schema\":1, the version of this format, raised when a field changes or goes\n"
        "(new fields keep it); yes/no values and pin levels (true: HIGH) are JSON\n"
        "booleans. An error is such an object too, on standard output:\n"
        "{\"schema\":1,\"error\":{\"message\":\"...\",\"errno\":13}} (errno null when none\n"
        "applies); the exit status is the same as without --json.\n"
        "\n"
        "Exit status: 0 done; 1 no port (is x4step loaded?).\n";
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
