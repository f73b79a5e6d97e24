// SPDX-License-Identifier: GPL-2.0
// x4ctl profile: the ramp of an axis' own moves (position.cpp).
#include "commands.hpp"
#include "options.hpp"
#include "position.hpp"
#include "subcommand.hpp"
#include "values.hpp"

namespace x4ctl {
namespace {

void operands(parse_state &s, const std::vector<std::string> &ops) {
  need_operands(ops, 1, 1, s.prefix);
  s.c.axis = parse_axis(ops[0], s.prefix);
}

int run(const config &c) { return with_port(c, profile_command, c.v0 || c.ve || c.vm || c.a0 || c.ae); }

}  // namespace

const subcommand &profile_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    const std::string vel = std::to_string(x4step::vel_max), acc = std::to_string(x4step::acc_max);
    c.name = "profile";
    c.usage = {"[OPTIONS] AXIS"};
    c.synopsis = "AXIS";
    c.summary = "show or set the ramp of an axis' own moves";
    c.prose =
        "Show the ramp of the axis' own moves ('goto'), or change the values given (the\n"
        "others stay) and show the result (ProStep4 section 2.5). The axis starts at\n"
        "v0, speeds up with a0 to vm, slows down with ae to ve and stops there; a move\n"
        "too short for vm turns where the ramps meet. The module keeps the profile\n"
        "after x4ctl exits.\n";
    c.options = {
        {"v0", 0, "V", "start velocity, 0.." + vel + " steps/s (default 0)",
         [](parse_state &s, const option_value &o) { s.c.v0 = parse_speed(o.value, "v0", 0, s.prefix); }},
        {"ve", 0, "V", "stop velocity, 0.." + vel + " steps/s (default 0)",
         [](parse_state &s, const option_value &o) { s.c.ve = parse_speed(o.value, "ve", 0, s.prefix); }},
        {"vm", 0, "V", "maximum velocity, 1.." + vel + " steps/s (default 1000)",
         [](parse_state &s, const option_value &o) { s.c.vm = parse_speed(o.value, "vm", 1, s.prefix); }},
        {"a0", 0, "A",
         "acceleration, 0.." + acc +
             " steps/s^2 (default 1000);\n"
             "0: no ramp, the axis jumps to vm",
         [](parse_state &s, const option_value &o) { s.c.a0 = parse_acceleration(o.value, "a0", s.prefix); }},
        {"ae", 0, "A", "deceleration, 0.." + acc + " steps/s^2 (default 1000)",
         [](parse_state &s, const option_value &o) { s.c.ae = parse_acceleration(o.value, "ae", s.prefix); }},
        json_option("one JSON object instead of text"),
    };
    c.epilogue =
        "v0 and ve must not exceed vm, and a ramp from rest to vm must last at most\n"
        "3600 s (vm / a0 and vm / ae).\n"
        "\n"
        "Exit status: 0 done; 1 the port refused (the axis moves), or another program\n"
        "holds it; 2 bad usage (nothing changed).\n"
        "Example: x4ctl profile 1 --v0 200 --vm 8000 --a0 40000 --ae 20000\n";
    c.operands = operands;
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
