// SPDX-License-Identifier: GPL-2.0
// x4ctl: how states, steps and progress look, as text and as JSON.
#ifndef X4CTL_SHOW_HPP
#define X4CTL_SHOW_HPP

#include <array>
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "../json_string.hpp"
#include "ports.hpp"
#include "x4step.hpp"

namespace x4ctl {

using step_counts = std::array<long long, x4step::axes>;

/// "1000 800 600 400"
std::string steps_text(const step_counts &steps);
/// "[#####-----]" for done of total (absolute values), width characters inside.
std::string bar(long long done, long long total, int width);
/// Live progress line of a move: per-axis steps, a bar, percent.
std::string progress_line(const step_counts &steps, long long done, long long total);
/// "pin15=1 pin13=0 pin12=0 pin10=1 pin11=0"
std::string inputs_text(unsigned inputs);
/// For inputs that were not read now (s.inputs_stale): "(stale: no
/// controller has the port; read 2.5 s ago)", or "... never read)".
std::string stale_text(const x4step::status &s, std::chrono::steady_clock::time_point now);
/// "ESC" for 1, else "key code N" (release codes say so).
std::string key_name(int code);
/// Multi-line text of `x4ctl status`.
std::string status_text(const x4step::status &s, const x4step::axes_status &a, const std::string &device);
/// One line of JSON for `x4ctl status --json` (see json.hpp for the style).
std::string status_json(const x4step::status &s, const x4step::axes_status &a, const std::string &device);
/// One line of JSON for `x4ctl in --json`: the levels, stale or not, and
/// their age (null: never read).
std::string inputs_json(const x4step::status &s, const std::string &device,
                        std::chrono::steady_clock::time_point now);

/// "1200, synchronized, running 850 steps/s accelerating, error: stopped at E+"
std::string axis_text(const x4step::axis_status &a);
/// "stopped at E+, ambiguous: ..." for x4step::axis_error bits; "" for 0.
std::string errors_text(unsigned error);
/// "1=1200 2=-5" for the axes.
std::string positions_text(const x4step::axes_status &a, x4step::axis_set axes);
/// "1000 -500 0 0": every coordinate.
std::string coordinates_text(const x4step::axes_status &a);
/// A line of `x4ctl monitor --json`: what (idle, running, started, ended)
/// and the status then.
std::string monitor_json(const char *what, const x4step::status &s);
/// Multi-line text of `x4ctl profile`, and its JSON.
std::string profile_text(x4step::axis axis, const x4step::profile &p);
std::string profile_json(x4step::axis axis, const x4step::profile &p, const std::string &device);
/// Multi-line text of `x4ctl limits`: each axis' switches, each input.
std::string limits_text(const x4step::switches &s, const x4step::axes_status &a);
std::string limits_json(const x4step::switches &s, const x4step::axes_status &a, const std::string &device);
/// "input 3 (pin 12)"; "none" for 0.
std::string input_name(int input);
/// A JSON string literal.
using x4tools::json_string;

/// One line of `x4ctl watch`: "#12 105.001234 move ended: axes 1 2, braked, at 100 -50 0 0".
std::string event_text(const x4step::event &e);
/// The same as one line of JSON.
std::string event_json(const x4step::event &e);
/// What `x4ctl watch` says of events it missed (n > 0), as text or JSON.
std::string missed_text(std::uint64_t n);
std::string missed_json(std::uint64_t n);

/// `x4ctl list`, as text (a line per port) and as JSON.
std::string list_text(const std::vector<port_entry> &ports);
std::string list_json(const std::vector<port_entry> &ports);

/// Every output mode, in the order the help lists them.
constexpr x4step::output_mode output_modes[] = {
    x4step::output_mode::clock_dir, x4step::output_mode::smc_phase, x4step::output_mode::smc_phase_hold};
/// "clock-dir", "smc-phase", "smc-hold": the names on the command line.
const char *mode_name(x4step::output_mode m);
/// One line of `x4ctl mode`: "smc-phase: SMC800/SMC1500 half-step phase drive, ...".
std::string mode_text(x4step::output_mode m);
/// `x4ctl mode --json`.
std::string mode_json(x4step::output_mode m, const std::string &device);
/// The highest frequency whose period fits the timing (at most cap, the
/// X4Step moves' 20000 Hz); the phase modes have no pulse, so no limit but cap.
int max_freq_hz(const x4step::step_timing &t, x4step::output_mode m, int cap = x4step::freq_max_hz);
/// Multi-line text of `x4ctl timing`.
std::string timing_text(const x4step::step_timing &t, x4step::output_mode m, const std::string &device);
/// One line of JSON for `x4ctl timing --json`.
std::string timing_json(const x4step::step_timing &t, x4step::output_mode m, const std::string &device);

}  // namespace x4ctl

#endif  // X4CTL_SHOW_HPP
