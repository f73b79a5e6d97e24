// SPDX-License-Identifier: GPL-2.0
// x4ctl monitor: the moves on the port, followed read-only.
#include <cstdint>
#include <iostream>

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

int run(const config &c) {
  refuse_sim(device_of(c), "monitor");
  const x4step::monitor mon = open_monitor(device_of(c));
  std_console con(false);
  x4step::status s = mon.get_status();
  std::uint64_t seen = s.moves_ended;
  bool was_active = s.active;
  long ended = 0;
  const bool live = con.live() && !c.json;
  std::cout << (c.json     ? monitor_json(s.active ? "running" : "idle", s) + "\n"
                : s.active ? "move running\n"
                           : "idle, waiting for moves\n")
            << std::flush;
  while (take_signal() == key::none) {
    s = mon.get_status();
    if (s.active && !was_active)
      std::cout << (c.json ? monitor_json("started", s)
                           : std::string(live ? "\r\x1b[K" : "") + "move started")
                << "\n"
                << std::flush;
    if (s.moves_ended != seen) {
      if (live) draw_live(con, "");
      if (c.json)
        std::cout << monitor_json("ended", s) << "\n" << std::flush;
      else
        std::cout << "move ended: steps " << steps_text(s.steps)
                  << (s.last_brake_code ? ", braked by " + key_name(s.last_brake_code) : "") << "\n"
                  << std::flush;
      ended += static_cast<long>(s.moves_ended - seen);
      seen = s.moves_ended;
      if (c.moves && ended >= *c.moves) return 0;
    }
    if (s.active && live) draw_live(con, "steps " + steps_text(s.steps));
    was_active = s.active;
    if (s.active)
      mon.wait(tick);  // returns at the move's end
    else
      nap(milliseconds(20));
  }
  if (live) std::cout << "\n";
  return 0;
}

}  // namespace

const subcommand &monitor_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "monitor";
    c.usage = {"[OPTIONS]"};
    c.summary = "follow the moves on the port, read-only";
    c.prose =
        "Follow the moves on the port without disturbing the program that controls\n"
        "it (read-only): a line when a move starts and when it ends, with the steps\n"
        "of the four axes; on a terminal the steps count live. Ends with Ctrl-C.\n";
    c.options = {
        {"moves", 'n', "N", "end after N moves have ended",
         [](parse_state &s, const option_value &o) {
           const long n = parse_number(o.value, s.prefix + "moves");
           if (n < 1) throw usage_error(s.prefix + "moves " + o.value + " out of range: use 1 or more");
           s.c.moves = n;
         }},
        json_option("one JSON object per line: idle, running, started, ended"),
    };
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
