// SPDX-License-Identifier: GPL-2.0
// x4ctl: the values of options and operands (values.hpp).
#include "values.hpp"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "cli.hpp"
#include "show.hpp"

namespace x4ctl {

using std::chrono::milliseconds;

int parse_lpt(const std::string &text, const std::string &prefix) {
  const long v = parse_number(text, prefix + "port");
  if (v < 1 || v > 4) throw usage_error(prefix + "port " + text + " out of range: use 1 to 4 (LPT1..LPT4)");
  return static_cast<int>(v);
}

int parse_freq(const std::string &text, const std::string &prefix) {
  const long v = parse_number(text, prefix + "frequency");
  if (v > x4step::freq_max_hz) throw usage_error(prefix + message(x4step::errc::freq_too_high));
  if (v < x4step::freq_min_hz) throw usage_error(prefix + message(x4step::errc::freq_too_low));
  return static_cast<int>(v);
}

int parse_ramp(const std::string &text, const std::string &prefix) {
  const long v = parse_number(text, prefix + "ramp");
  if (v > x4step::ramp_max.count()) throw usage_error(prefix + message(x4step::errc::ramp_too_high));
  if (v < 0)
    throw usage_error(prefix + "ramp " + text + " out of range: use 0 to " +
                      std::to_string(x4step::ramp_max.count()) + " ms");
  return static_cast<int>(v);
}

long parse_steps(const std::string &text, const std::string &prefix) {
  const long v = parse_number(text, prefix + "steps");
  if (v > x4step::steps_max || v < -x4step::steps_max)
    throw usage_error(prefix + message(x4step::errc::steps_too_high));
  return v;
}

x4step::axis parse_axis(const std::string &text, const std::string &prefix) {
  const long v = parse_number(text, prefix + "axis");
  if (v < 1 || v > x4step::axes) throw usage_error(prefix + "axis " + text + " out of range: use 1 to 4");
  return x4step::axis(static_cast<int>(v));
}

milliseconds parse_time(const std::string &text, const std::string &prefix) {
  const long v = parse_number(text, prefix + "time");
  if (v < 0) throw usage_error(prefix + "time " + text + " out of range: use 0 ms or more");
  return milliseconds(v);
}

// A step time of `timing`: 0..1 ms; a pulse 0 (symmetric clock) or at least 1 us.
std::chrono::nanoseconds parse_ns(const std::string &text, const std::string &what, bool pulse,
                                  const std::string &prefix) {
  const long v = parse_number(text, prefix + what);
  const long timing_max_ns = x4step::timing_max.count(), pulse_min_ns = x4step::pulse_min.count();
  if (pulse && (v < 0 || v > timing_max_ns || (v != 0 && v < pulse_min_ns)))
    throw usage_error(prefix + what + " " + text + " out of range: use 0 (symmetric clock) or " +
                      std::to_string(pulse_min_ns) + " to " + std::to_string(timing_max_ns) + " ns");
  if (v < 0 || v > timing_max_ns)
    throw usage_error(prefix + what + " " + text + " out of range: use 0 to " +
                      std::to_string(timing_max_ns) + " ns");
  return std::chrono::nanoseconds(v);
}

x4step::output_mode parse_mode(const std::string &text, const std::string &prefix) {
  // step-dir: the machine file's first name for clock-dir (docs: clock-dir).
  if (text == "step-dir") return x4step::output_mode::clock_dir;
  std::string names;
  for (const auto m : output_modes) {
    if (text == mode_name(m)) return m;
    names += std::string(names.empty() ? "" : ", ") + mode_name(m);
  }
  throw usage_error(prefix + "no mode '" + text + "': use " + names);
}

// A number above 0 (not necessarily whole), else "WHAT 'TEXT': use a number above 0 UNIT".
double parse_positive(const std::string &text, const std::string &what, const std::string &unit,
                      const std::string &prefix) {
  char *end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end || !std::isfinite(v) || v <= 0)
    throw usage_error(prefix + what + " '" + text + "': use a number above 0" + unit);
  return v;
}

