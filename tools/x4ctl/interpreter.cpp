// SPDX-License-Identifier: GPL-2.0
// x4ctl: the interpreter of the TEST.EXE command language (lang.hpp).
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <ostream>

#include "cli.hpp"
#include "lang.hpp"

namespace x4ctl {
namespace {

// How long C keeps moving after a cursor key: the first press must outlast
// the terminal's auto-repeat delay (250..660 ms usually), later repeats
// come every 30..40 ms. No repeat within this time means: key released.
constexpr milliseconds first_hold{700};
constexpr milliseconds repeat_hold{200};

bool is_halt_key(key k) {
  return k == key::esc || k == key::interrupt || k == key::brake_request || k == key::stop_request;
}

// What brakes a move without a terminal: another x4ctl cannot reach a
// simulated port.
std::string brakes_text(const port &p) {
  return p.simulated() ? "a brake key or Ctrl-C brakes" : "a brake key, Ctrl-C or 'x4ctl brake' brakes";
}

}  // namespace

interpreter::interpreter(console &con, port *p, bool strict) : con_(con), port_(p), strict_(strict) {}

std::string interpreter::prompt() const { return std::to_string(axis_) + "-> "; }

int interpreter::leader() const {
  step_counts steps{};
  for (int i = 0; i < x4step::axes; i++) steps[i] = values_[i].distance;
  const int lead = leader_index(steps);
  return steps[lead] ? lead + 1 : 0;
}

x4step::move interpreter::go_move() const {
  const int lead = leader();
  const axis_values &lv = values_[(lead ? lead : axis_) - 1];
  x4step::move m;
  for (int i = 0; i < x4step::axes; i++) m.steps[i] = values_[i].distance;
  m.freq_hz = lv.freq_hz;
  m.ramp = milliseconds(lv.ramp_ms);
  return m;
}

x4step::move interpreter::axis_move(long steps, int freq_hz) const {
  x4step::move m;
  m.steps[axis_ - 1] = steps;
  m.freq_hz = freq_hz;
  m.ramp = milliseconds(values_[axis_ - 1].ramp_ms);
  return m;
}

deadline interpreter::until(const command &c) const {
  if (!c.time_ms) return std::nullopt;
  return port_->now() + milliseconds(*c.time_ms);
}

std::string interpreter::info() const {
  const int lead = leader();
  std::string s = "axis  distance  freq Hz  ramp ms\n";
  for (int a = 1; a <= x4step::axes; a++) {
    const axis_values &v = values_[a - 1];
    char line[96];
    std::snprintf(line, sizeof line, "%c %d  %9ld  %7d  %7d%s\n", a == axis_ ? '>' : ' ', a, v.distance,
                  v.freq_hz, v.ramp_ms, a == lead ? "  leader" : "");
    s += line;
  }
  if (!lead) return s + "No axis has a distance yet: D sets one. (> marks the selected axis.)\n";
  const axis_values &lv = values_[lead - 1];
  return s + "G moves the axes with a distance interpolated, at the frequency and ramp of\n" +
         "the leader (the longest distance): axis " + std::to_string(lead) + ", " +
         std::to_string(lv.freq_hz) + " Hz, " + std::to_string(lv.ramp_ms) +
         " ms. (> marks the selected axis.)\n";
}

bool interpreter::execute(const command &c) {
  axis_values &v = values_[axis_ - 1];
  switch (c.what) {
    case verb::select:
      axis_ = static_cast<int>(c.args[0]);
      break;
    case verb::distance:
      v.distance = c.args[0];
      break;
    case verb::frequency:
      v.freq_hz = static_cast<int>(c.args[0]);
      break;
    case verb::ramp:
      v.ramp_ms = static_cast<int>(c.args[0]);
      break;
    case verb::info:
      con_.out() << info();
      break;
    case verb::help:
      con_.out() << language_help();
      break;
    case verb::quit:
      return false;
    case verb::go:
      go();
      break;
    case verb::endless:
      endless(c);
      break;
    case verb::cursor:
      cursor();
      break;
    case verb::sweep:
      sweep(c);
      break;
    case verb::toggle:
      toggle(c);
      break;
    case verb::inputs:
      inputs(c);
      break;
    case verb::wait:
      wait(c);
      break;
    case verb::output:
      if (!port_) break;
      port_->set_output(c.args[0] == 1 ? x4step::signal::one : x4step::signal::two, c.args[1] != 0);
      con_.out() << "O: signal " << c.args[0] << " (pin " << (c.args[0] == 1 ? 1 : 14) << ") "
                 << (c.args[1] ? "on" : "off") << "\n";
      break;
    case verb::keys: {
      if (!port_) break;
      const std::vector<int> codes(c.args.begin(), c.args.end());
      port_->set_brake_codes(codes);
      std::string list;
      for (int k : codes) list += " " + std::to_string(k);
      con_.out() << (codes.empty() ? "K: only ESC brakes\n" : "K: brake keys" + list + " and ESC\n");
      break;
    }
  }
  return true;
}

void interpreter::go() {
  const x4step::move m = go_move();
  if (const auto e = x4step::check(m); e != x4step::errc::ok) {
    std::string why = "G: " + message(e);
    if (const int lead = leader())
      why += " (G uses the leader axis " + std::to_string(lead) + ": F" + std::to_string(m.freq_hz) + " R" +
             std::to_string(m.ramp.count()) + ")";
    else
      why += " (D sets the distance of the selected axis)";
    throw usage_error(why);
  }
  if (!port_) return;
  con_.out() << "G: " << steps_text(steps_of(m)) << " at " << m.freq_hz << " Hz, ramp " << m.ramp.count()
             << " ms (leader axis " << leader() << ")\n"
             << std::flush;
  const outcome o = run_move(*port_, con_, m);
  if (!o.completed && strict_) throw failure("G: " + describe(o, steps_of(m)));
  con_.out() << describe(o, steps_of(m)) << "\n";
}

void interpreter::endless(const command &c) {
  const axis_values &v = values_[axis_ - 1];
  const char *name = c.dir == x4step::direction::positive ? "M+" : "M-";
  if (const auto e = x4step::check_endless(v.freq_hz, milliseconds(v.ramp_ms)); e != x4step::errc::ok)
    throw usage_error(std::string(name) + ": " + message(e) + " (axis " + std::to_string(axis_) + ": F" +
                      std::to_string(v.freq_hz) + " R" + std::to_string(v.ramp_ms) + ")");
  if (!port_) return;
  check_endless_ends(*port_, con_, c.time_ms.has_value(), name, std::make_pair(x4step::axis(axis_), c.dir));
  con_.out() << name << ": axis " << axis_ << " endless at " << v.freq_hz << " Hz, ramp " << v.ramp_ms
             << " ms; "
             << (c.time_ms             ? "brakes after " + std::to_string(*c.time_ms) + " ms"
                 : con_.has_keyboard() ? "ESC brakes"
                                       : brakes_text(*port_))
             << "\n"
             << std::flush;
  const outcome o =
      run_endless(*port_, con_, x4step::axis(axis_), c.dir, v.freq_hz, milliseconds(v.ramp_ms), until(c));
  con_.out() << describe(o, std::nullopt) << "\n";
}

void interpreter::cursor() {
  const axis_values &v = values_[axis_ - 1];
  if (!con_.has_keyboard())
    throw usage_error("C: C needs a terminal for the cursor keys; in scripts use M+ or M- with a time");
  if (const auto e = x4step::check_endless(v.freq_hz, milliseconds(v.ramp_ms)); e != x4step::errc::ok)
    throw usage_error("C: " + message(e));
  if (!port_) return;
  con_.out() << "C: axis " << axis_ << " with LEFT and RIGHT (moves while the key is held), ESC ends\n"
             << std::flush;
  keys_guard keys(con_);
  int moving = 0;        // direction of the running jog, 0: none
  bool pending = false;  // a jog ran whose steps are not in total yet
  long long total = 0;   // steps of the finished jogs (each start clears the counters)
  steady::time_point release_at{};
  auto settle = [&] {  // wait for the last jog to end, count its steps
    if (!pending) return;
    port_->wait(milliseconds(3000));
    total += port_->get_status().steps[axis_ - 1];
    pending = false;
    moving = 0;
  };
  for (;;) {
    const key k = pause(*port_, con_, milliseconds(20), true);
    const auto now = steady::now();
    if (is_halt_key(k)) {
      if (k == key::stop_request)
        stop_quietly(*port_);
      else if (moving)
        brake_quietly(*port_);
      break;
    }
    if (k == key::left || k == key::right) {
      const int dir = k == key::right ? 1 : -1;
      if (moving && dir != moving) brake_quietly(*port_);
      if (moving != dir) {
        settle();
        start_endless(*port_, x4step::axis(axis_),
                      dir > 0 ? x4step::direction::positive : x4step::direction::negative, v.freq_hz,
                      milliseconds(v.ramp_ms));
        moving = dir;
        pending = true;
        release_at = now + first_hold;
      } else {
        release_at = now + repeat_hold;
      }
    }
    const auto st = port_->get_status();
    if (moving && !st.active) moving = 0;  // braked by a brake key
    if (moving && now >= release_at) {
      brake_quietly(*port_);
      moving = 0;
    }
    if (con_.live())
      draw_live(con_, "C: axis " + std::to_string(axis_) + " at " +
                          std::to_string(total + (pending ? st.steps[axis_ - 1] : 0)) + " steps");
  }
  settle();
  if (con_.live()) draw_live(con_, "");
  con_.out() << "C: axis " << axis_ << " ended " << total << " steps from where C began\n";
}

void interpreter::sweep(const command &c) {
  const axis_values &v = values_[axis_ - 1];
  const long from = c.args[0], to = c.args[1], step = c.args[2];
  if (v.distance == 0)
    throw usage_error("A: " + message(x4step::errc::no_steps) + " (D sets the distance of axis " +
                      std::to_string(axis_) + ")");
  const x4step::move slowest = axis_move(v.distance, static_cast<int>(std::min(from, to)));
  if (const auto e = x4step::check(slowest); e != x4step::errc::ok)
    throw usage_error("A: " + message(e) + " (axis " + std::to_string(axis_) + ": R" +
                      std::to_string(v.ramp_ms) + ", lowest frequency " + std::to_string(slowest.freq_hz) +
                      " Hz)");
  if (!port_) return;
  keys_guard keys(con_);  // raw for the whole sweep: an ESC between two moves counts too
  const long dir = from <= to ? 1 : -1;
  int n = 0;
  for (long f = from; dir > 0 ? f <= to : f >= to; f += dir * step, n++) {
    // Alternately forth and back, so the axis stays within its travel.
    const x4step::move m = axis_move(n % 2 ? -v.distance : v.distance, static_cast<int>(f));
    const outcome o = run_move(*port_, con_, m);
    const std::string line =
        "A: " + std::to_string(f) + " Hz " + std::to_string(m.steps[axis_ - 1]) + " steps ";
    if (!o.completed) {
      if (strict_) throw failure(line + describe(o, steps_of(m)));
      con_.out() << line << describe(o, steps_of(m)) << "\n";
      return;
    }
    con_.out() << line << "done\n" << std::flush;
  }
}

void interpreter::toggle(const command &c) {
  const axis_values &v = values_[axis_ - 1];
  const x4step::move forth = axis_move(v.distance, v.freq_hz);
  if (const auto e = x4step::check(forth); e != x4step::errc::ok)
    throw usage_error("T: " + message(e) + " (axis " + std::to_string(axis_) + ": D" +
                      std::to_string(v.distance) + " F" + std::to_string(v.freq_hz) + " R" +
                      std::to_string(v.ramp_ms) + ")");
  if (!port_) return;
  check_endless_ends(*port_, con_, c.time_ms.has_value(), "T");
  const x4step::move back = axis_move(-v.distance, v.freq_hz);
  con_.out() << "T: axis " << axis_ << " back and forth by " << v.distance << " steps at " << v.freq_hz
             << " Hz, ramp " << v.ramp_ms << " ms; "
             << (c.time_ms             ? "brakes after " + std::to_string(*c.time_ms) + " ms"
                 : con_.has_keyboard() ? "ESC brakes"
                                       : brakes_text(*port_))
             << "\n"
             << std::flush;
  keys_guard keys(con_);  // raw for all the moves: an ESC between two moves counts too
  const deadline u = until(c);
  for (long moves = 0;; moves++) {
    const x4step::move &m = moves % 2 ? back : forth;
    const outcome o = run_move(*port_, con_, m, u);
    if (!o.completed) {
      con_.out() << "T: " << moves << " moves, then " << describe(o, steps_of(m)) << "\n";
      return;
    }
    if (u && port_->now() >= *u) {
      con_.out() << "T: " << moves + 1 << " moves, time up\n";
      return;
    }
  }
}

void interpreter::inputs(const command &c) {
  if (!port_) return;
  auto line = [&] { return "E: " + inputs_text(port_->get_status().inputs); };
  if (!con_.has_keyboard() && !c.time_ms) {
    con_.out() << line() << "\n";
    return;
  }
  keys_guard keys(con_);
  const deadline u = until(c);
  std::string last;
  for (;;) {
    const std::string now = line();
    if (con_.live())
      draw_live(con_, now + "  (ESC ends)");
    else if (now != last)
      con_.out() << now << "\n" << std::flush;  // only changes, when it is a log
    last = now;
    if (is_halt_key(pause(*port_, con_, milliseconds(100), !u))) break;
    if (u && port_->now() >= *u) break;
  }
  if (con_.live()) draw_live(con_, last + "\n");
}

void interpreter::wait(const command &c) {
  if (!port_) return;
  const auto end = port_->now() + milliseconds(c.args[0]);
  for (auto now = port_->now(); now < end; now = port_->now()) {
    const auto left = std::chrono::ceil<milliseconds>(end - now);
    if (is_halt_key(pause(*port_, con_, std::min(left, milliseconds(100))))) throw failure("W: interrupted");
  }
}

}  // namespace x4ctl
