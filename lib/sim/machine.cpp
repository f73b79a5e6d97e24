// SPDX-License-Identifier: LGPL-2.1-or-later
// libx4step: the simulated port's machine (machine.hpp): its file, its
// input script, and its axes and switches as x4vport moves them.
#include "machine.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "x4step.hpp"

namespace x4step::sim {
namespace {

constexpr std::int64_t pos_max = std::int64_t{1} << 62;  // as x4vport
constexpr int input_pins[5] = {15, 13, 12, 10, 11};      // X4GetIn bits 0..4

[[noreturn]] void refuse(const std::string &where, const std::string &what) {
  throw error(make_error_code(errc::lpt_not_found), where + ": " + what);
}

const char *kind_name(machine_switch::kind k) {
  switch (k) {
    case machine_switch::kind::ref:
      return "REF";
    case machine_switch::kind::plus:
      return "E+";
    case machine_switch::kind::probe:
      return "probe";
    default:
      return "E-";
  }
}

std::string pin_of(int bit) { return "pin " + std::to_string(input_pins[bit]); }

// "10" or "pin10": the X4GetIn bit of an input pin.
int input_bit(const std::string &w, const std::string &where) {
  const std::string num = w.rfind("pin", 0) == 0 ? w.substr(3) : w;
  char *end = nullptr;
  errno = 0;
  const long n = std::strtol(num.c_str(), &end, 10);
  if (!num.empty() && *end == '\0' && !errno)
    for (int b = 0; b < 5; b++)
      if (input_pins[b] == n) return b;
  refuse(where, "'" + w + "' is not an input pin: the inputs are pins 10, 11, 12, 13 and 15");
}

std::int64_t steps(const std::string &w, const char *what, const std::string &where) {
  char *end = nullptr;
  errno = 0;
  const long long n = std::strtoll(w.c_str(), &end, 10);
  if (w.empty() || *end != '\0' || errno || n < -pos_max || n > pos_max)
    refuse(where, std::string(what) + " '" + w + "' is not a whole number of steps in -2^62..2^62");
  return n;
}

int axis_of(const std::string &w, const std::string &where) {
  if (w.size() != 1 || w[0] < '1' || w[0] > '4') refuse(where, "axis '" + w + "': use 1, 2, 3 or 4");
  return w[0] - '1';
}

// "T_MS": a time in ms (fractions allowed) as engine ns.
std::uint64_t time_ns(const std::string &w, const std::string &where) {
  char *end = nullptr;
  errno = 0;
  const double ms = std::strtod(w.c_str(), &end);
  if (w.empty() || *end != '\0' || errno || !(ms >= 0) || ms > 1e12)
    refuse(where, "time '" + w + "' is not a time in ms (0 or more, e.g. 250 or 12.5)");
  return static_cast<std::uint64_t>(std::llround(ms * 1e6));
}

// "PIN=LEVEL" into c.
void pin_level(const std::string &w, input_change &c, const std::string &where) {
  const auto eq = w.find('=');
  const std::string level = eq == std::string::npos ? "" : w.substr(eq + 1);
  if (level != "0" && level != "1")
    refuse(where, "'" + w + "': set an input as PIN=0 or PIN=1, e.g. pin15=1");
  const int b = input_bit(w.substr(0, eq), where);
  c.mask |= 1u << b;
  if (level == "1") c.levels |= 1u << b;
}

std::vector<std::string> words(const std::string &line) {
  std::istringstream in(line.substr(0, line.find('#')));
  std::vector<std::string> w;
  for (std::string s; in >> s;) w.push_back(s);
  return w;
}

}  // namespace

void machine::read(std::istream &in, const std::string &name) {
  int n = 0;
  for (std::string line; std::getline(in, line);) {
    const std::string where = name + ":" + std::to_string(++n);
    const auto w = words(line);
    if (w.empty()) continue;
    const std::string &key = w[0];
    if (key == "ref" || key == "probe" || key == "e+" || key == "e-") {
      // ref|probe AXIS below|above AT PIN no|nc [hyst N]; e+/e- AXIS AT PIN no|nc [hyst N]
      machine_switch s;
      s.line = n;
      const bool ref = key == "ref" || key == "probe";
      const std::size_t k = ref ? 3 : 2;  // index of AT
      if (w.size() != k + 3 && !(w.size() == k + 5 && w[k + 3] == "hyst"))
        refuse(where, ref ? "write a " + std::string(key == "ref" ? "REF" : "probe") + " switch as: " + key +
                                " AXIS below|above AT PIN no|nc [hyst STEPS]"
                          : "write a limit switch as: " + key + " AXIS AT PIN no|nc [hyst STEPS]");
      s.what = key == "probe" ? machine_switch::kind::probe
               : key == "ref" ? machine_switch::kind::ref
               : key == "e+"  ? machine_switch::kind::plus
                              : machine_switch::kind::minus;
      s.axis = axis_of(w[1], where);
      if (ref && w[2] != "below" && w[2] != "above")
        refuse(where, std::string(key == "ref" ? "REF" : "probe") + " side '" + w[2] +
                          "': use below (active at AT and under) or above (at AT and over)");
      s.above = ref ? w[2] == "above" : s.what == machine_switch::kind::plus;
      s.at = steps(w[k], "position", where);
      s.bit = input_bit(w[k + 1], where);
      if (w[k + 2] != "no" && w[k + 2] != "nc")
        refuse(where, "polarity '" + w[k + 2] + "': use no (HIGH while pressed) or nc (LOW while pressed)");
      s.nc = w[k + 2] == "nc";
      if (w.size() == k + 5) {
        s.hyst = steps(w[k + 4], "hysteresis", where);
        if (s.hyst < 0) refuse(where, "hysteresis " + w[k + 4] + ": use 0 or more steps");
      }
      add_switch(s, name);
    } else if (key == "position") {
      if (w.size() != 3) refuse(where, "write a start position as: position AXIS STEPS");
      pos_[axis_of(w[1], where)] = steps(w[2], "position", where);
    } else if (key == "input") {
      if (w.size() < 3)
        refuse(where, "write scripted inputs as: input T_MS PIN=LEVEL..., e.g. input 250 pin15=1");
      input_change c{time_ns(w[1], where), 0, 0};
      for (std::size_t i = 2; i < w.size(); i++) pin_level(w[i], c, where);
      add_change(c, where);
    } else {
      refuse(where, "'" + key + "' is not a machine line: use ref, e+, e-, probe, position or input");
    }
  }
  update_switches();
}

void machine::add_script(const std::string &spec) {
  std::istringstream in(spec);
  int n = 0;
  for (std::string item; std::getline(in, item, ',');) {
    const std::string where = "X4STEP_SIM_INPUTS item " + std::to_string(++n) + " '" + item + "'";
    const auto colon = item.find(':');
    if (colon == std::string::npos) refuse(where, "write each item as T_MS:PIN=LEVEL, e.g. 250:pin15=1");
    input_change c{time_ns(item.substr(0, colon), where), 0, 0};
    pin_level(item.substr(colon + 1), c, where);
    add_change(c, where);
  }
}

// A switch against those before it: one of each kind per axis, REF between
// the limits, and one polarity per input (the engine's NO/NC is per input,
// and switches in parallel are one contact to it).
void machine::add_switch(machine_switch s, const std::string &name) {
  const std::string where = name + ":" + std::to_string(s.line);
  const std::string ax = "axis " + std::to_string(s.axis + 1);
  for (const machine_switch &o : sw_) {
    const std::string there = " (line " + std::to_string(o.line) + ")";
    if (o.bit == s.bit && o.nc != s.nc)
      refuse(where, pin_of(s.bit) + " has a " + (o.nc ? "nc" : "no") + " switch already" + there +
                        ": switches on one input are in parallel, give them one polarity");
    if (o.axis == s.axis && o.what == s.what)
      refuse(where, ax + " has its " + kind_name(s.what) + " switch already" + there + ": one per axis");
    if (o.axis != s.axis) continue;
    const machine_switch *lo = nullptr, *hi = nullptr, *ref = nullptr;
    for (const machine_switch *p : {&o, static_cast<const machine_switch *>(&s)}) {
      if (p->what == machine_switch::kind::minus) lo = p;
      if (p->what == machine_switch::kind::plus) hi = p;
      if (p->what == machine_switch::kind::ref) ref = p;
    }
    if (lo && hi && lo->at >= hi->at)
      refuse(where, ax + ": E- at " + std::to_string(lo->at) + " is not below E+ at " +
                        std::to_string(hi->at) + there + ": E- must be the lower end of the travel");
    if (ref && ((lo && ref->at < lo->at) || (hi && ref->at > hi->at)))
      refuse(where, ax + ": REF at " + std::to_string(ref->at) + " lies outside E-..E+" + there +
                        ": place it between the limit switches");
  }
  for (const input_change &c : script_)
    if (c.mask & (1u << s.bit))
      refuse(where, pin_of(s.bit) + " is set by the input script: a switch drives it, script another input");
  driven_ |= 1u << s.bit;
  if (s.nc) nc_ |= 1u << s.bit;
  sw_.push_back(s);
}

void machine::add_change(input_change c, const std::string &where) {
  if (const unsigned both = c.mask & driven_) {
    int b = 0;
    while (!(both & (1u << b))) b++;
    refuse(where, pin_of(b) + " is driven by a switch: script another input");
  }
  const auto at =
      std::upper_bound(script_.begin() + static_cast<std::ptrdiff_t>(script_next_), script_.end(), c,
                       [](const input_change &a, const input_change &b) { return a.t_ns < b.t_ns; });
  script_.insert(at, c);
}

void machine::write_data(std::uint8_t data) {
  const std::uint8_t rise = data & ~data_ & 0xaa;
  data_ = data;
  if (!rise) return;
  for (int i = 0; i < 4; i++)
    if (rise & (2u << (2 * i))) pos_[i] += (data & (1u << (2 * i))) ? 1 : -1;
  update_switches();
}

// x4vport's x4v_update_locked(): a switch is active past its position,
// and stays so until more than hyst steps back.
void machine::update_switches() {
  for (machine_switch &s : sw_) {
    const std::int64_t p = pos_[static_cast<std::size_t>(s.axis)];
    const std::int64_t h = s.active ? s.hyst : 0;
    s.active = s.above ? p >= s.at - h : p <= s.at + h;
  }
}

unsigned machine::inputs(std::uint64_t t_ns) {
  for (; script_next_ < script_.size() && script_[script_next_].t_ns <= t_ns; script_next_++) {
    const input_change &c = script_[script_next_];
    levels_ = (levels_ & ~c.mask) | c.levels;
  }
  unsigned active = 0;
  for (const machine_switch &s : sw_)
    if (s.active) active |= 1u << s.bit;
  return (levels_ & ~driven_) | ((active ^ nc_) & driven_);
}

}  // namespace x4step::sim
