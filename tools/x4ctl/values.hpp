// SPDX-License-Identifier: GPL-2.0
// x4ctl: the values of options and operands, each checked against its
// range: a usage_error names what is wrong and what to use instead. prefix
// ("move: ") starts every message.
#ifndef X4CTL_VALUES_HPP
#define X4CTL_VALUES_HPP

#include <chrono>
#include <string>
#include <vector>

#include "x4step.hpp"

namespace x4ctl {

int parse_lpt(const std::string &text, const std::string &prefix);
int parse_freq(const std::string &text, const std::string &prefix);
int parse_ramp(const std::string &text, const std::string &prefix);
long parse_steps(const std::string &text, const std::string &prefix);
x4step::axis parse_axis(const std::string &text, const std::string &prefix);
std::chrono::milliseconds parse_time(const std::string &text, const std::string &prefix);
/// A step time of `timing`: 0..1 ms; a pulse 0 (symmetric clock) or at least 1 us.
std::chrono::nanoseconds parse_ns(const std::string &text, const std::string &what, bool pulse,
                                  const std::string &prefix);
x4step::output_mode parse_mode(const std::string &text, const std::string &prefix);
/// A number above 0 (not necessarily whole), else "WHAT 'TEXT': use a number above 0 UNIT".
double parse_positive(const std::string &text, const std::string &what, const std::string &unit,
                      const std::string &prefix);
bool is_axis_letter(char ch);
char upper(char ch);
/// A number in min..max, else "WHAT TEXT out of range: use MIN to MAX UNIT".
long parse_range(const std::string &text, const std::string &what, long min, long max,
                 const std::string &unit, const std::string &prefix);
/// A coordinate or distance of the axes' own moves: signed 32 bits.
long parse_position(const std::string &text, const std::string &what, const std::string &prefix);
unsigned parse_speed(const std::string &text, const std::string &what, long min, const std::string &prefix);
unsigned parse_acceleration(const std::string &text, const std::string &what, const std::string &prefix);
/// A signed reference speed: the sign is the direction.
int parse_vref(const std::string &text, const std::string &what, const std::string &prefix);
/// An input 1..5, or 0 or "none".
int parse_input(const std::string &text, const std::string &prefix);
/// Normally closed inputs: "none", a list "1,3", or a mask "0x05".
unsigned parse_nc(const std::string &text, const std::string &prefix);
/// AXIS... as a set: each 1..4, once.
x4step::axis_set parse_axes(const std::vector<std::string> &ops, const std::string &prefix);

}  // namespace x4ctl

#endif  // X4CTL_VALUES_HPP
