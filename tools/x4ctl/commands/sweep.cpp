// SPDX-License-Identifier: GPL-2.0
// x4ctl sweep: a frequency sweep of one axis, to find resonances.
#include <algorithm>

#include "commands.hpp"
#include "holder.hpp"
#include "lang.hpp"
#include "options.hpp"
#include "subcommand.hpp"
#include "term.hpp"
#include "values.hpp"

namespace x4ctl {
namespace {

void operands(parse_state &s, const std::vector<std::string> &ops) {
  config &c = s.c;
  const std::string &prefix = s.prefix;
  need_operands(ops, 5, 5, prefix);
  c.axis = parse_axis(ops[0], prefix);
  c.move.steps[c.axis.index()] = parse_steps(ops[1], prefix);
  c.sweep_from = parse_freq(ops[2], prefix);
  c.sweep_to = parse_freq(ops[3], prefix);
  const long step = parse_number(ops[4], prefix + "frequency step");
  if (step < 1 || step > x4step::freq_max_hz)
    throw usage_error(prefix + "frequency step " + ops[4] + " out of range: use 1 to " +
                      std::to_string(x4step::freq_max_hz) + " Hz");
  c.sweep_step = static_cast<int>(step);
  // Resonance tests want constant speed: no ramp unless asked for.
  c.move.ramp = milliseconds(s.ramp.value_or(0));
  c.move.freq_hz = std::min(c.sweep_from, c.sweep_to);  // the strictest for the ramp check
  if (const auto e = x4step::check(c.move); e != x4step::errc::ok) throw usage_error(prefix + message(e));
}

int run(const config &c) {
  controller_port p(open_controller(device_of(c)));
  std_console con(true);
  interpreter in(con, &p, true);
  // The A command of the test program, on the given axis.
  const std::string script = "S" + std::to_string(c.axis.number()) + "; D" +
                             std::to_string(c.move.steps[c.axis.index()]) + "; R" +
                             std::to_string(c.move.ramp.count()) + "; A" + std::to_string(c.sweep_from) +
                             "," + std::to_string(c.sweep_to) + "," + std::to_string(c.sweep_step);
  for (const command &cmd : parse_line(script)) in.execute(cmd);
  return 0;
}

}  // namespace

const subcommand &sweep_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "sweep";
    c.usage = {"[OPTIONS] AXIS STEPS FROM TO STEP"};
    c.synopsis = "AXIS STEPS FROM TO STEP";
    c.summary = "frequency sweep of one axis, to find resonances";
    c.prose =
        "Frequency sweep of one axis to find its resonances (TEST.EXE's A command):\n"
        "AXIS moves STEPS at FROM Hz, FROM+STEP Hz, ... up to TO Hz, alternately\n"
        "forth and back so that it stays within its travel. FROM > TO sweeps down.\n"
        "Ctrl-C or ESC on the console keyboard brakes and ends the sweep.\n";
    c.options = {
        ramp_option("ramp time, at most FROM and TO in Hz (default 0)"),
    };
    c.epilogue =
        "Exit status: 0 every frequency ran; 1 the port refused or a move was braked;\n"
        "2 bad usage.\n"
        "Example: x4ctl sweep 2 1000 200 500 20\n";
    c.operands = operands;
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
