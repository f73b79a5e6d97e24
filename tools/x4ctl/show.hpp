// SPDX-License-Identifier: GPL-2.0
// x4ctl: how states, steps and progress look, as text and as JSON.
#ifndef X4CTL_SHOW_HPP
#define X4CTL_SHOW_HPP

#include <array>
#include <string>

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
/// "ESC" for 1, else "key code N" (release codes say so).
std::string key_name(int code);
/// Multi-line text of `x4ctl status`.
std::string status_text(const x4step::status &s, const std::string &device);
/// One line of JSON for `x4ctl status --json`.
std::string status_json(const x4step::status &s, const std::string &device);
/// A JSON string literal.
std::string json_string(const std::string &s);

/// Every output mode, in the order the help lists them.
constexpr x4step::output_mode output_modes[] = {
    x4step::output_mode::clock_dir, x4step::output_mode::smc_phase, x4step::output_mode::smc_phase_hold};
/// "clock-dir", "smc-phase", "smc-hold": the names on the command line.
const char *mode_name(x4step::output_mode m);
/// One line of `x4ctl mode`: "smc-phase: SMC800/SMC1500 half-step phase drive, ...".
std::string mode_text(x4step::output_mode m);
/// The highest frequency whose period fits the timing (at most 20000 Hz);
/// the phase modes have no pulse, so no limit but that.
int max_freq_hz(const x4step::step_timing &t, x4step::output_mode m);
/// Multi-line text of `x4ctl timing`.
std::string timing_text(const x4step::step_timing &t, x4step::output_mode m, const std::string &device);
/// One line of JSON for `x4ctl timing --json`.
std::string timing_json(const x4step::step_timing &t, x4step::output_mode m, const std::string &device);

}  // namespace x4ctl

#endif  // X4CTL_SHOW_HPP
