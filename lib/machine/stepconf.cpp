// SPDX-License-Identifier: LGPL-2.1-or-later
// A StepConf configuration (LinuxCNC's INI and HAL files) made into a
// machine file. LinuxCNC's INI is read as LinuxCNC reads it (the first of
// a repeated key counts); the HAL file for its nets of parport pins only.
#include "stepconf.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <istream>
#include <map>
#include <optional>
#include <set>
#include <sstream>

namespace x4step::machine {

namespace {

std::string trim(const std::string &s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

std::string upper(std::string s) {
  for (char &c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

std::string lower(std::string s) {
  for (char &c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::optional<double> number(const std::string &t) {
  char *end = nullptr;
  const double v = std::strtod(t.c_str(), &end);
  if (t.empty() || *end || !std::isfinite(v)) return std::nullopt;
  return v;
}

std::string text_of(double v) {
  std::ostringstream o;
  o << v;
  return o.str();
}

// LinuxCNC's INI: sections of keys, in file order; what was taken is marked.
class linuxcnc_ini {
 public:
  explicit linuxcnc_ini(std::istream &in) {
    std::string cur;
    for (std::string l; std::getline(in, l);) {
      const std::string t = trim(l);
      if (t.empty() || t[0] == '#' || t[0] == ';') continue;
      if (t[0] == '[' && t.find(']') != std::string::npos) {
        cur = upper(trim(t.substr(1, t.find(']') - 1)));
        if (!keys_.count(cur)) order_.push_back(cur);
        keys_[cur];
        continue;
      }
      const size_t eq = t.find('=');
      if (eq == std::string::npos || cur.empty()) continue;
      const std::string key = upper(trim(t.substr(0, eq)));
      auto &sec = keys_[cur];
      if (!sec.count(key)) {
        sec[key] = trim(t.substr(eq + 1));
        key_order_[cur].push_back(key);
      }
    }
  }
  // The value, marked as carried.
  std::optional<std::string> take(const std::string &section, const std::string &key) {
    auto s = keys_.find(section);
    if (s == keys_.end() || !s->second.count(key)) return std::nullopt;
    taken_.insert(section + " " + key);
    return s->second.at(key);
  }
  std::optional<std::string> peek(const std::string &section, const std::string &key) const {
    auto s = keys_.find(section);
    if (s == keys_.end() || !s->second.count(key)) return std::nullopt;
    return s->second.at(key);
  }
  bool has_section(const std::string &s) const { return keys_.count(s) != 0; }
  void mark(const std::string &section, const std::string &key) { taken_.insert(section + " " + key); }
  // What was not taken: whole sections, then the keys of the others.
  std::vector<std::string> left() const {
    std::vector<std::string> out;
    std::string sections;
    for (const std::string &s : order_) {
      std::string keys;
      size_t n_taken = 0;
      for (const std::string &k : key_order_.count(s) ? key_order_.at(s) : std::vector<std::string>{}) {
        if (taken_.count(s + " " + k))
          n_taken++;
        else
          keys += (keys.empty() ? " " : ", ") + k + " = " + keys_.at(s).at(k);
      }
      if (n_taken == 0)
        sections += " [" + s + "]";
      else if (!keys.empty())
        out.push_back("[" + s + "]" + keys);
    }
    if (!sections.empty()) out.insert(out.begin(), "LinuxCNC's sections:" + sections);
    return out;
  }

 private:
  std::vector<std::string> order_;
  std::map<std::string, std::map<std::string, std::string>> keys_;
  std::map<std::string, std::vector<std::string>> key_order_;
  std::set<std::string> taken_;
};

// A parport pin of a HAL net: "parport.0.pin-02-out", "parport.0.pin-10-in-not".
struct port_pin {
  int port = -1, pin = 0;
  bool out = false, inverted = false;
};

std::optional<port_pin> parport_pin(const std::string &name) {
  port_pin p;
  char dir[8] = {};
  char tail[8] = {};
  if (std::sscanf(name.c_str(), "parport.%d.pin-%d-%3[a-z]-%3[a-z]", &p.port, &p.pin, dir, tail) < 3)
    return std::nullopt;
  const std::string d = dir, t = tail;
  if (d != "out" && d != "in") return std::nullopt;
  p.out = d == "out";
  p.inverted = t == "not";
  if (!t.empty() && t != "not") return std::nullopt;
  return p;
}

// The HAL file: its nets (signal to pins), parport output inversions, the
// stepgen settings, the parport's address.
struct hal_file {
  std::map<std::string, std::vector<std::string>> nets;
  std::vector<std::string> net_order;
  std::set<int> inverted_out;
  std::vector<std::string> stepgen_timing;  // "stepgen.0.steplen 1"
  std::string parport_cfg;

  explicit hal_file(std::istream &in) {
    for (std::string l; std::getline(in, l);) {
      const size_t hash = l.find('#');
      std::istringstream words(l.substr(0, hash));
      std::vector<std::string> w;
      for (std::string s; words >> s;) w.push_back(s);
      if (w.empty()) continue;
      if (w[0] == "net" && w.size() >= 2) {
        if (!nets.count(w[1])) net_order.push_back(w[1]);
        auto &pins = nets[w[1]];
        for (size_t i = 2; i < w.size(); i++)
          if (w[i] != "<=" && w[i] != "=>" && w[i] != "<=>") pins.push_back(w[i]);
      } else if (w[0] == "setp" && w.size() >= 3) {
        int port = 0, pin = 0;
        char tail[16] = {};
        if (std::sscanf(w[1].c_str(), "parport.%d.pin-%d-out-%15s", &port, &pin, tail) == 3 &&
            std::string(tail) == "invert" && port == 0 && w[2] != "0")
          inverted_out.insert(pin);
        for (const char *t : {".steplen", ".stepspace", ".dirhold", ".dirsetup"})
          if (w[1].compare(0, 8, "stepgen.") == 0 && w[1].size() > std::string(t).size() &&
              w[1].compare(w[1].size() - std::string(t).size(), std::string::npos, t) == 0)
            stepgen_timing.push_back(w[1] + " " + w[2]);
      } else if (w[0] == "loadrt" && w.size() >= 3 && w[1] == "hal_parport") {
        const size_t q = l.find("cfg=");
        if (q != std::string::npos) {
          std::string cfg = l.substr(q + 4);
          cfg.erase(std::remove(cfg.begin(), cfg.end(), '"'), cfg.end());
          parport_cfg = trim(cfg);
        }
      }
    }
  }

  // The signal a pin (e.g. "joint.0.home-sw-in") is on; "" if none.
  std::string signal_of(const std::string &pin) const {
    for (const auto &[sig, pins] : nets)
      if (std::find(pins.begin(), pins.end(), pin) != pins.end()) return sig;
    return "";
  }
  // The parport 0 pins of a signal.
  std::vector<port_pin> port_pins(const std::string &sig) const {
    std::vector<port_pin> out;
    auto it = nets.find(sig);
    if (it == nets.end()) return out;
    for (const std::string &p : it->second)
      if (auto pp = parport_pin(p); pp && pp->port == 0) out.push_back(*pp);
    return out;
  }
};

// x4step's inputs 1..5 are pins 15, 13, 12, 10, 11; 0: the pin is none.
int input_of_pin(int pin) {
  const int pins[] = {15, 13, 12, 10, 11};
  for (int i = 0; i < 5; i++)
    if (pins[i] == pin) return i + 1;
  return 0;
}

struct limit_inputs {
  int minus = 0, plus = 0;
};

}  // namespace

imported import_stepconf(std::istream &ini_in, const std::string &ini_name, std::istream *hal_in,
                         const std::string &hal_name, const std::string &tool_table) {
  linuxcnc_ini ini(ini_in);
  std::optional<hal_file> hal;
  if (hal_in) hal.emplace(*hal_in);
  imported r;
  std::ostringstream o;
  auto carry = [&](const std::string &section, const std::string &key, const std::string &as) {
    if (auto v = ini.take(section, key)) o << as << " = " << *v << "\n";
  };

  o << "# Made by 'x4ctl machine import' of the LinuxCNC configuration " << ini_name;
  if (hal) o << "\n# and " << hal_name;
  o << ". Every key: machines/README.md.\n";

  // [EMC], [EMCIO]
  o << "\n[EMC]\n";
  carry("EMC", "MACHINE", "MACHINE");
  if (auto t = ini.peek("EMCIO", "TOOL_TABLE"); t && !tool_table.empty()) {
    ini.mark("EMCIO", "TOOL_TABLE");
    o << "\n[EMCIO]\nTOOL_TABLE = " << tool_table << "\n";
  }

  // [TRAJ]: the axes, joint n the n-th letter (trivkins).
  const std::string coords = upper(ini.take("TRAJ", "COORDINATES").value_or(""));
  if (auto k = ini.peek("KINS", "KINEMATICS"); k && k->find("trivkins") == std::string::npos)
    r.not_carried.push_back("[KINS] KINEMATICS = " + *k +
                            ": x4step's kinematics are trivial (joint n is the n-th letter of COORDINATES)");
  // LinuxCNC's joint of each letter kept is its place in COORDINATES (a
  // gantry's X Y Y Z: Z is joint 3); x4step's joint n is the n-th kept.
  std::string letters, dropped;
  std::vector<size_t> source_joint;
  size_t place = 0;
  for (char c : coords) {
    if (c == ' ' || c == '\t') continue;
    if (std::string("XYZABC").find(c) == std::string::npos || letters.find(c) != std::string::npos ||
        letters.size() == 4) {
      dropped += c;
    } else {
      letters += c;
      source_joint.push_back(place);
    }
    place++;
  }
  const size_t joints = letters.size();
  if (!dropped.empty())
    r.not_carried.push_back("[TRAJ] COORDINATES = " + coords + ": axes " + dropped +
                            " (x4step: at most 4 motors, one per axis, letters of XYZABC)");

  // The port's outputs: spindle and coolant on pins 1 and 14 are the machine's;
  // the rest is the pin map, which x4step does not have: its pins are fixed.
  std::map<int, std::string> out_pin_of;  // pin (port 0) -> signal
  std::vector<std::string> pin_map;
  if (hal)
    for (const std::string &sig : hal->net_order)
      for (const port_pin &p : hal->port_pins(sig))
        if (p.out) out_pin_of[p.pin] = sig;
  std::string spindle = "none", flood = "none", mist = "none";
  std::set<std::string> carried_signals;
  for (const auto &[pin, sig] : out_pin_of) {
    std::string *to = sig == "spindle-cw" || sig == "spindle-on" ? &spindle
                      : sig == "coolant-flood"                   ? &flood
                      : sig == "coolant-mist"                    ? &mist
                                                                 : nullptr;
    if (to && (pin == 1 || pin == 14) && *to == "none" && !hal->inverted_out.count(pin)) {
      *to = std::to_string(pin);
      carried_signals.insert(sig);
    }
  }
  o << "\n[X4STEP]\nPORT = LPT1\nOUTPUT_MODE = clock-dir\n";
  const bool inch = lower(ini.peek("TRAJ", "LINEAR_UNITS").value_or("mm")).compare(0, 2, "in") == 0;
  o << "# LinuxCNC has no such keys: x4step's choice, change it to suit.\n"
    << "ARC_TOLERANCE = " << (inch ? "0.0005" : "0.01") << "\n"
    << "JUNCTION_DEVIATION = " << (inch ? "0.0005" : "0.01") << "\n";
  r.notes.push_back(std::string("[X4STEP] ARC_TOLERANCE and JUNCTION_DEVIATION: ") +
                    (inch ? "0.0005 inch" : "0.01 mm") + " chosen (LinuxCNC has no such keys)");
  o << "SPINDLE_PIN = " << spindle << "\nFLOOD_PIN = " << flood << "\nMIST_PIN = " << mist << "\n";
  if (hal && !hal->parport_cfg.empty() && hal->parport_cfg.compare(0, 5, "0x378") != 0)
    r.notes.push_back("[X4STEP] PORT = LPT1 assumed: the HAL's parport is cfg=\"" + hal->parport_cfg +
                      "\" (LPT1..LPT4: /dev/x4step0..3)");

  o << "\n[TRAJ]\nCOORDINATES = " << letters << "\n";
  carry("TRAJ", "LINEAR_UNITS", "LINEAR_UNITS");
  carry("TRAJ", "ANGULAR_UNITS", "ANGULAR_UNITS");
  carry("TRAJ", "MAX_LINEAR_VELOCITY", "MAX_LINEAR_VELOCITY");

  std::vector<limit_inputs> limits(joints);
  for (size_t n = 0; n < joints; n++) {
    const std::string axis = std::string("AXIS_") + letters[n], joint = "JOINT_" + std::to_string(n);
    const std::string from = std::to_string(source_joint[n]);  // LinuxCNC's joint number
    // LinuxCNC 2.7's files have [AXIS_<n>] for both.
    const std::string old_axis = "AXIS_" + from;
    const std::string axis_sec = ini.has_section(axis) ? axis : old_axis;
    const std::string joint_sec = ini.has_section("JOINT_" + from) ? "JOINT_" + from : old_axis;
    o << "\n[" << axis << "]\n";
    for (const char *k : {"MIN_LIMIT", "MAX_LIMIT", "MAX_VELOCITY", "MAX_ACCELERATION"}) {
      const std::optional<std::string> v = ini.take(axis_sec, k);
      if (v) o << k << " = " << *v << "\n";
      // The joint's own, as StepConf writes them: the same as the axis' are carried.
      if (joint_sec != axis_sec)
        if (auto j = ini.peek(joint_sec, k); j && v && number(*j) == number(*v)) ini.mark(joint_sec, k);
    }
    o << "\n[" << joint << "]\n";
    o << "MOTOR = " << n + 1 << "\n";
    carry(joint_sec, "SCALE", "SCALE");

    // Homing: x4step homes on a switch only (HOME_SEARCH_VEL), needs its input.
    const double search = number(ini.peek(joint_sec, "HOME_SEARCH_VEL").value_or("0")).value_or(0);
    int input = 0;
    bool normally_closed = false;
    std::string home_sig;
    if (hal) {
      home_sig = hal->signal_of("joint." + from + ".home-sw-in");
      if (home_sig.empty()) home_sig = hal->signal_of("axis." + from + ".home-sw-in");
      for (const port_pin &p : hal->port_pins(home_sig))
        if (!p.out && input_of_pin(p.pin)) {
          input = input_of_pin(p.pin);
          normally_closed = p.inverted;
        }
      for (const char *end : {"neg", "pos"}) {
        const std::string sig = hal->signal_of("joint." + from + "." + end + "-lim-sw-in");
        for (const port_pin &p : hal->port_pins(sig))
          if (!p.out && input_of_pin(p.pin))
            (end[0] == 'n' ? limits[n].minus : limits[n].plus) = input_of_pin(p.pin);
      }
    }
    const std::optional<double> latch = number(ini.peek(joint_sec, "HOME_LATCH_VEL").value_or(""));
    if (search != 0 && input && latch && *latch != 0) {
      ini.mark(joint_sec, "HOME_SEARCH_VEL");
      ini.mark(joint_sec, "HOME_LATCH_VEL");
      o << "HOME_INPUT = " << input << "\n";
      o << "HOME_SEARCH_VEL = " << *ini.peek(joint_sec, "HOME_SEARCH_VEL") << "\n";
      if ((*latch > 0) == (search > 0)) {
        o << "HOME_LATCH_VEL = " << text_of(-*latch) << "\n";
        r.notes.push_back("[" + joint + "] HOME_LATCH_VEL " + text_of(*latch) + " made " + text_of(-*latch) +
                          ": LinuxCNC, given the sign of HOME_SEARCH_VEL, latches on a second approach; "
                          "x4step latches while it backs off the switch");
      } else {
        o << "HOME_LATCH_VEL = " << *ini.peek(joint_sec, "HOME_LATCH_VEL") << "\n";
      }
      carry(joint_sec, "HOME_OFFSET", "HOME_OFFSET");
      carry(joint_sec, "HOME", "HOME");
      if (auto s = ini.peek(joint_sec, "HOME_SEQUENCE")) {
        const std::optional<double> q = number(*s);
        if (q && *q == std::floor(*q) && std::fabs(*q) <= 9) {
          ini.mark(joint_sec, "HOME_SEQUENCE");
          o << "HOME_SEQUENCE = " << text_of(std::fabs(*q)) << "\n";
          if (*q < 0)
            r.notes.push_back("[" + joint + "] HOME_SEQUENCE " + *s + " made " + text_of(-*q) +
                              " (x4step has no synchronised homing of joints)");
        }
      }
      if (normally_closed)
        r.not_carried.push_back("home switch of " + std::string(1, letters[n]) + " normally closed (" +
                                home_sig + " on pin-NN-in-not): the port's setting, 'x4ctl limits --nc " +
                                std::to_string(input) + "'");
    } else if (search != 0) {
      r.not_carried.push_back(
          "[" + joint_sec + "] homing: " +
          std::string(!hal     ? "no HAL file to find the home switch's input in"
                      : !input ? "no parport input for joint." + from + ".home-sw-in in " + hal_name
                               : "HOME_LATCH_VEL missing or 0") +
          " (x4step homes on a switch, at HOME_SEARCH_VEL then HOME_LATCH_VEL)");
    }
  }

  // Limit switches are the port's setting, which the module keeps.
  std::string limit_cmds;
  for (size_t n = 0; n < joints; n++)
    if (limits[n].minus || limits[n].plus) {
      limit_cmds += std::string(limit_cmds.empty() ? "" : "; ") + "x4ctl limits " + std::to_string(n + 1);
      if (limits[n].minus) limit_cmds += " --minus " + std::to_string(limits[n].minus);
      if (limits[n].plus) limit_cmds += " --plus " + std::to_string(limits[n].plus);
    }
  if (!limit_cmds.empty())
    r.not_carried.push_back("limit switches (the port's setting, which the module keeps): " + limit_cmds);

  // The pin map: x4step's pins are fixed (docs/hardware.md).
  if (hal) {
    for (const auto &[pin, sig] : out_pin_of)
      if (!carried_signals.count(sig))
        pin_map.push_back(sig + " pin " + std::to_string(pin) +
                          (hal->inverted_out.count(pin) ? " inverted" : ""));
    if (!pin_map.empty()) {
      std::string l = "pin map:";
      for (const std::string &p : pin_map) l += (l.back() == ':' ? " " : ", ") + p;
      r.not_carried.push_back(l +
                              " (x4step's outputs are fixed: motor n direction on pin 2n, clock on pin "
                              "2n+1, signals 1 and 2 on pins 1 and 14; MOTOR n+1 drives joint n here)");
    }
    if (!hal->stepgen_timing.empty()) {
      std::string l = "step timing:";
      for (const std::string &t : hal->stepgen_timing) l += (l.back() == ':' ? " " : ", ") + t;
      r.not_carried.push_back(l + " (the port's setting: x4ctl timing)");
    }
  }
  for (const std::string &l : ini.left()) r.not_carried.push_back(l);
  r.text = o.str();
  return r;
}

}  // namespace x4step::machine
