// SPDX-License-Identifier: GPL-2.0
// x4ctl in: the five inputs.
#include <iostream>
#include <optional>
#include <utility>

#include "commands.hpp"
#include "json.hpp"
#include "motion.hpp"
#include "options.hpp"
#include "show.hpp"
#include "sim.hpp"
#include "subcommand.hpp"
#include "term.hpp"
#include "values.hpp"

namespace x4ctl {
namespace {

// The inputs as `x4ctl in` shows them. The module reads the port only
// while it has claimed it: through another program's controller when there
// is one, else x4ctl takes the port (kept until it ends), unless read_only.
class input_reader {
 public:
  input_reader(std::string dev, bool read_only)
      : dev_(std::move(dev)), read_only_(read_only), mon_(open_monitor(dev_)) {}

  // A wait between two reads (paced as the wall clock: only Ctrl-C ends
  // the watch); a simulated port in virtual time passes it too.
  void pause(milliseconds d) {
    nap(d);
    if (ctl_ && !ctl_->clock_runs()) ctl_->sleep_for(d);
  }

  x4step::status read() {
    if (ctl_) return ctl_->get_status();
    const x4step::status s = mon_.get_status();
    if (!s.inputs_stale || read_only_) return s;
    try {
      ctl_.emplace(dev_);
    } catch (const x4step::error &) {
      return s;  // another driver (or a controller that just opened) has it
    }
    return ctl_->get_status();
  }

 private:
  std::string dev_;
  bool read_only_;
  x4step::monitor mon_;
  std::optional<x4step::controller> ctl_;
};

int run(const config &c) {
  input_reader in(device_of(c), c.read_only);
  auto line = [&] {
    const x4step::status s = in.read();
    const auto now = std::chrono::steady_clock::now();
    if (c.json) return inputs_json(s, device_of(c), now);
    return inputs_text(s.inputs) + " (" + std::to_string(s.inputs) + ")" +
           (s.inputs_stale ? " " + stale_text(s, now) : "");
  };
  if (!c.watch) {
    std::cout << line() << "\n";
    return 0;
  }
  std_console con(false);
  std::string last;
  while (take_signal() == key::none) {  // until Ctrl-C
    const std::string now = line();
    if (con.live() && !c.json)
      draw_live(con, now);
    else if (now != last)
      std::cout << now << "\n" << std::flush;
    last = now;
    in.pause(milliseconds(100));
  }
  if (con.live()) std::cout << "\n";
  return 0;
}

}  // namespace

const subcommand &in_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "in";
    c.usage = {"[OPTIONS]"};
    c.summary = "show the five inputs";
    c.prose =
        "Show the levels of the five inputs (X4GetIn), 1 = HIGH: pins 15, 13, 12, 10\n"
        "and 11 are bits 0..4 of the value. The module reads the port only while it\n"
        "has claimed it, for a controller: while another program controls the port\n"
        "they are read through its claim; while none does, x4ctl takes the port for\n"
        "as long as it runs (as 'x4ctl out' does). When another driver (lp, ppdev)\n"
        "holds the port, or with --read-only, the levels shown are the last ones read,\n"
        "marked 'stale' with their age.\n";
    c.options = {
        {"watch", 'w', "", "show them continuously until Ctrl-C",
         [](parse_state &s, const option_value &) { s.c.watch = true; }},
        {"read-only", 'r', "", "never take the port (stale levels if nobody controls it)",
         [](parse_state &s, const option_value &) { s.c.read_only = true; }},
        json_option("JSON instead of text (one object per line with --watch)"),
    };
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
