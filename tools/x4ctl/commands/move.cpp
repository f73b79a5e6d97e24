// SPDX-License-Identifier: GPL-2.0
// x4ctl move: an interpolated move of up to four axes, and the moves after it (--then).
#include <iostream>
#include <vector>

#include "commands.hpp"
#include "holder.hpp"
#include "motion.hpp"
#include "options.hpp"
#include "show.hpp"
#include "subcommand.hpp"
#include "term.hpp"
#include "values.hpp"

namespace x4ctl {
namespace {

std::string describe_move(const x4step::move &m) {
  return steps_text(steps_of(m)) + " at " + std::to_string(m.freq_hz) + " Hz, ramp " +
         std::to_string(m.ramp.count()) + " ms";
}

// "move 3 of 3 not started", "moves 2 to 3 not started" (from: an index).
std::string not_started(size_t from, size_t n) {
  return (from + 1 == n ? "move " : "moves " + std::to_string(from + 1) + " to ") + std::to_string(n) +
         " not started";
}

// A move stays in the foreground until it ends, as gpioset does: 'x4ctl
// move 100; x4ctl move -100' runs one after the other.
void defaults(config &c) { c.wait = true; }

void operands(parse_state &s, const std::vector<std::string> &ops) {
  config &c = s.c;
  const std::string &prefix = s.prefix;
  need_operands(ops, 1, x4step::axes, prefix);
  for (size_t i = 0; i < ops.size(); i++) c.move.steps[i] = parse_steps(ops[i], prefix);
  if (const auto e = x4step::check(c.move); e != x4step::errc::ok) throw usage_error(prefix + message(e));
  for (const auto &path : s.then_paths) {
    const std::string then = prefix + "--then ";
    if (path.size() > x4step::axes)
      throw usage_error(prefix + "--then: unexpected argument '" + path[x4step::axes] + "'");
    x4step::move m = c.move;  // the same frequency and ramp
    m.steps = {};
    for (size_t i = 0; i < path.size(); i++) m.steps[i] = parse_steps(path[i], then);
    if (const auto e = x4step::check(m); e != x4step::errc::ok) throw usage_error(then + message(e));
    c.then.push_back(m);
  }
}

// move, and the moves of --then: each preloaded while the one before it
// runs, and started the moment that one ends.
int run(const config &c) {
  controller_port p(open_controller(device_of(c)));
  std_console con(c.wait);
  std::vector<x4step::move> moves{c.move};
  moves.insert(moves.end(), c.then.begin(), c.then.end());
  const size_t n = moves.size();
  auto nth = [&](size_t i) { return "move " + std::to_string(i + 1) + " of " + std::to_string(n); };
  auto header = [&](size_t i) {
    return (n == 1 ? std::string("move") : nth(i)) + ": " + describe_move(moves[i]);
  };
  if (!c.wait) {
    for (size_t i = 0; i < n; i++) std::cout << header(i) << "\n";
    std::cout << std::flush;
    start_moves(p, moves);
    hold_in_background(p, [&](console &bg) { follow_moves(p, bg, moves); });
    return 0;  // the background process, after the moves
  }
  std::cout << header(0) << "\n" << std::flush;
  start_moves(p, moves);
  const std::vector<outcome> done = follow_moves(p, con, moves, [&](size_t i, const outcome &o) {
    if (!o.completed) return;  // the failure below says it
    std::cout << describe(o, steps_of(moves[i])) << "\n";
    if (i + 1 < n && o.late_halt.empty()) std::cout << header(i + 1) << "\n";
    std::cout << std::flush;
  });
  const size_t i = done.size() - 1;
  const outcome &last = done.back();
  if (!last.completed) {
    const std::string why = describe(last, steps_of(moves[i]));
    if (n == 1) throw failure(why);
    throw failure(nth(i) + ": " + why + (i + 1 < n ? "; " + not_started(i + 1, n) : ""));
  }
  if (i + 1 < n)  // a brake request that came as the move ended
    throw failure("halted (" + last.late_halt + ") at the end of " + nth(i) + ": " + not_started(i + 1, n));
  return 0;
}

}  // namespace

const subcommand &move_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    const std::string steps = std::to_string(x4step::steps_max);
    c.name = "move";
    c.usage = {"[OPTIONS] STEPS1 [STEPS2 [STEPS3 [STEPS4]]]",
               "[OPTIONS] STEPS... --then STEPS... [--then STEPS...]..."};
    c.synopsis = "STEPS...";
    c.summary = "interpolated move of up to four axes";
    c.prose = "Move axes 1..4 by the given steps (signed, -" + steps + ".." + steps +
              "; missing\n"
              "axes stay) interpolated (X4Load, X4Start): the axis with the longest path\n"
              "runs at the frequency, the others follow it, all start and stop together.\n"
              "Each --then is one more move at the same frequency and ramp: it is\n"
              "preloaded while the move before it runs, and started the moment that one ends\n"
              "(X4Load during the move, X4Start once X4GetState is 0): no pause for planning.\n"
              "A move that is braked or stopped ends the sequence: the rest do not start.\n";
    c.options = {
        freq_option(),
        ramp_option(),
        {"then", 0, "STEPS1 [STEPS2 [STEPS3 [STEPS4]]]", "one more move after the one before (repeatable)",
         [](parse_state &s, const option_value &o) {
           s.then_paths.push_back({o.value});
           s.then_paths.back().insert(s.then_paths.back().end(), o.more.begin(), o.more.end());
         },
         true},
        wait_option("stay until the moves end, showing progress (the\n"
                    "default); Ctrl-C brakes, a second Ctrl-C stops"),
        {"background", 'b', "", "return once the motors run (see below)",
         [](parse_state &s, const option_value &) { s.c.wait = false; }},
    };
    c.epilogue =
        "With --background, x4ctl returns once the motors run, and a background\n"
        "x4ctl holds the port until the moves end, starting the --then moves too\n"
        "(the module brakes a move whose program exits). 'x4ctl brake', 'x4ctl stop'\n"
        "or ESC on the console keyboard end it early; 'x4ctl monitor' follows it.\n"
        "\n"
        "Exit status: 0 every move reached its target (with --background: the move\n"
        "runs); 1 the port refused, or a move was braked or stopped; 2 bad usage (a\n"
        "bad value after --then too: nothing moved).\n"
        "Examples: x4ctl move 1000 800 600 400 --freq 1000 --ramp 50\n"
        "          x4ctl move 1000 800 600 400 --then -1000 -800 -600 -400\n"
        "          x4ctl move 100000 --background; x4ctl brake\n";
    c.defaults = defaults;
    c.operands = operands;
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