bool is_axis_letter(char ch) { return ch && std::strchr("XYZABCxyzabc", ch); }

char upper(char ch) { return static_cast<char>(std::toupper(static_cast<unsigned char>(ch))); }

// A number in min..max, else "WHAT TEXT out of range: use MIN to MAX UNIT".
long parse_range(const std::string &text, const std::string &what, long min, long max,
                 const std::string &unit, const std::string &prefix) {
  const long v = parse_number(text, prefix + what);
  if (v < min || v > max)
    throw usage_error(prefix + what + " " + text + " out of range: use " + std::to_string(min) + " to " +
                      std::to_string(max) + unit);
  return v;
}

// A coordinate or distance of the axes' own moves: signed 32 bits.
long parse_position(const std::string &text, const std::string &what, const std::string &prefix) {
  return parse_range(text, what, INT32_MIN, INT32_MAX, "", prefix);
}

unsigned parse_speed(const std::string &text, const std::string &what, long min, const std::string &prefix) {
  return static_cast<unsigned>(parse_range(text, what, min, x4step::vel_max, " steps/s", prefix));
}

unsigned parse_acceleration(const std::string &text, const std::string &what, const std::string &prefix) {
  return static_cast<unsigned>(parse_range(text, what, 0, x4step::acc_max, " steps/s^2", prefix));
}

// A signed reference speed: the sign is the direction.
int parse_vref(const std::string &text, const std::string &what, const std::string &prefix) {
  const long v = parse_number(text, prefix + what);
  const long max = x4step::vel_max;
  if (v == 0 || v < -max || v > max)
    throw usage_error(prefix + what + " " + text + " out of range: use -" + std::to_string(max) +
                      " to -1 or 1 to " + std::to_string(max) + " steps/s (the sign is the direction)");
  return static_cast<int>(v);
}

// An input 1..5, or 0 or "none".
int parse_input(const std::string &text, const std::string &prefix) {
  if (text == "none") return 0;
  const long v = parse_number(text, prefix + "input");
  if (v < 0 || v > 5)
    throw usage_error(prefix + "input " + text +
                      " out of range: use 1 to 5 (pins 15, 13, 12, 10, 11), or 0 for none");
  return static_cast<int>(v);
}

// Normally closed inputs: "none", a list "1,3", or a mask "0x05".
unsigned parse_nc(const std::string &text, const std::string &prefix) {
  if (text == "none") return 0;
  if (text.rfind("0x", 0) == 0) {
    char *end = nullptr;
    const unsigned long v = std::strtoul(text.c_str() + 2, &end, 16);
    if (text.size() == 2 || *end || v > 0x1f)
      throw usage_error(prefix + "nc mask " + text + " out of range: use 0x00 to 0x1f (bit k: input k+1)");
    return static_cast<unsigned>(v);
  }
  unsigned mask = 0;
  size_t from = 0;
  for (;;) {
    const size_t comma = text.find(',', from);
    const std::string one = text.substr(from, comma == std::string::npos ? comma : comma - from);
    const int in = parse_input(one, prefix + "--nc ");
    if (in == 0) throw usage_error(prefix + "--nc input " + one + ": use 1 to 5, e.g. --nc 1,3");
    mask |= 1u << (in - 1);
    if (comma == std::string::npos) return mask;
    from = comma + 1;
  }
}

// AXIS... as a mask: each 1..4, once.
x4step::axis_set parse_axes(const std::vector<std::string> &ops, const std::string &prefix) {
  x4step::axis_set axes;
  for (const auto &o : ops) {
    const x4step::axis a = parse_axis(o, prefix);
    if (axes.contains(a)) throw usage_error(prefix + "axis " + o + " given twice");
    axes |= a;
  }
  return axes;
}

}  // namespace x4ctl
