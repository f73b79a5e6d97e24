// SPDX-License-Identifier: GPL-2.0
// x4grbl: GRBL 1.1's error and alarm codes (gnea/grbl doc/csv), and which
// error a refusal of x4step's interpreter is closest to.
#ifndef X4GRBL_CODES_HPP
#define X4GRBL_CODES_HPP

#include <string>

namespace x4grbl {

namespace error_code {
constexpr int expected_letter = 1, bad_number = 2, invalid_statement = 3, negative_value = 4,
              setting_disabled = 5, not_idle = 8, gcode_lock = 9, line_overflow = 11, travel_exceeded = 15,
              invalid_jog = 16, unsupported = 20, modal_group = 21, undefined_feed = 22, integer_needed = 23,
              repeated_word = 25, no_axis_words = 26, line_number = 27, value_word_missing = 28,
              g53_motion = 30, axis_words_unused = 31, invalid_target = 33, arc_radius = 34,
              arc_offset_missing = 35, unused_words = 36;
}  // namespace error_code

namespace alarm_code {
constexpr int hard_limit = 1, soft_limit = 2, abort_cycle = 3, probe_initial = 4, probe_contact = 5,
              homing_reset = 6, homing_not_found = 9;
}  // namespace alarm_code

/// The GRBL error closest to a message of x4step's interpreter or planner.
inline int error_code_of(const std::string &why) {
  using namespace error_code;
  const auto has = [&why](const char *s) { return why.find(s) != std::string::npos; };
  if (has("feed rate of zero") || has("needs an F word")) return undefined_feed;
  if (has("G53 needs")) return g53_motion;
  if (has("without a G code that uses them") || has("G80 takes none")) return axis_words_unused;
  if (has("with no ") && has("to use it")) return unused_words;
  if (has("at least one axis word")) return no_axis_words;
  if (has("radius")) return arc_radius;
  if (has("end point is its start point")) return invalid_target;
  if (has("needs R or the centre") || has("word missing for an arc")) return arc_offset_missing;
  if (has("needs P") || has("needs L") || has("needs Q") || has("needs R") || has("needs Z"))
    return value_word_missing;
  if (has("line number")) return line_number;
  if (has("negative")) return negative_value;
  if (has("whole number")) return integer_needed;
  if (has("bad number")) return bad_number;
  if (has("multiple") || has("one of them per line")) return modal_group;
  if (has("twice") || has("repeated")) return repeated_word;
  return unsupported;
}

}  // namespace x4grbl

#endif  // X4GRBL_CODES_HPP
