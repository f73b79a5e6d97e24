// SPDX-License-Identifier: GPL-2.0
// x4ctl timing: the step signal timing of the port.
#include <iostream>

#include "commands.hpp"
#include "json.hpp"
#include "options.hpp"
#include "show.hpp"
#include "subcommand.hpp"
#include "values.hpp"

namespace x4ctl {

void timing_command(port &p, const config &c, std::ostream &out) {
  x4step::step_timing t = p.get_step_timing();
  if (c.pulse || c.space || c.dir_setup || c.dir_hold) {
    if (c.pulse) t.pulse(*c.pulse);
    if (c.space) t.space(*c.space);
    if (c.dir_setup) t.dir_setup(*c.dir_setup);
    if (c.dir_hold) t.dir_hold(*c.dir_hold);
    p.set_step_timing(t);
    t = p.get_step_timing();  // what the port took
  }
  const x4step::output_mode m = p.get_config().mode();
  const std::string dev = device_of(c);
  out << (c.json ? timing_json(t, m, dev) + "\n" : timing_text(t, m, dev));
}

namespace {
int run(const config &c) {
  return with_port(c, timing_command, c.pulse || c.space || c.dir_setup || c.dir_hold);
}

}  // namespace

const subcommand &timing_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    const std::string max = std::to_string(x4step::timing_max.count());
    c.name = "timing";
    c.usage = {"[OPTIONS]"};
    c.summary = "show or set the step signal timing (pulse, space, ...)";
    c.prose =
        "Show the step signal timing of the port, or change the times given (the\n"
        "others stay) and show the result. The module keeps the timing for the port\n"
        "after x4ctl exits, until it is set again. Every time is a minimum, in ns.\n";
    c.options = {
        {"pulse", 0, "NS",
         "clock high time: 0 (symmetric clock, half a period high,\n"
         "as X4Step does) or " +
             std::to_string(x4step::pulse_min.count()) + ".." + max + " ns",
         [](parse_state &s, const option_value &o) {
           s.c.pulse = parse_ns(o.value, "pulse", true, s.prefix);
         }},
        {"space", 0, "NS", "minimum clock low time, 0.." + max + " ns",
         [](parse_state &s, const option_value &o) {
           s.c.space = parse_ns(o.value, "space", false, s.prefix);
         }},
        {"setup", 0, "NS",
         "directions out before the first step, 0.." + max +
             " ns\n"
             "(X4Step: 100000)",
         [](parse_state &s, const option_value &o) {
           s.c.dir_setup = parse_ns(o.value, "setup", false, s.prefix);
         }},
        {"hold", 0, "NS", "directions kept after the last step, 0.." + max + " ns",
         [](parse_state &s, const option_value &o) {
           s.c.dir_hold = parse_ns(o.value, "hold", false, s.prefix);
         }},
        json_option("one JSON object instead of text"),
    };
    c.epilogue =
        "A move or jog whose frequency leaves no room for pulse + space (with the\n"
        "symmetric clock: for space in half a period) is refused later by the module\n"
        "with \"frequency too high\"; 'max freq' shows the limit. In the smc-phase and\n"
        "smc-hold modes (see 'x4ctl mode') pulse and space do not apply.\n"
        "\n"
        "Exit status: 0 done; 1 the port refused, or another program holds it;\n"
        "2 bad usage (a time out of range: nothing changed).\n"
        "Example: x4ctl timing --pulse 10000 --space 40000   (moves up to 20000 Hz)\n";
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
