// SPDX-License-Identifier: GPL-2.0
// x4ctl: following a running move.
#include "motion.hpp"

#include <cstdlib>

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

}  // namespace

void brake_quietly(port &p) {
  halt([&] { p.brake(); });
}

void stop_quietly(port &p) {
  halt([&] { p.stop(); });
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
  keys_guard keys(con);
  outcome o;
  bool braking = false;
  const int lead = target ? leader_index(*target) : 0;
  auto brake_for = [&](const char *why) {
    if (braking) return;
    braking = true;
    o.halted_by = why;
    brake_quietly(p);
  };
  for (;;) {
    if (p.wait(tick)) break;
    switch (con.read_key(milliseconds(0))) {
      case key::esc:
        brake_for("ESC");
        break;
      case key::brake_request:
        brake_for("brake request");
        break;
      case key::interrupt:
        if (!braking) {
          brake_for("Ctrl-C");
        } else {  // a second Ctrl-C: no patience for the ramp
          o.halted_by = "Ctrl-C, stopped";
          stop_quietly(p);
        }
        break;
      case key::stop_request:
        braking = true;
        o.halted_by = "stop request";
        stop_quietly(p);
        break;
      default:
        break;
    }
    if (until && steady::now() >= *until) brake_for("time up");
    if (con.live()) {
      const auto s = p.get_status();
      if (target)
        draw_live(con, progress_line(s.steps, s.steps[lead], (*target)[lead]));
      else
        draw_live(con, "steps " + steps_text(s.steps) +
                           (braking              ? "  braking"
                            : con.has_keyboard() ? "  (ESC brakes)"
                                                 : ""));
    }
  }
  if (con.live()) draw_live(con, "");
  o.end = p.get_status();
  o.completed = target && o.end.steps == *target;
  if (o.completed) {
    o.halted_by.clear();  // a late brake request that found the move at its end
  } else if (o.halted_by.empty()) {
    o.halted_by = o.end.last_brake_code ? key_name(o.end.last_brake_code) : "braked elsewhere";
  }
  return o;
}

outcome run_move(port &p, console &con, const x4step::move &m, deadline until) {
  p.load(m);
  p.start();
  return follow(p, con, steps_of(m), until);
}

outcome run_endless(port &p, console &con, int axis, x4step::direction dir, int freq_hz, milliseconds ramp,
                    deadline until) {
  p.move_endless(axis, dir, freq_hz, ramp);
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
