// SPDX-License-Identifier: GPL-2.0
// x4ctl: formatting of states, steps and progress.
#include "show.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "json.hpp"

namespace x4ctl {
namespace {

// Input bits 0..4 of X4GetIn and their pins.
const int input_pins[5] = {15, 13, 12, 10, 11};

int bit(unsigned v, int n) { return (v >> n) & 1u; }

}  // namespace

std::string steps_text(const step_counts &steps) {
  std::string s;
  for (long long v : steps) s += (s.empty() ? "" : " ") + std::to_string(v);
  return s;
}

std::string bar(long long done, long long total, int width) {
  done = std::llabs(done);
  total = std::llabs(total);
  const int filled = total > 0 ? static_cast<int>(std::min(done, total) * width / total) : 0;
  return "[" + std::string(filled, '#') + std::string(width - filled, '-') + "]";
}

std::string progress_line(const step_counts &steps, long long done, long long total) {
  char axes[80];
  std::snprintf(axes, sizeof axes, "%9lld %9lld %9lld %9lld ", steps[0], steps[1], steps[2], steps[3]);
  const long long pct = total ? std::min(std::llabs(done), std::llabs(total)) * 100 / std::llabs(total) : 0;
  return axes + bar(done, total, 20) + " " + std::to_string(pct) + "%";
}

std::string inputs_text(unsigned inputs) {
  std::string s;
  for (int i = 0; i < 5; i++)
    s += (i ? " pin" : "pin") + std::to_string(input_pins[i]) + "=" + std::to_string(bit(inputs, i));
  return s;
}

std::string stale_text(const x4step::status &s, std::chrono::steady_clock::time_point now) {
  std::string when = "never read";
  if (s.inputs_time.time_since_epoch().count() > 0) {
    const double age = std::chrono::duration<double>(now - s.inputs_time).count();
    char t[40];
    std::snprintf(t, sizeof t, "read %.1f s ago", age < 0 ? 0.0 : age);
    when = t;
  }
  return "(stale: no controller has the port; " + when + ")";
}

std::string key_name(int code) {
  if (code == 1) return "ESC";
  if (code > 128)
    return "key code " + std::to_string(code) + " (release of " + std::to_string(code - 128) + ")";
  return "key code " + std::to_string(code);
}

std::string errors_text(unsigned error) {
  std::string s;
  auto add = [&](unsigned bit, const char *text) {
    if (error & bit) s += (s.empty() ? "" : ", ") + std::string(text);
  };
  add(x4step::axis_error::ref_travel, "reference travel exceeded");
  add(x4step::axis_error::limit_pos, "stopped at E+");
  add(x4step::axis_error::limit_neg, "stopped at E-");
  add(x4step::axis_error::ambiguous, "ambiguous: the input serves other limits too");
  add(x4step::axis_error::ref_passed, "braked off the reference switch");
  return s;
}

std::string axis_text(const x4step::axis_status &a) {
  std::string s = std::to_string(a.position) + (a.synced ? ", synchronized" : ", not synchronized");
  if (a.running) {
    s += ", running " + std::to_string(a.velocity) + " steps/s";
    if (a.ref1) s += ", reference phase 1";
    if (a.ref2) s += ", reference phase 2";
    if (a.accelerating) s += ", accelerating";
    if (a.cruising) s += ", cruising";
    if (a.decelerating) s += ", decelerating";
  } else {
    s += ", idle";
  }
  if (a.error) s += ", error: " + errors_text(a.error);
  return s;
}

std::string positions_text(const x4step::axes_status &a, x4step::axis_set axes) {
  std::string s;
  for (x4step::axis ax : axes)
    s += (s.empty() ? "" : " ") + std::to_string(ax.number()) + "=" + std::to_string(a[ax].position);
  return s;
}

std::string coordinates_text(const x4step::axes_status &a) {
  step_counts c{};
  for (int i = 0; i < x4step::axes; i++) c[i] = a.axis[i].position;
  return steps_text(c);
}

std::string input_name(int input) {
  if (input < 1 || input > 5) return "none";
  return "input " + std::to_string(input) + " (pin " + std::to_string(input_pins[input - 1]) + ")";
}

std::string profile_text(x4step::axis axis, const x4step::profile &p) {
  // A ramp's length in seconds, to the millisecond.
  auto ramp = [](unsigned from, unsigned to, unsigned a) {
    if (a == 0) return std::string("no ramp: jumps to ") + std::to_string(to) + " steps/s";
    char t[40];
    std::snprintf(t, sizeof t, "%.3f", (to > from ? to - from : from - to) / static_cast<double>(a));
    return std::string("ramp ") + t + " s";
  };
  std::ostringstream o;
  o << "axis         " << axis.number() << "\n"
    << "v0           " << p.start_speed() << " steps/s (start)\n"
    << "ve           " << p.end_speed() << " steps/s (stop)\n"
    << "vm           " << p.top_speed() << " steps/s (maximum)\n"
    << "a0           " << p.accel() << " steps/s^2 (" << ramp(p.start_speed(), p.top_speed(), p.accel())
    << ")\n"
    << "ae           " << p.decel() << " steps/s^2 (" << ramp(p.top_speed(), p.end_speed(), p.decel())
    << ")\n";
  return o.str();
}

std::string limits_text(const x4step::switches &s, const x4step::axes_status &a) {
  std::ostringstream o;
  for (int i = 0; i < x4step::axes; i++)
    o << "axis " << i + 1 << "       ref " << input_name(s.ref[i]) << ", E+ " << input_name(s.plus[i])
      << ", E- " << input_name(s.minus[i]) << "\n";
  for (int k = 1; k <= 5; k++) {
    std::string uses;
    for (int i = 0; i < x4step::axes; i++) {
      const std::string axis = " " + std::to_string(i + 1);
      if (s.ref[i] == k) uses += ", ref" + axis;
      if (s.plus[i] == k) uses += ", E+" + axis;
      if (s.minus[i] == k) uses += ", E-" + axis;
    }
    const bool nc = s.nc >> (k - 1) & 1u;
    o << "input " << k << "      pin " << input_pins[k - 1] << (bit(a.inputs, k - 1) ? " HIGH" : " LOW");
    if (uses.empty())
      o << ", free (X4GetIn only)";
    else
      o << ", normally " << (nc ? "closed" : "open") << ", "
        << (bit(a.switches_active, k - 1) ? "active" : "idle") << uses;
    o << "\n";
  }
  return o.str();
}

std::string status_text(const x4step::status &s, const x4step::axes_status &a, const std::string &device) {
  std::ostringstream o;
  o << "device       " << device << "\n"
    << "state        " << (s.active ? "running" : "idle") << (s.loaded ? ", a move is loaded" : "")
    << (s.controlled ? ", controlled" : ", no controller") << "\n"
    << "steps        " << steps_text(s.steps) << "\n"
    << "inputs       " << inputs_text(s.inputs)
    << (s.inputs_stale ? " " + stale_text(s, std::chrono::steady_clock::now()) : "") << "\n"
    << "outputs      pin1=" << bit(s.outputs, 0) << " pin14=" << bit(s.outputs, 1)
    << " pin16(BOOST)=" << bit(s.outputs, 2) << " pin17(AKTIV)=" << bit(s.outputs, 3) << "\n"
    << "braked by    " << (s.last_brake_code ? key_name(s.last_brake_code) : "no key") << "\n"
    << "moves ended  " << s.moves_ended << "\n";
  for (int i = 0; i < x4step::axes; i++) o << "axis " << i + 1 << "       " << axis_text(a.axis[i]) << "\n";
  return o.str();
}

// Each input's level by pin, as JSON: {"15":true,...} (true: HIGH).
json_object pins_json(unsigned inputs) {
  json_object o;
  for (int i = 0; i < 5; i++) o.add(std::to_string(input_pins[i]), bit(inputs, i) == 1);
  return o;
}

std::string status_json(const x4step::status &s, const x4step::axes_status &a, const std::string &device) {
  static const char *const error_names[] = {"ref_travel", "limit_pos", "limit_neg", "ambiguous",
                                            "ref_passed"};
  const std::string axes = json_array(a.axis.begin(), a.axis.end(), [&](const x4step::axis_status &x) {
    const char *ramp = x.accelerating ? "accel" : x.cruising ? "cruise" : x.decelerating ? "decel" : "none";
    std::string errors;
    for (int b = 0; b < 5; b++)
      if (x.error >> b & 1u) errors += (errors.empty() ? "\"" : ",\"") + std::string(error_names[b]) + "\"";
    return json_object()
        .add("axis", static_cast<int>(&x - a.axis.data()) + 1)
        .add("position", x.position)
        .add("velocity", x.velocity)
        .add("running", x.running)
        .add("synced", x.synced)
        .add("homing", x.ref1   ? 1
                       : x.ref2 ? 2
                                : 0)
        .add("ramp", ramp)
        .add("error", x.error)
        .raw("errors", "[" + errors + "]")
        .str();
  });
  return json_document()
      .add("device", device)
      .add("active", s.active)
      .add("loaded", s.loaded)
      .add("controlled", s.controlled)
      .raw("steps", json_array(s.steps.begin(), s.steps.end(), [](long long v) { return std::to_string(v); }))
      .add("inputs", s.inputs)
      .add("inputs_stale", s.inputs_stale)
      .add("input_pins", pins_json(s.inputs))
      .add("outputs", s.outputs)
      .add("signal1", bit(s.outputs, 0) == 1)
      .add("signal2", bit(s.outputs, 1) == 1)
      .add("boost", bit(s.outputs, 2) == 1)
      .add("aktiv", bit(s.outputs, 3) == 1)
      .add("last_brake_code", s.last_brake_code)
      .add("moves_ended", s.moves_ended)
      .raw("axes", axes)
      .add("switches_active", a.switches_active)
      .str();
}

std::string inputs_json(const x4step::status &s, const std::string &device,
                        std::chrono::steady_clock::time_point now) {
  json_object o =
      json_document().add("device", device).add("inputs", s.inputs).add("input_pins", pins_json(s.inputs));
  o.add("stale", s.inputs_stale);
  if (s.inputs_stale && s.inputs_time.time_since_epoch().count() > 0)
    o.add("age_ms", std::chrono::duration_cast<std::chrono::milliseconds>(now - s.inputs_time).count());
  else
    o.raw("age_ms", s.inputs_stale ? "null" : "0");
  return o.str();
}

std::string monitor_json(const char *what, const x4step::status &s) {
  return json_document()
      .add("event", what)
      .add("active", s.active)
      .raw("steps", json_array(s.steps.begin(), s.steps.end(), [](long long v) { return std::to_string(v); }))
      .add("last_brake_code", s.last_brake_code)
      .add("moves_ended", s.moves_ended)
      .str();
}

std::string profile_json(x4step::axis axis, const x4step::profile &p, const std::string &device) {
  return json_document()
      .add("device", device)
      .add("axis", axis.number())
      .add("v0", p.start_speed())
      .add("ve", p.end_speed())
      .add("vm", p.top_speed())
      .add("a0", p.accel())
      .add("ae", p.decel())
      .str();
}

std::string limits_json(const x4step::switches &s, const x4step::axes_status &a, const std::string &device) {
  const int numbers[] = {1, 2, 3, 4, 5};
  const std::string axes = json_array(numbers, numbers + x4step::axes, [&](int n) {
    return json_object()
        .add("axis", n)
        .add("ref", s.ref[n - 1])
        .add("plus", s.plus[n - 1])
        .add("minus", s.minus[n - 1])
        .str();
  });
  const std::string inputs = json_array(numbers, numbers + 5, [&](int k) {
    return json_object()
        .add("input", k)
        .add("pin", input_pins[k - 1])
        .add("high", bit(a.inputs, k - 1) == 1)
        .add("nc", bit(s.nc, k - 1) == 1)
        .add("active", bit(a.switches_active, k - 1) == 1)
        .str();
  });
  return json_document()
      .add("device", device)
      .raw("axes", axes)
      .raw("inputs", inputs)
      .add("inputs_stale", a.inputs_stale)
      .str();
}

namespace {

// Who has the port, in words: its controller (PID and name when visible
// here), another parport driver, or nobody.
std::string holder_text(const port_entry &p) {
  if (p.controller)
    return "controlled by PID " + std::to_string(p.controller->pid) + " (" + p.controller->name + ")";
  if (p.controlled) return "controlled (by another user's program, or braking after its close)";
  if (!p.claimant.empty() && p.claimant != "x4step")
    return "free for x4step, but claimed by " + p.claimant + " (another parport driver)";
  return "free";
}

}  // namespace

std::string list_text(const std::vector<port_entry> &ports) {
  std::ostringstream o;
  o << "library      libx4step " << x4step::version() << "\n";
  for (const port_entry &p : ports) {
    if (p.simulated)
      o << p.device << "  LPT" << p.parport + 1 << "  ";
    else
      o << p.device << "  parport" << p.parport << "  ";
    if (!p.error.empty())
      o << p.error << "\n";
    else if (p.simulated)
      o << "ABI " << p.abi << "  simulated: a fresh port in each program that opens it, held by none here\n";
    else
      o << "ABI " << p.abi << "  " << holder_text(p) << "\n";
  }
  return o.str();
}

std::string list_json(const std::vector<port_entry> &ports) {
  const std::string rows = json_array(ports.begin(), ports.end(), [](const port_entry &p) {
    json_object o = json_object().add("device", p.device);
    if (p.simulated)
      o.add("lpt", p.parport + 1).add("simulated", true);
    else
      o.add("parport", p.parport);
    if (!p.error.empty()) return o.add("error", json_error_object(p.error, p.err)).str();
    o.add("abi", p.abi).add("controlled", p.controlled);
    if (p.controller)
      o.add("controller",
            json_object().add("pid", static_cast<long>(p.controller->pid)).add("name", p.controller->name));
    else
      o.raw("controller", "null");
    return o.raw("claimed_by", p.claimant.empty() ? "null" : json_string(p.claimant)).str();
  });
  return json_document().add("library", x4step::version()).raw("ports", rows).str();
}

const char *mode_name(x4step::output_mode m) {
  switch (m) {
    case x4step::output_mode::clock_dir:
      return "clock-dir";
    case x4step::output_mode::smc_phase:
      return "smc-phase";
    case x4step::output_mode::smc_phase_hold:
      return "smc-hold";
  }
  return "unknown";
}

std::string mode_text(x4step::output_mode m) {
  switch (m) {
    case x4step::output_mode::clock_dir:
      return "clock-dir: clock and direction signals per axis (X4Step)";
    case x4step::output_mode::smc_phase:
      return "smc-phase: SMC800/SMC1500 half-step phase drive of axes 1..3, motors off at rest";
    case x4step::output_mode::smc_phase_hold:
      return "smc-hold: SMC800/SMC1500 half-step phase drive of axes 1..3, reduced holding current at rest";
  }
  return "mode " + std::to_string(static_cast<int>(m)) + ": unknown to this x4ctl";
}

int max_freq_hz(const x4step::step_timing &t, x4step::output_mode m, int cap) {
  // The module's check: pulse + space within the period, or with the
  // symmetric clock the space within half of it (integer nanoseconds).
  const long long need = t.pulse().count() ? t.pulse().count() + t.space().count() : 2 * t.space().count();
  if (m != x4step::output_mode::clock_dir || need <= 0) return cap;
  return static_cast<int>(std::min<long long>(cap, 1000000000LL / need));
}

std::string timing_text(const x4step::step_timing &t, x4step::output_mode m, const std::string &device) {
  const bool phase = m != x4step::output_mode::clock_dir;
  std::ostringstream o;
  o << "device       " << device << "\n"
    << "pulse        " << t.pulse().count() << " ns" << (t.pulse().count() ? "" : " (symmetric clock)")
    << "\n"
    << "space        " << t.space().count() << " ns\n"
    << "dir setup    " << t.dir_setup().count() << " ns\n"
    << "dir hold     " << t.dir_hold().count() << " ns\n"
    << "max freq     " << max_freq_hz(t, m) << " Hz"
    << (phase ? std::string(" (") + mode_name(m) + " mode: pulse and space do not apply)" : "") << "\n";
  return o.str();
}

std::string timing_json(const x4step::step_timing &t, x4step::output_mode m, const std::string &device) {
  return json_document()
      .add("device", device)
      .add("pulse_ns", t.pulse().count())
      .add("space_ns", t.space().count())
      .add("dir_setup_ns", t.dir_setup().count())
      .add("dir_hold_ns", t.dir_hold().count())
      .add("mode", mode_name(m))
      .add("max_freq_hz", max_freq_hz(t, m))
      .str();
}

std::string mode_json(x4step::output_mode m, const std::string &device) {
  return json_document()
      .add("device", device)
      .add("mode", mode_name(m))
      .add("description", mode_text(m))
      .str();
}

}  // namespace x4ctl
