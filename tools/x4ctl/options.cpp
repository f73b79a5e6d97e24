// SPDX-License-Identifier: GPL-2.0
// x4ctl: options that several commands share (options.hpp).
#include "options.hpp"

#include "values.hpp"

namespace x4ctl {

option freq_option() {
  return {"freq", 'f', "HZ",
          "frequency of the leader axis, " + std::to_string(x4step::freq_min_hz) + ".." +
              std::to_string(x4step::freq_max_hz) + " Hz (default " + std::to_string(default_freq_hz) + ")",
          [](parse_state &s, const option_value &o) { s.freq = parse_freq(o.value, s.prefix); }};
}

option ramp_option() {
  return ramp_option("ramp time, 0.." + std::to_string(x4step::ramp_max.count()) +
                     " ms and at most the frequency in Hz\n"
                     "(default 50, or the frequency if that is lower)");
}

option ramp_option(const std::string &help) {
  return {"ramp", 'r', "MS", help,
          [](parse_state &s, const option_value &o) { s.ramp = parse_ramp(o.value, s.prefix); }};
}

option wait_option(const std::string &help) {
  return {"wait", 'w', "", help, [](parse_state &s, const option_value &) { s.c.wait = true; }};
}

option time_option(const std::string &help) {
  return {"time", 't', "MS", help,
          [](parse_state &s, const option_value &o) { s.c.time = parse_time(o.value, s.prefix); }};
}

option json_option(const std::string &help) {
  return {"json", 'j', "", help, [](parse_state &s, const option_value &) { s.c.json = true; }};
}

option machine_option(const std::string &help) {
  return {"machine", 'm', "FILE", help, [](parse_state &s, const option_value &o) {
            if (o.value.empty()) throw usage_error(s.prefix + "--machine needs a file");
            s.c.machine = o.value;
          }};
}

option feed_option(const std::string &help) {
  return {"feed", 0, "F", help, [](parse_state &s, const option_value &o) {
            s.c.feed = parse_positive(o.value, "feed", " units/min", s.prefix);
          }};
}

option override_option() {
  return {"override", 'o', "PCT", "feed override, 1..200 percent (100)",
          [](parse_state &s, const option_value &o) {
            s.c.override_percent =
                static_cast<unsigned>(parse_range(o.value, "override", 1, 200, " %", s.prefix));
          }};
}

option check_option(const std::string &help) {
  return {"check", 'c', "", help, [](parse_state &s, const option_value &) { s.c.check = true; }};
}

option no_pause_option(const std::string &help) {
  return {"no-pause", 0, "", help, [](parse_state &s, const option_value &) { s.c.no_pause = true; }};
}

const char *const machine_file_help =
    "the machine file (default: $X4STEP_MACHINE, else\n"
    "/etc/x4step/machine.ini)";

}  // namespace x4ctl
