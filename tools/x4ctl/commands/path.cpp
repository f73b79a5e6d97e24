// SPDX-License-Identifier: GPL-2.0
// x4ctl path: a continuous path of straight segments in steps (path.cpp runs it).
#include "path.hpp"

#include "commands.hpp"
#include "options.hpp"
#include "subcommand.hpp"
#include "values.hpp"

namespace x4ctl {
namespace {

void operands(parse_state &s, const std::vector<std::string> &ops) {
  need_operands(ops, 0, 1, s.prefix);
  if (!ops.empty()) s.c.file = ops[0];
}

}  // namespace

const subcommand &path_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "path";
    c.usage = {"[OPTIONS] [FILE]"};
    c.synopsis = "[FILE]";
    c.summary = "run a continuous path of straight segments in steps";
    c.prose =
        "Run a continuous path: straight segments one after the other without\n"
        "stopping between them, planned ahead by the module so that the motors\n"
        "always come to rest on the path. FILE (default: standard input) has one\n"
        "segment per line: up to 4 step counts (axes 1..4, signed), then optionally\n"
        "speed=STEPS/S (along the path), accel=STEPS/S^2 and corner=STEPS/S (the\n"
        "most the corner before it allows; else from the corner's angle and the\n"
        "junction deviation). '#' starts a comment. The whole file is checked\n"
        "before the first step: a bad line is named as FILE:LINE:COLUMN. Then it is\n"
        "streamed to the module while it runs, with the progress shown.\n"
        "Ctrl-C (or 'x4ctl brake') holds the path along it and flushes it; 'x4ctl\n"
        "stop' stops at once.\n";
    c.options = {
        {"speed", 's', "STEPS/S", "speed along the path where a line has none (1000)",
         [](parse_state &s, const option_value &o) {
           s.c.path.speed = parse_speed(o.value, "speed", 1, s.prefix);
         }},
        {"accel", 'a', "STEPS/S^2", "acceleration where a line has none (10000)",
         [](parse_state &s, const option_value &o) {
           s.c.path.accel = static_cast<unsigned>(
               parse_range(o.value, "accel", 1, x4step::acc_max, " steps/s^2", s.prefix));
         }},
        {"deviation", 0, "D",
         "junction deviation in steps (0.5): how far from a\n"
         "corner the path may round it at speed (as GRBL's)",
         [](parse_state &s, const option_value &o) {
           char *end = nullptr;
           const double v = std::strtod(o.value.c_str(), &end);
           if (o.value.empty() || *end || !(v > 0 && v <= 1000))
             throw usage_error(s.prefix + "deviation '" + o.value +
                               "': use a number of steps, 0 < D <= 1000");
           s.c.path.deviation = v;
         }},
        override_option(),
        check_option("check the file and stop there: nothing moves"),
        json_option("progress as JSON lines (state, line, done, speed)"),
    };
    c.epilogue =
        "Exit status: 0 the path ran to its end; 1 it was aborted or the port\n"
        "refused; 2 bad usage or a bad line.\n"
        "Example: printf '4000 0\\n0 4000\\n-4000 0\\n0 -4000\\n' | x4ctl path -s 2000\n";
    c.operands = operands;
    c.run = cmd_path;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
