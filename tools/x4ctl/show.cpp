// SPDX-License-Identifier: GPL-2.0
// x4ctl: formatting of states, steps and progress.
#include "show.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <sstream>

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

std::string key_name(int code) {
  if (code == 1) return "ESC";
  if (code > 128)
    return "key code " + std::to_string(code) + " (release of " + std::to_string(code - 128) + ")";
  return "key code " + std::to_string(code);
}

std::string status_text(const x4step::status &s, const std::string &device) {
  std::ostringstream o;
  o << "device       " << device << "\n"
    << "state        " << (s.active ? "running" : "idle") << (s.loaded ? ", a move is loaded" : "")
    << (s.controlled ? ", controlled" : ", no controller") << "\n"
    << "steps        " << steps_text(s.steps) << "\n"
    << "inputs       " << inputs_text(s.inputs) << "\n"
    << "outputs      pin1=" << bit(s.outputs, 0) << " pin14=" << bit(s.outputs, 1)
    << " pin16(BOOST)=" << bit(s.outputs, 2) << " pin17(AKTIV)=" << bit(s.outputs, 3) << "\n"
    << "braked by    " << (s.last_brake_code ? key_name(s.last_brake_code) : "no key") << "\n"
    << "moves ended  " << s.moves_ended << "\n";
  return o.str();
}

std::string json_string(const std::string &s) {
  std::string r = "\"";
  for (unsigned char c : s) {
    if (c == '"' || c == '\\') {
      r += '\\';
      r += static_cast<char>(c);
    } else if (c < 0x20) {
      char esc[8];
      std::snprintf(esc, sizeof esc, "\\u%04x", c);
      r += esc;
    } else {
      r += static_cast<char>(c);
    }
  }
  return r + "\"";
}

std::string status_json(const x4step::status &s, const std::string &device) {
  auto boolean = [](bool b) { return b ? "true" : "false"; };
  std::ostringstream o;
  o << "{\"device\":" << json_string(device) << ",\"active\":" << boolean(s.active)
    << ",\"loaded\":" << boolean(s.loaded) << ",\"controlled\":" << boolean(s.controlled) << ",\"steps\":[";
  for (int i = 0; i < x4step::axes; i++) o << (i ? "," : "") << s.steps[i];
  o << "],\"inputs\":" << s.inputs << ",\"input_pins\":{";
  for (int i = 0; i < 5; i++) o << (i ? "," : "") << "\"" << input_pins[i] << "\":" << bit(s.inputs, i);
  o << "},\"outputs\":" << s.outputs << ",\"signal1\":" << bit(s.outputs, 0)
    << ",\"signal2\":" << bit(s.outputs, 1) << ",\"boost\":" << bit(s.outputs, 2)
    << ",\"aktiv\":" << bit(s.outputs, 3) << ",\"last_brake_code\":" << s.last_brake_code
    << ",\"moves_ended\":" << s.moves_ended << "}";
  return o.str();
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

int max_freq_hz(const x4step::step_timing &t, x4step::output_mode m) {
  // The module's check: pulse + space within the period, or with the
  // symmetric clock the space within half of it (integer nanoseconds).
  const long long need = t.pulse.count() ? t.pulse.count() + t.space.count() : 2 * t.space.count();
  if (m != x4step::output_mode::clock_dir || need <= 0) return x4step::freq_max_hz;
  return static_cast<int>(std::min<long long>(x4step::freq_max_hz, 1000000000LL / need));
}

std::string timing_text(const x4step::step_timing &t, x4step::output_mode m, const std::string &device) {
  const bool phase = m != x4step::output_mode::clock_dir;
  std::ostringstream o;
  o << "device       " << device << "\n"
    << "pulse        " << t.pulse.count() << " ns" << (t.pulse.count() ? "" : " (symmetric clock)") << "\n"
    << "space        " << t.space.count() << " ns\n"
    << "dir setup    " << t.dir_setup.count() << " ns\n"
    << "dir hold     " << t.dir_hold.count() << " ns\n"
    << "max freq     " << max_freq_hz(t, m) << " Hz"
    << (phase ? std::string(" (") + mode_name(m) + " mode: pulse and space do not apply)" : "") << "\n";
  return o.str();
}

std::string timing_json(const x4step::step_timing &t, x4step::output_mode m, const std::string &device) {
  std::ostringstream o;
  o << "{\"device\":" << json_string(device) << ",\"pulse_ns\":" << t.pulse.count()
    << ",\"space_ns\":" << t.space.count() << ",\"dir_setup_ns\":" << t.dir_setup.count()
    << ",\"dir_hold_ns\":" << t.dir_hold.count() << ",\"mode\":" << json_string(mode_name(m))
    << ",\"max_freq_hz\":" << max_freq_hz(t, m) << "}";
  return o.str();
}

}  // namespace x4ctl
