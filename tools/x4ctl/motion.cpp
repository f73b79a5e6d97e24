// SPDX-License-Identifier: GPL-2.0
// x4ctl: following a running move.
#include "motion.hpp"

#include <cstdlib>
#include <optional>
#include <string>

#include "cli.hpp"

namespace x4ctl {
namespace {

// brake() and stop() race with the move's own end: "not active" then is no error.
template <typename F>
void halt(F &&f) {
  try {
    f();
  } catch (const x4step::error &e) {
    if (e.code() != x4step::make_error_code(x4step::errc::not_active)) throw;
  }
}

// A move of axis 4 in a phase mode, which the module refuses: a failure
// that says why.
void check_axis4(const port &p) {
  const x4step::output_mode m = p.get_config().mode();
  if (m != x4step::output_mode::clock_dir)
    throw failure(std::string("axis 4 cannot move in ") + mode_name(m) +
                  " mode: the SMC800/SMC1500 boards drive axes 1 to 3 ('x4ctl mode clock-dir' for " +
                  "clock and direction signals)");
}

// Why the port refused a move of the axes with e, if its
// settings are the reason; rethrows e otherwise. freq_hz: the frequency of
// an X4Step move; none for the axes' own moves (the profile's speeds).
// Only called while e is being handled.
[[noreturn]] void explain(const port &p, const x4step::error &e, x4step::axis_set axes,
                          std::optional<int> freq_hz) {
  if (e.code() == x4step::errc::param_fail && axes.contains(x4step::axis::a)) check_axis4(p);
  if (e.code() == x4step::errc::freq_too_high && freq_hz.value_or(0) <= x4step::freq_max_hz) {
    const x4step::output_mode m = p.get_config().mode();
    const x4step::step_timing t = p.get_step_timing();
    const std::string timing = "pulse " + std::to_string(t.pulse().count()) + " ns and space " +
                               std::to_string(t.space().count()) + " ns allow at most ";
    if (!freq_hz)
      throw failure("too fast for the step timing: " + timing +
                    std::to_string(max_freq_hz(t, m, static_cast<int>(x4step::vel_max))) +
                    " steps/s ('x4ctl profile' lowers vm, 'x4ctl timing' changes the times)");
    if (const int max = max_freq_hz(t, m); *freq_hz > max)
      throw failure("frequency too high for the step timing: " + std::to_string(*freq_hz) + " Hz, but " +
                    timing + std::to_string(max) + " Hz ('x4ctl timing' changes them)");
  }
  throw;  // e, as it was
}

// What follow_until does to what runs, and shows meanwhile.
struct follow_ops {
  x4step::axis_set axes;                                   // the axes followed
  std::function<bool()> ended;                             // waits up to a tick: true once it ended
  std::function<void(x4step::axis_set axes)> brake, stop;  // of some of the axes
  std::function<std::string(bool braking)> live;           // the live line
  std::function<steady::time_point()> now;                 // the port's clock, for the deadline
};

// Follows until ops.ended(): ESC, Ctrl-C, a brake request or the deadline
// brake, a second Ctrl-C or a stop request stop; requests only the axes
// they name. Returns why something was halted, empty if nothing was.
std::string follow_until(console &con, const follow_ops &ops, deadline until) {
  keys_guard keys(con);
  std::string why;
  x4step::axis_set halted;  // the axes braked or stopped
  auto brake_for = [&](const char *w, x4step::axis_set axes) {
    axes &= ops.axes & ~halted;
    if (axes.empty()) return;
    halted |= axes;
    if (why.empty()) why = w;
    ops.brake(axes);
  };
  auto stop_for = [&](const char *w, x4step::axis_set axes) {
    axes &= ops.axes;
    if (axes.empty()) return;
    halted |= axes;
    why = w;
    ops.stop(axes);
  };
  while (!ops.ended()) {
    switch (con.read_key(milliseconds(0))) {
      case key::esc:
        brake_for("ESC", all_axes);
        break;
      case key::brake_request:
        brake_for("brake request", con.requested_axes());
        break;
      case key::interrupt:
        if (halted.empty())
          brake_for("Ctrl-C", all_axes);
        else  // a second Ctrl-C: no patience for the ramp
          stop_for("Ctrl-C, stopped", all_axes);
        break;
      case key::stop_request:
        stop_for("stop request", con.requested_axes());
        break;
      default:
        break;
    }
    if (until && ops.now() >= *until) brake_for("time up", all_axes);
    if (con.live()) draw_live(con, ops.live(!halted.empty()));
  }
  return why;
}

// Why a move ended that nobody here halted: a limit switch that stopped
// an axis, else someone else ('x4ctl brake', another reader's halt).
std::string limit_stop(const x4step::axes_status &a) {
  for (x4step::axis ax : all_axes) {
    const unsigned e = a[ax].error;
    if (e & (x4step::axis_error::limit_pos | x4step::axis_error::limit_neg))
      return std::string("limit switch ") + (e & x4step::axis_error::limit_pos ? "E+" : "E-") + " of axis " +
             std::to_string(ax.number());
  }
  return "braked elsewhere";
}

// ", braking" while braking, else what brakes.
std::string live_hint(const console &con, bool braking) {
  return braking ? "  braking" : con.has_keyboard() ? "  (ESC brakes)" : "";
}

void halt_quietly(port &p, x4step::axis_set axes, x4step::halt_mode how) {
  halt([&] { p.halt(axes, how); });
}

// Loads m while the move before it runs. Should the port refuse, that move
// is braked (and waited for), so that nothing runs on that x4ctl does not follow.
void preload(port &p, const x4step::move &m) {
  try {
    load_move(p, m);
  } catch (...) {
    brake_quietly(p);
    p.wait(milliseconds(5000));  // a brake takes at most the longest ramp, 1 s
    throw;
  }
}

}  // namespace

void load_move(port &p, const x4step::move &m) {
  try {
    p.load(m);
  } catch (const x4step::error &e) {
    x4step::axis_set axes;
    for (x4step::axis a : all_axes)
      if (m.steps[a.index()]) axes |= a;
    explain(p, e, axes, m.freq_hz);
  }
}

void start_endless(port &p, x4step::axis a, x4step::direction dir, int freq_hz, milliseconds ramp) {
  try {
    p.move_endless(a, dir, freq_hz, ramp);
  } catch (const x4step::error &e) {
    explain(p, e, a, freq_hz);
  }
}

void start_goto(port &p, x4step::axis_set axes, const std::array<long, x4step::axes> &targets,
                bool relative) {
  try {
    p.move_to(axes, targets, relative);
  } catch (const x4step::error &e) {
    explain(p, e, axes, std::nullopt);
  }
}

void start_home(port &p, x4step::axis a, const x4step::homing &h) {
  if (!p.get_switches().ref.at(a.index()))
    throw failure("axis " + std::to_string(a.number()) + " has no reference switch: 'x4ctl limits " +
                  std::to_string(a.number()) + " --ref INPUT' names its input (1..5)");
  try {
    p.home(a, h);
  } catch (const x4step::error &e) {
    explain(p, e, a, std::nullopt);
  }
}

void brake_quietly(port &p) {
  halt([&] { p.brake(); });
}

void stop_quietly(port &p) {
  halt([&] { p.stop(); });
}

key pause(port &p, console &con, milliseconds d, bool paced) {
  if (p.clock_runs()) return con.read_key(d);
  const key k = con.read_key(paced ? d : milliseconds(0));
  p.pass(d);
  return k;
}

deadline deadline_in(const port &p, const std::optional<milliseconds> &t) {
  if (!t) return std::nullopt;
  return p.now() + *t;
}

void check_endless_ends(const port &p, const console &con, bool timed, const std::string &what,
                        const std::optional<std::pair<x4step::axis, x4step::direction>> &toward) {
  if (timed || p.clock_runs() || con.has_keyboard() || sim_keys_scripted()) return;
  if (toward) {  // a limit switch ahead stops it there
    const x4step::switches s = p.get_switches();
    const auto i = static_cast<std::size_t>(toward->first.index());
    if ((toward->second == x4step::direction::positive ? s.plus : s.minus)[i]) return;
  }
  throw usage_error(what +
                    ": on a simulated port in virtual time nothing would end this endless move (no "
                    "terminal, no brake key script, no limit switch ahead): give it a time, a key script "
                    "(X4STEP_SIM_KEYS=500ms:esc), a machine with the limit (X4STEP_SIM_MACHINE) or real "
                    "time (X4STEP_SIM_TIME=real)");
}

void draw_live(console &con, const std::string &line) { con.out() << '\r' << line << "\x1b[K" << std::flush; }

step_counts steps_of(const x4step::move &m) {
  step_counts s{};
  for (int i = 0; i < x4step::axes; i++) s[i] = m.steps[i];
  return s;
}

int leader_index(const step_counts &steps) {
  int lead = 0;
  for (int i = 1; i < x4step::axes; i++)
    if (std::llabs(steps[i]) > std::llabs(steps[lead])) lead = i;
  return lead;
}

outcome follow(port &p, console &con, const std::optional<step_counts> &target, deadline until) {
  const int lead = target ? leader_index(*target) : 0;
  const follow_ops ops{all_axes,
                       [&] { return p.wait(tick); },
                       [&](x4step::axis_set) { brake_quietly(p); },
                       [&](x4step::axis_set) { stop_quietly(p); },
                       [&](bool braking) {
                         const auto s = p.get_status();
                         if (target) return progress_line(s.steps, s.steps[lead], (*target)[lead]);
                         return "steps " + steps_text(s.steps) + live_hint(con, braking);
                       },
                       [&] { return p.now(); }};
  outcome o;
  o.halted_by = follow_until(con, ops, until);
  // First the outcome: the next move of a sequence starts on it.
  o.end = p.get_status();
  o.completed = target && o.end.steps == *target;
  if (o.completed) {
    o.late_halt = std::move(o.halted_by);  // a late brake request that found the move at its end
    o.halted_by.clear();
  } else if (o.halted_by.empty()) {
    o.halted_by = o.end.last_brake_code ? key_name(o.end.last_brake_code) : limit_stop(p.get_axes());
  }
  if (con.live()) draw_live(con, "");
  return o;
}

axes_outcome follow_axes(port &p, console &con, x4step::axis_set axes, deadline until) {
  const follow_ops ops{
      axes,
      [&] { return p.wait_axes(axes, tick); },
      [&](x4step::axis_set some) { halt_quietly(p, some, x4step::halt_mode::brake); },
      [&](x4step::axis_set some) { halt_quietly(p, some, x4step::halt_mode::stop); },
      [&](bool braking) { return positions_text(p.get_axes(), axes) + live_hint(con, braking); },
      [&] { return p.now(); }};
  axes_outcome o;
  o.halted_by = follow_until(con, ops, until);
  o.end = p.get_axes();
  if (con.live()) draw_live(con, "");
  return o;
}

outcome run_move(port &p, console &con, const x4step::move &m, deadline until) {
  load_move(p, m);
  p.start();
  return follow(p, con, steps_of(m), until);
}

void start_moves(port &p, const std::vector<x4step::move> &moves) {
  // The port's settings refuse a move of axis 4 in a phase mode: for the later
  // moves, find out before the first one runs.
  for (size_t i = 1; i < moves.size(); i++)
    if (moves[i].steps[3]) {
      check_axis4(p);
      break;
    }
  load_move(p, moves.at(0));
  p.start();
  if (moves.size() > 1) preload(p, moves[1]);
}

std::vector<outcome> follow_moves(port &p, console &con, const std::vector<x4step::move> &moves,
                                  const move_ended &ended) {
  keys_guard keys(con);  // one raw terminal for the whole sequence: no key gets lost between moves
  std::vector<outcome> done;
  for (size_t i = 0; i < moves.size(); i++) {
    done.push_back(follow(p, con, steps_of(moves[i]), std::nullopt));
    const outcome &o = done.back();
    const bool next = i + 1 < moves.size() && o.completed && o.late_halt.empty();
    if (next) {
      p.start();  // moves[i + 1], loaded while moves[i] ran
      if (i + 2 < moves.size()) preload(p, moves[i + 2]);
    }
    if (ended) ended(i, o);
    if (!next) break;
  }
  return done;
}

outcome run_endless(port &p, console &con, x4step::axis a, x4step::direction dir, int freq_hz,
                    milliseconds ramp, deadline until) {
  start_endless(p, a, dir, freq_hz, ramp);
  return follow(p, con, std::nullopt, until);
}

std::string describe(const outcome &o, const std::optional<step_counts> &target) {
  if (o.completed) return "done: " + steps_text(o.end.steps);
  std::string s = "halted (" + o.halted_by + ")";
  if (target) {
    const int lead = leader_index(*target);
    s += " at " + std::to_string(std::llabs(o.end.steps[lead])) + " of " +
         std::to_string(std::llabs((*target)[lead])) + " steps";
  }
  return s + ": " + steps_text(o.end.steps);
}

}  // namespace x4ctl
