// SPDX-License-Identifier: GPL-2.0
// x4grbl: the $ settings (settings.hpp). The machine file is changed as a
// person would edit it: the key's line gets the new value, comments and
// order stay; the result is checked whole as any machine file, and only a
// file found good replaces the old one.
#include "settings.hpp"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <vector>

#include "files.hpp"

namespace x4grbl {

namespace m = x4step::machine;
namespace g = x4step::gcode;

namespace {

// GRBL's error codes for settings.
constexpr int invalid_statement = 3, negative_value = 4, step_pulse = 6, step_rate = 12, laser_mode = 17;

// The bridge's own settings and their defaults (GRBL's).
const std::map<int, double> own_defaults = {{1, 25},   {4, 0},     {10, 1}, {13, 0},
                                            {26, 250}, {30, 1000}, {31, 0}, {32, 0}};

// GRBL's axes X Y Z A: $100 + i.
constexpr size_t grbl_axes = 4;

std::string text_of(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.3f", v);
  return buf;
}

std::string key_value(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

std::string trim(const std::string &s) {
  const size_t b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

// The machine file's text, as lines, with what an edit needs.
class ini_text {
 public:
  explicit ini_text(const std::string &text) {
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) lines_.push_back(l);
  }
  std::string str() const {
    std::string s;
    for (const std::string &l : lines_) s += l + "\n";
    return s;
  }
  // The value of [section] key, "" if none.
  std::string get(const std::string &section, const std::string &key) const {
    const long i = find(section, key);
    return i < 0 ? "" : trim(lines_[size_t(i)].substr(lines_[size_t(i)].find('=') + 1));
  }
  // Sets [section] key = value: in its line, or after the section's last key.
  void set(const std::string &section, const std::string &key, const std::string &value) {
    if (const long i = find(section, key); i >= 0) {
      std::string &l = lines_[size_t(i)];
      l = l.substr(0, l.find('=') + 1) + " " + value;
      return;
    }
    long last = -1;
    std::string in;
    for (size_t i = 0; i < lines_.size(); i++) {
      const std::string t = trim(lines_[i]);
      if (!t.empty() && t.front() == '[')
        in = t;
      else if (in == "[" + section + "]" && !t.empty() && t.front() != '#' && t.front() != ';')
        last = long(i);
      if (t == "[" + section + "]" && last < 0) last = long(i);
    }
    if (last < 0) {
      lines_.push_back("[" + section + "]");
      last = long(lines_.size()) - 1;
    }
    lines_.insert(lines_.begin() + last + 1, key + " = " + value);
  }

 private:
  long find(const std::string &section, const std::string &key) const {
    std::string in;
    for (size_t i = 0; i < lines_.size(); i++) {
      const std::string t = trim(lines_[i]);
      if (!t.empty() && t.front() == '[') {
        in = t;
        continue;
      }
      const size_t eq = t.find('=');
      if (in == "[" + section + "]" && eq != std::string::npos && trim(t.substr(0, eq)) == key)
        return long(i);
    }
    return -1;
  }
  std::vector<std::string> lines_;
};

// mm per machine unit: GRBL's settings are in mm.
double mm_per_unit(const m::machine &mc) { return mc.units == g::units::inch ? 25.4 : 1.0; }

const m::axis *grbl_axis(const m::machine &mc, size_t i) {
  const auto &a = mc.axes[i];
  return a ? &*a : nullptr;
}

// The first axis that homes: GRBL has one homing speed for all.
const m::homing *first_homing(const m::machine &mc) {
  for (const auto &a : mc.axes)
    if (a && a->home.enabled) return &a->home;
  return nullptr;
}

}  // namespace

settings::settings(std::string machine_path) : machine_path_(std::move(machine_path)) {
  const size_t dot = machine_path_.rfind(".ini");
  path_ = (dot != std::string::npos && dot + 4 == machine_path_.size() ? machine_path_.substr(0, dot)
                                                                       : machine_path_) +
          ".grbl";
  const std::string text = m::read_text(path_, true);
  std::istringstream in(text);
  int n = 0;
  for (std::string l; std::getline(in, l);) {
    n++;
    l = trim(l);
    if (l.empty() || l[0] == '#') continue;
    const auto bad = [&](const std::string &why) {
      return std::runtime_error(path_ + ":" + std::to_string(n) + ": '" + l + "': " + why);
    };
    if (l.rfind("$N", 0) == 0 && l.size() > 3 && (l[2] == '0' || l[2] == '1') && l[3] == '=') {
      startup_[size_t(l[2] - '0')] = l.substr(4);
      continue;
    }
    char *end = nullptr;
    const long number = l[0] == '$' ? std::strtol(l.c_str() + 1, &end, 10) : -1;
    if (number < 0 || !own_defaults.count(int(number)) || *end != '=')
      throw bad("not one of x4grbl's own settings ($1 $4 $10 $13 $26 $30 $31 $32 $N0 $N1 as $10=1)");
    const char *v = end + 1;
    const double value = std::strtod(v, &end);
    if (end == v || *end || !std::isfinite(value)) throw bad("the value is no number");
    own_[int(number)] = value;
  }
}

double settings::value(int number) const {
  if (const auto it = own_.find(number); it != own_.end()) return it->second;
  const auto d = own_defaults.find(number);
  return d == own_defaults.end() ? 0 : d->second;
}

std::string settings::report(const m::machine &mc, const port_facts &p) const {
  const double k = mm_per_unit(mc);
  std::string r;
  auto line = [&r](int n, const std::string &v) { r += "$" + std::to_string(n) + "=" + v + "\r\n"; };
  auto mask = [&mc](x4step::axis_set s) {
    unsigned bits = 0;
    for (size_t i = 0; i < grbl_axes; i++)
      if (const m::axis *a = grbl_axis(mc, i); a && s.contains(x4step::axis(a->motor + 1))) bits |= 1u << i;
    return std::to_string(bits);
  };
  const m::homing *h = first_homing(mc);
  unsigned home_dirs = 0;
  for (size_t i = 0; i < grbl_axes; i++)
    if (const m::axis *a = grbl_axis(mc, i); a && a->home.enabled && a->home.search_vel < 0)
      home_dirs |= 1u << i;
  line(0, std::to_string(int(std::lround(p.pulse_us))));
  line(1, std::to_string(int(value(1))));
  line(2, mask(p.clock_invert));
  line(3, mask(p.dir_invert));
  line(4, std::to_string(int(value(4))));
  line(5, p.nc ? "1" : "0");
  line(6, mc.probe_nc ? "1" : "0");
  line(10, std::to_string(int(value(10))));
  line(11, text_of(mc.junction_deviation * k));
  line(12, text_of(mc.arc_tolerance * k));
  line(13, std::to_string(int(value(13))));
  line(20, "1");
  line(21, "0");
  line(22, h ? "1" : "0");
  line(23, std::to_string(home_dirs));
  line(24, text_of(h ? std::fabs(h->latch_vel) * 60 * k : 0));
  line(25, text_of(h ? std::fabs(h->search_vel) * 60 * k : 0));
  line(26, std::to_string(int(value(26))));
  line(27, text_of(h ? std::fabs(h->home - h->offset) * k : 0));
  line(30, std::to_string(int(value(30))));
  line(31, std::to_string(int(value(31))));
  line(32, std::to_string(int(value(32))));
  // X Y Z always (senders expect them), A when the machine has it.
  const size_t shown = mc.axes[g::A] ? 4 : 3;
  for (int base : {100, 110, 120, 130})
    for (size_t i = 0; i < shown; i++) {
      const m::axis *a = grbl_axis(mc, i);
      const double ka = i < 3 ? k : 1.0;  // A: degrees
      double v = 0;
      if (a)
        v = base == 100   ? std::fabs(a->scale) / ka
            : base == 110 ? a->max_velocity * 60 * ka
            : base == 120 ? a->max_acceleration * ka
                          : (a->max_limit - a->min_limit) * ka;
      line(base + int(i), text_of(v));
    }
  return r;
}

int settings::set(int number, double value, m::machine &mc, const port_facts &p, std::string &why) {
  if (own_defaults.count(number)) {
    if (value < 0) return negative_value;
    if (number == 32 && value != 0) {
      why = "laser mode needs a PWM spindle output, which x4step has not";
      return laser_mode;
    }
    std::map<int, double> own = own_;
    own[number] = number == 10 || number == 13 || number == 4 ? std::trunc(value) : value;
    return keep(own, startup_, why);
  }
  // The rest: the machine file's, or shown only. Writing what is there changes nothing.
  std::string now;
  {
    const std::string all = report(mc, p);
    const std::string key = "$" + std::to_string(number) + "=";
    const size_t at = all.find(key);
    if (at == std::string::npos || (at > 0 && all[at - 1] != '\n')) return invalid_statement;
    now = all.substr(at + key.size(), all.find('\r', at) - at - key.size());
  }
  if (std::fabs(std::strtod(now.c_str(), nullptr) - value) < 5e-4) return 0;
  if (value < 0) return negative_value;
  const auto shown_only = [&why](const std::string &where) {
    why = where;
    return invalid_statement;
  };
  switch (number) {
    case 0:
      if (value < 3) return step_pulse;
      return shown_only("$0 is the port's step pulse: set it with x4ctl timing --pulse");
    case 2:
    case 3:
      return shown_only("$2 and $3 are the port's polarities: set them with x4ctl (x4step_config)");
    case 5:
      return shown_only("$5 is the switches' polarity: set it with x4ctl limits --nc");
    case 20:
      return shown_only("x4step always keeps the soft limits ([AXIS_*] MIN_LIMIT, MAX_LIMIT)");
    case 21:
    case 22:
    case 23:
    case 27:
      return shown_only("$" + std::to_string(number) + " follows the machine file's HOME_* keys: edit " +
                        machine_path_);
    default:
      break;
  }
  // The machine file's keys.
  try {
    return change_machine_file(number, value, mc, why);
  } catch (const m::file_error &e) {
    why = e.what();
    return invalid_statement;
  }
}

int settings::change_machine_file(int number, double value, m::machine &mc, std::string &why) {
  const double k = mm_per_unit(mc);
  const m::file_lock lock(machine_path_);
  ini_text ini(m::read_text(machine_path_, false));
  // A joint's number is its letter's place in COORDINATES as the machine
  // reader takes it: blanks skipped, either case ("X Y Z" is XYZ).
  std::string letters;
  for (const char c : ini.get("TRAJ", "COORDINATES"))
    if (c != ' ' && c != '\t') letters += char(std::toupper(static_cast<unsigned char>(c)));
  auto joint_of = [&letters](size_t axis_index) {
    return "JOINT_" + std::to_string(letters.find("XYZABC"[axis_index]));
  };
  auto axis_section = [](size_t i) { return std::string("AXIS_") + "XYZABC"[i]; };
  if (number == 6) {
    ini.set("X4STEP", "PROBE_NC", value != 0 ? "1" : "0");
  } else if (number == 11) {
    ini.set("X4STEP", "JUNCTION_DEVIATION", key_value(value / k));
  } else if (number == 12) {
    ini.set("X4STEP", "ARC_TOLERANCE", key_value(value / k));
  } else if (number == 24 || number == 25) {
    const char *key = number == 24 ? "HOME_LATCH_VEL" : "HOME_SEARCH_VEL";
    bool any = false;
    for (size_t i = 0; i < g::n_axes; i++) {
      const auto &a = mc.axes[i];
      if (!a || !a->home.enabled) continue;
      const double old = number == 24 ? a->home.latch_vel : a->home.search_vel;
      ini.set(joint_of(i), key, key_value(std::copysign(value / 60 / k, old)));
      any = true;
    }
    if (!any) {
      why = "no axis homes: give HOME_SEARCH_VEL in " + machine_path_ + " first";
      return invalid_statement;
    }
  } else if (number >= 100 && number < 140 && number % 10 < int(grbl_axes)) {
    const size_t i = size_t(number % 10);
    const m::axis *a = grbl_axis(mc, i);
    if (!a) return invalid_statement;
    const double ka = i < 3 ? k : 1.0;
    switch (number / 10) {
      case 10:
        ini.set(joint_of(i), "SCALE", key_value(std::copysign(value * ka, a->scale)));
        break;
      case 11:
        ini.set(axis_section(i), "MAX_VELOCITY", key_value(value / 60 / ka));
        break;
      case 12:
        ini.set(axis_section(i), "MAX_ACCELERATION", key_value(value / ka));
        break;
      default:
        ini.set(axis_section(i), "MAX_LIMIT", key_value(a->min_limit + value / ka));
        break;
    }
  } else {
    return invalid_statement;
  }
  // Checked as any machine file before it replaces the old one.
  const std::string text = ini.str();
  try {
    std::istringstream in(text);
    m::machine changed = m::read(in, machine_path_);
    m::replace_file(machine_path_, text);
    mc = std::move(changed);
  } catch (const m::error &e) {
    why = e.lines().front();
    return why.find("steps/s") != std::string::npos ? step_rate : invalid_statement;
  }
  return 0;
}

int settings::restore_defaults(std::string &why) { return keep({}, {}, why); }

int settings::set_startup(int n, const std::string &block, std::string &why) {
  if (n < 0 || n > 1) {
    why = "startup blocks are $N0 and $N1";
    return invalid_statement;
  }
  std::array<std::string, 2> startup = startup_;
  startup[size_t(n)] = block;
  return keep(own_, startup, why);
}

int settings::keep(const std::map<int, double> &own, const std::array<std::string, 2> &startup,
                   std::string &why) {
  std::string text = "# x4grbl's own settings for " + machine_path_ + " (the rest is the machine file's)\n";
  for (const auto &[n, v] : own) text += "$" + std::to_string(n) + "=" + key_value(v) + "\n";
  for (size_t i = 0; i < startup.size(); i++)
    if (!startup[i].empty()) text += "$N" + std::to_string(i) + "=" + startup[i] + "\n";
  try {
    const m::file_lock lock(path_);
    m::replace_file(path_, text);
  } catch (const m::file_error &e) {
    why = e.what();
    return invalid_statement;
  }
  own_ = own;
  startup_ = startup;
  return 0;
}

}  // namespace x4grbl
