// SPDX-License-Identifier: GPL-2.0
// x4ctl watch: the port's events as they happen, read-only.
#include <cstdint>
#include <iostream>
#include <optional>

#include "commands.hpp"
#include "json.hpp"
#include "motion.hpp"
#include "options.hpp"
#include "show.hpp"
#include "subcommand.hpp"
#include "term.hpp"
#include "values.hpp"

namespace x4ctl {
namespace {

// The port's events, one line each, until Ctrl-C or --count of them.
int run(const config &c) {
  refuse_sim(device_of(c), "watch");
  const x4step::monitor mon = open_monitor(device_of(c));
  std::uint64_t next = 0;  // the seq expected next; 0: any
  long seen = 0;
  while (take_signal() == key::none) {
    std::optional<x4step::event> e;
    try {
      e = mon.read_event(tick);
    } catch (const x4step::error &err) {
      if (err.code() != x4step::errc::lpt_not_found) throw;
      throw failure(device_of(c) + ": the port went away");
    }
    if (!e) continue;
    if (next && e->seq > next)
      std::cout << (c.json ? missed_json(e->seq - next) : missed_text(e->seq - next)) << "\n";
    next = e->seq + 1;
    std::cout << (c.json ? event_json(*e) : event_text(*e)) << "\n" << std::flush;
    if (c.count && ++seen >= *c.count) return 0;
    if (e->type == x4step::event_type::port_gone) throw failure(device_of(c) + ": the port went away");
  }
  return 0;
}

}  // namespace

const subcommand &watch_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "watch";
    c.usage = {"[OPTIONS]"};
    c.summary = "print the port's events as they happen, read-only";
    c.prose =
        "Print the events of the port as the module reports them, one line each,\n"
        "until Ctrl-C (read-only): moves started (and their kind) and ended (completed,\n"
        "braked, stopped, at a limit, homed, ...), brake requests and who made them\n"
        "(a program, a brake key and its code, a controller's close), limit and\n"
        "reference switches hit, controllers opening and closing, the port going\n"
        "away. Each line starts with the event's number and its CLOCK_MONOTONIC\n"
        "time in seconds. The module keeps the last 256 events: events a slow reader\n"
        "missed show as 'missed N events'.\n";
    c.options = {
        json_option("one JSON object per line instead of text"),
        {"count", 'n', "N", "end after N events",
         [](parse_state &s, const option_value &o) {
           const long n = parse_number(o.value, s.prefix + "count");
           if (n < 1) throw usage_error(s.prefix + "count " + o.value + " out of range: use 1 or more");
           s.c.count = n;
         }},
    };
    c.epilogue = "Exit status: 0 at Ctrl-C or after N events; 1 the port is missing or went away.\n";
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
