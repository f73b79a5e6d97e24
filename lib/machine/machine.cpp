// SPDX-License-Identifier: LGPL-2.1-or-later
// The machine file: read the INI text whole, then check every section and
// key against what x4step knows, so that nothing is skipped silently.
#include "machine.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <vector>

#include "x4step.hpp"

namespace x4step::machine {

namespace {

// ---- the names x4step knows ---------------------------------------------------------------
// The keys x4step reads, one a line, by section: "AXIS_" stands for every
// [AXIS_<letter>], "JOINT_" for every [JOINT_<n>]. A section with keys here
// is x4step's; a key of it found in neither table is refused ("did you mean").
struct key_name {
  const char *section, *key;
};
constexpr key_name x4step_keys[] = {
    {"EMC", "MACHINE"},
    {"EMCIO", "TOOL_TABLE"},
    {"RS274NGC", "PARAMETER_FILE"},
    {"X4STEP", "PORT"},
    {"X4STEP", "OUTPUT_MODE"},
    {"X4STEP", "ARC_TOLERANCE"},
    {"X4STEP", "JUNCTION_DEVIATION"},
    {"X4STEP", "SPINDLE_PIN"},
    {"X4STEP", "FLOOD_PIN"},
    {"X4STEP", "MIST_PIN"},
    {"X4STEP", "PROBE_INPUT"},
    {"X4STEP", "PROBE_NC"},
    {"TRAJ", "COORDINATES"},
    {"TRAJ", "LINEAR_UNITS"},
    {"TRAJ", "ANGULAR_UNITS"},
    {"TRAJ", "MAX_LINEAR_VELOCITY"},
    {"TRAJ", "NO_FORCE_HOMING"},
    {"AXIS_", "MIN_LIMIT"},
    {"AXIS_", "MAX_LIMIT"},
    {"AXIS_", "MAX_VELOCITY"},
    {"AXIS_", "MAX_ACCELERATION"},
    {"JOINT_", "MOTOR"},
    {"JOINT_", "SCALE"},
    {"JOINT_", "HOME_SEARCH_VEL"},
    {"JOINT_", "HOME_LATCH_VEL"},
    {"JOINT_", "HOME_INPUT"},
    {"JOINT_", "HOME_OFFSET"},
    {"JOINT_", "HOME"},
    {"JOINT_", "HOME_SEQUENCE"},
};
// LinuxCNC's sections that x4step does not read: accepted whole, with a
// warning (their keys are LinuxCNC's and HAL files' business), except a
// key a letter or two from one of x4step's (a misspelling) or one of
// x4step's, which is read. "SPINDLE_" stands for [SPINDLE_<n>].
constexpr const char *linuxcnc_sections[] = {
    "DISPLAY", "FILTER",       "RS274NGC", "EMCMOT", "TASK",     "HAL",
    "HALUI",   "APPLICATIONS", "KINS",     "PYTHON", "SPINDLE_",
};
// LinuxCNC's keys in the sections x4step reads, that x4step does not use
// (the joints' own limits and speeds: x4step's are the axes'): accepted,
// with a warning.
constexpr key_name linuxcnc_keys[] = {
    {"EMC", "VERSION"},
    {"EMC", "DEBUG"},
    {"EMC", "NML_FILE"},
    {"EMCIO", "EMCIO"},
    {"EMCIO", "CYCLE_TIME"},
    {"EMCIO", "TOOL_CHANGE_POSITION"},
    {"EMCIO", "TOOL_CHANGE_QUILL_UP"},
    {"EMCIO", "TOOL_CHANGE_WITH_SPINDLE_ON"},
    {"EMCIO", "TOOL_CHANGE_AT_G30"},
    {"EMCIO", "RANDOM_TOOLCHANGER"},
    {"TRAJ", "AXES"},
    {"TRAJ", "JOINTS"},
    {"TRAJ", "HOME"},
    {"TRAJ", "CYCLE_TIME"},
    {"TRAJ", "DEFAULT_VELOCITY"},
    {"TRAJ", "MAX_VELOCITY"},
    {"TRAJ", "DEFAULT_ACCELERATION"},
    {"TRAJ", "MAX_ACCELERATION"},
    {"TRAJ", "DEFAULT_LINEAR_VELOCITY"},
    {"TRAJ", "MIN_LINEAR_VELOCITY"},
    {"TRAJ", "DEFAULT_LINEAR_ACCELERATION"},
    {"TRAJ", "MAX_LINEAR_ACCELERATION"},
    {"TRAJ", "DEFAULT_ANGULAR_VELOCITY"},
    {"TRAJ", "MAX_ANGULAR_VELOCITY"},
    {"TRAJ", "DEFAULT_ANGULAR_ACCELERATION"},
    {"TRAJ", "MAX_ANGULAR_ACCELERATION"},
    {"TRAJ", "POSITION_FILE"},
    {"TRAJ", "NO_FORCE_HOMING"},
    {"TRAJ", "SPINDLES"},
    {"TRAJ", "PLANNER_TYPE"},
    {"TRAJ", "MAX_LINEAR_JERK"},
    {"TRAJ", "ARC_BLEND_ENABLE"},
    {"TRAJ", "ARC_BLEND_FALLBACK_ENABLE"},
    {"TRAJ", "ARC_BLEND_OPTIMIZATION_DEPTH"},
    {"TRAJ", "ARC_BLEND_GAP_CYCLES"},
    {"TRAJ", "ARC_BLEND_RAMP_FREQ"},
    {"TRAJ", "ARC_BLEND_KINK_RATIO"},
    {"AXIS_", "MAX_JERK"},
    {"AXIS_", "HOME"},
    {"AXIS_", "LOCKING_INDEXER_JOINT"},
    {"AXIS_", "WRAPPED_ROTARY"},
    {"AXIS_", "OFFSET_AV_RATIO"},
    {"JOINT_", "TYPE"},
    {"JOINT_", "UNITS"},
    {"JOINT_", "MIN_LIMIT"},
    {"JOINT_", "MAX_LIMIT"},
    {"JOINT_", "MAX_VELOCITY"},
    {"JOINT_", "MAX_ACCELERATION"},
    {"JOINT_", "MAX_JERK"},
    {"JOINT_", "BACKLASH"},
    {"JOINT_", "COMP_FILE"},
    {"JOINT_", "COMP_FILE_TYPE"},
    {"JOINT_", "FERROR"},
    {"JOINT_", "MIN_FERROR"},
    {"JOINT_", "LOCKING_INDEXER"},
    {"JOINT_", "HOME_FINAL_VEL"},
    {"JOINT_", "HOME_IGNORE_LIMITS"},
    {"JOINT_", "HOME_USE_INDEX"},
    {"JOINT_", "HOME_INDEX_NO_ENCODER_RESET"},
    {"JOINT_", "HOME_IS_SHARED"},
    {"JOINT_", "HOME_ABSOLUTE_ENCODER"},
    {"JOINT_", "VOLATILE_HOME"},
    {"JOINT_", "STEPGEN_MAXACCEL"},
    {"JOINT_", "STEPGEN_MAXVEL"},
    {"JOINT_", "DIRSETUP"},
    {"JOINT_", "DIRHOLD"},
    {"JOINT_", "STEPLEN"},
    {"JOINT_", "STEPSPACE"},
    {"JOINT_", "OUTPUT_SCALE"},
    {"JOINT_", "OUTPUT_OFFSET"},
    {"JOINT_", "INPUT_SCALE"},
    {"JOINT_", "ENCODER_SCALE"},
    {"JOINT_", "P"},
    {"JOINT_", "I"},
    {"JOINT_", "D"},
    {"JOINT_", "FF0"},
    {"JOINT_", "FF1"},
    {"JOINT_", "FF2"},
    {"JOINT_", "BIAS"},
    {"JOINT_", "DEADBAND"},
    {"JOINT_", "MAX_OUTPUT"},
};

// The table name of a section: AXIS_X -> AXIS_, JOINT_0 -> JOINT_, SPINDLE_0 -> SPINDLE_.
std::string kind_of(const std::string &section) {
  for (const char *k : {"AXIS_", "JOINT_", "SPINDLE_"})
    if (section.size() > std::strlen(k) && section.compare(0, std::strlen(k), k) == 0) return k;
  return section;
}

template <size_t n>
std::vector<std::string> keys_of(const key_name (&table)[n], const std::string &kind) {
  std::vector<std::string> out;
  for (const key_name &k : table)
    if (kind == k.section) out.push_back(k.key);
  return out;
}

bool is_x4step_section(const std::string &kind) { return !keys_of(x4step_keys, kind).empty(); }

bool is_linuxcnc_section(const std::string &kind) {
  for (const char *s : linuxcnc_sections)
    if (kind == s) return true;
  return false;
}

bool contains(const std::vector<std::string> &v, const std::string &s) {
  return std::find(v.begin(), v.end(), s) != v.end();
}

// ---- the file's text ------------------------------------------------------------------------

std::string where(const std::string &file, int line, int col) {
  if (line <= 0) return file;
  return file + ":" + std::to_string(line) + (col > 0 ? ":" + std::to_string(col) : "");
}

struct entry {
  std::string value;
  int line = 0, key_col = 1, value_col = 1;
};

struct section {
  int line = 0;
  std::map<std::string, entry> keys;
};

std::string trim(const std::string &s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const size_t e = s.find_last_not_of(" \t\r");
  return s.substr(a, e - a + 1);
}

std::string upper(std::string s) {
  for (char &c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// The value of "KEY = VALUE # comment": a '#' or ';' that starts the value
// or follows a blank begins a comment.
size_t comment_start(const std::string &line, size_t from) {
  for (size_t i = from; i < line.size(); i++)
    if ((line[i] == '#' || line[i] == ';') && (i == from || line[i - 1] == ' ' || line[i - 1] == '\t'))
      return i;
  return line.size();
}

// The whole file as sections of keys, each with its line and columns; the
// syntax alone. Every mistake is kept (problems()), and the reading goes on.
class ini {
 public:
  ini(std::istream &in, std::string file) : file_(std::move(file)) {
    std::string text;
    section *cur = nullptr;
    std::string cur_name;
    bool lost = false;  // after a broken header: its keys are no section's, and not reported
    for (int n = 1; std::getline(in, text); n++) {
      const std::string t = trim(text);
      if (t.empty() || t[0] == '#' || t[0] == ';') continue;
      const int col = static_cast<int>(text.find_first_not_of(" \t")) + 1;
      if (t[0] == '[') {
        cur = nullptr;
        lost = true;
        // A broken header is reported, and read as the name it has, so
        // that its keys are not all lost (nor reported as missing).
        const size_t close = t.find(']');
        cur_name = upper(trim(t.substr(1, close == std::string::npos ? std::string::npos : close - 1)));
        if (close != t.size() - 1 || cur_name.empty())
          add(n, col, "", "'" + t + "' is no section header: write [NAME]");
        if (cur_name.empty()) continue;
        auto [it, fresh] = sections_.try_emplace(cur_name);
        if (!fresh) {
          add(n, col, "[" + cur_name + "]",
              "section given twice (first at line " + std::to_string(it->second.line) + "): merge them");
          continue;
        }
        it->second.line = n;
        cur = &it->second;
        lost = false;
        order_.push_back(cur_name);
        continue;
      }
      const size_t eq = text.find('=');
      if (eq == std::string::npos) {
        if (lost) continue;
        add(n, col, cur ? "[" + cur_name + "]" : "", "'" + t + "': write KEY = VALUE");
        // "KEY VALUE": the key is given, if badly; it is not missing too.
        if (cur) misspelt.insert(cur_name + " " + upper(t.substr(0, t.find_first_of(" \t"))));
        continue;
      }
      const std::string key = upper(trim(text.substr(0, eq)));
      if (lost) continue;
      if (!cur) {
        add(n, col, key, "a key before any [SECTION]: put it in its section");
        continue;
      }
      if (key.empty()) {
        add(n, col, "[" + cur_name + "]", "'" + t + "' has no key before '='");
        continue;
      }
      entry e;
      e.line = n;
      e.key_col = col;
      const size_t v = text.find_first_not_of(" \t", eq + 1);
      const size_t vb = v == std::string::npos ? text.size() : v;
      e.value = trim(text.substr(vb, comment_start(text, vb) - vb));
      e.value_col = static_cast<int>(vb) + 1;
      auto [it, fresh] = cur->keys.try_emplace(key, e);
      // LinuxCNC's own sections repeat keys ([FILTER] PROGRAM_EXTENSION, [HAL] HALFILE).
      if (!fresh && !is_linuxcnc_section(kind_of(cur_name)))
        add(n, col, "[" + cur_name + "] " + key,
            "given twice (first at line " + std::to_string(it->second.line) + "): keep one");
    }
    if (in.bad()) add(0, 0, "", "read error");
  }

  const std::string &file() const { return file_; }
  const std::vector<std::string> &order() const { return order_; }
  section *find(const std::string &name) {
    auto it = sections_.find(name);
    return it == sections_.end() ? nullptr : &it->second;
  }
  void add(int line, int col, const std::string &key, const std::string &message) {
    problems_.push_back({line, col, key, message});
  }
  std::vector<error::problem> &problems() { return problems_; }
  std::set<std::string> misspelt;  ///< "SECTION KEY" that a misspelt key stands for

 private:
  std::string file_;
  std::map<std::string, section> sections_;
  std::vector<std::string> order_;
  std::vector<error::problem> problems_;
};

// The keys of one section, taken by name. Each mistake is recorded in the
// file's problems and gives no value (nullopt), so that the reading goes
// on and the checks that need the value are skipped.
class reader {
 public:
  reader(ini &f, std::string name) : f_(f), name_(std::move(name)), s_(f.find(name_)) {}

  bool has(const std::string &key) const { return s_ && s_->keys.count(key); }
  int line(const std::string &key) const { return has(key) ? s_->keys.at(key).line : section_line(); }
  int col(const std::string &key) const { return has(key) ? s_->keys.at(key).value_col : 1; }
  int section_line() const { return s_ ? s_->line : 0; }
  const std::string &name() const { return name_; }

  // A mistake in the key's value (at the value; at the section if the key is absent).
  void fail(const std::string &key, const std::string &what) const {
    f_.add(line(key), section_line() ? col(key) : 0, "[" + name_ + "] " + key, what);
  }
  void fail_section(const std::string &what) const { f_.add(section_line(), 1, "[" + name_ + "]", what); }

  const std::string *text(const std::string &key) const {
    if (!has(key)) return nullptr;
    return &s_->keys.at(key).value;
  }
  // Missing is a mistake, unless a misspelt key already stands for it.
  bool need(const std::string &key, const std::string &what) const {
    if (has(key)) return true;
    if (!f_.misspelt.count(name_ + " " + key)) fail(key, "missing: give " + what);
    return false;
  }
  std::optional<std::string> required_text(const std::string &key, const std::string &what) const {
    if (!need(key, what)) return std::nullopt;
    return *text(key);
  }

  std::optional<double> number(const std::string &key) const {
    const std::string *t = text(key);
    if (!t) return std::nullopt;
    char *end = nullptr;
    errno = 0;
    const double v = std::strtod(t->c_str(), &end);
    if (t->empty() || *end || errno || !std::isfinite(v)) {
      fail(key, "'" + *t + "' is no number");
      return std::nullopt;
    }
    return v;
  }
  std::optional<double> required(const std::string &key, const std::string &what) const {
    if (!need(key, what)) return std::nullopt;
    return number(key);
  }
  std::optional<double> positive(const std::string &key, const std::string &what) const {
    const std::optional<double> v = required(key, what);
    if (v && *v <= 0) {
      fail(key, "'" + *text(key) + "': must be above 0 (" + what + ")");
      return std::nullopt;
    }
    return v;
  }
  std::optional<long> whole(const std::string &key, long min, long max) const {
    const std::optional<double> v = number(key);
    if (!v) return std::nullopt;
    if (*v != std::floor(*v) || *v < min || *v > max) {
      fail(key,
           "'" + *text(key) + "': use a whole number " + std::to_string(min) + ".." + std::to_string(max));
      return std::nullopt;
    }
    return static_cast<long>(*v);
  }

  // The keys that are neither x4step's nor LinuxCNC's: refused, with the
  // nearest name. LinuxCNC's are listed for the warning.
  void check_keys(std::vector<std::string> &ignored) {
    if (!s_) return;
    const std::string kind = kind_of(name_);
    const std::vector<std::string> ours = keys_of(x4step_keys, kind);
    const std::vector<std::string> theirs = keys_of(linuxcnc_keys, kind);
    const bool linuxcnc_section = is_linuxcnc_section(kind);
    for (const auto &[key, e] : s_->keys) {
      if (contains(ours, key)) continue;
      const std::string near = nearest(key, ours);
      if (contains(theirs, key) || (linuxcnc_section && near.empty())) {
        if (!ours.empty()) ignored.push_back(key);  // a whole LinuxCNC section is listed as one
        continue;
      }
      std::string what = "unknown key";
      if (!near.empty()) {
        what += ": did you mean " + near + "?";
        f_.misspelt.insert(name_ + " " + near);
      } else {
        what += ": [" + name_ + "] takes ";
        for (size_t i = 0; i < ours.size(); i++)
          what += (i == 0 ? "" : i + 1 == ours.size() ? " and " : ", ") + ours[i];
      }
      f_.add(e.line, e.key_col, "[" + name_ + "] " + key, what);
    }
  }

 private:
  ini &f_;
  std::string name_;
  section *s_;
};

std::string number_text(double v) {
  std::ostringstream o;
  o << v;
  return o.str();
}

std::optional<gcode::units> units_of(const reader &r) {
  const std::optional<std::string> t = r.required_text("LINEAR_UNITS", "mm or inch");
  if (!t) return std::nullopt;
  const std::string u = upper(*t);
  if (u == "MM" || u == "METRIC") return gcode::units::mm;
  if (u == "INCH" || u == "IN" || u == "IMPERIAL") return gcode::units::inch;
  r.fail("LINEAR_UNITS", "'" + u + "': use mm or inch");
  return std::nullopt;
}

pin pin_of(const reader &r, const std::string &key) {
  const std::string *t = r.text(key);
  if (!t || upper(*t) == "NONE") return pin::none;
  if (*t == "1") return pin::pin1;
  if (*t == "14") return pin::pin14;
  r.fail(key, "'" + *t + "': use 1 (signal 1), 14 (signal 2) or none");
  return pin::none;
}

void read_x4step(ini &f, machine &m, bool linuxcnc) {
  reader r(f, "X4STEP");
  if (r.section_line() == 0) {
    f.add(0, 0, "[X4STEP]",
          "no [X4STEP] section: it needs ARC_TOLERANCE and JUNCTION_DEVIATION" +
              std::string(linuxcnc ? " (a LinuxCNC configuration? 'x4ctl machine import' makes a machine "
                                     "file of it and its HAL file)"
                                   : ""));
    return;
  }
  if (const std::string *p = r.text("PORT")) {
    const std::string u = upper(*p);
    if (u.size() != 4 || u.compare(0, 3, "LPT") || u[3] < '1' || u[3] > '4')
      r.fail("PORT", "'" + *p + "': use LPT1, LPT2, LPT3 or LPT4");
    else
      m.port = u;
  }
  if (const std::string *o = r.text("OUTPUT_MODE")) {
    // clock-dir as `x4ctl mode` says; step-dir, as the first machine files said, too.
    if (*o == "clock-dir" || *o == "step-dir")
      m.mode = output_mode::clock_dir;
    else if (*o == "smc-phase")
      m.mode = output_mode::smc_phase;
    else if (*o == "smc-hold")
      m.mode = output_mode::smc_hold;
    else
      r.fail("OUTPUT_MODE", "'" + *o + "': use clock-dir (or step-dir), smc-phase or smc-hold");
  }
  m.arc_tolerance =
      r.positive("ARC_TOLERANCE", "the most a chord may leave an arc, in machine units").value_or(0);
  m.junction_deviation =
      r.required("JUNCTION_DEVIATION", "GRBL's junction deviation, in machine units").value_or(0);
  if (m.junction_deviation < 0) r.fail("JUNCTION_DEVIATION", "must be 0 (stop at every corner) or more");
  m.spindle = pin_of(r, "SPINDLE_PIN");
  m.flood = pin_of(r, "FLOOD_PIN");
  m.mist = pin_of(r, "MIST_PIN");
  m.probe_input = int(r.whole("PROBE_INPUT", 1, 5).value_or(0));
  m.probe_nc = r.whole("PROBE_NC", 0, 1).value_or(0) == 1;
  if (r.has("PROBE_NC") && !m.probe_input)
    r.fail("PROBE_NC", "no PROBE_INPUT: give the probe's input 1..5 first");
  // One pin, one job: the second key naming a pin is the contradiction.
  const std::pair<const char *, pin> pins[] = {
      {"SPINDLE_PIN", m.spindle}, {"FLOOD_PIN", m.flood}, {"MIST_PIN", m.mist}};
  for (size_t i = 0; i < 3; i++)
    for (size_t j = i + 1; j < 3; j++)
      if (pins[i].second != pin::none && pins[i].second == pins[j].second) {
        const bool j_later = r.line(pins[j].first) >= r.line(pins[i].first);
        const char *later = j_later ? pins[j].first : pins[i].first,
                   *other = j_later ? pins[i].first : pins[j].first;
        r.fail(later, "pin " + std::to_string(int(pins[j].second)) + " is the " + other +
                          " already: give each its own");
      }
}

// [TRAJ]: the axis letters in joint order ("" if none can be read).
std::string read_traj(ini &f, machine &m) {
  reader r(f, "TRAJ");
  if (r.section_line() == 0) {
    f.add(0, 0, "[TRAJ]", "no [TRAJ] section: it needs COORDINATES and LINEAR_UNITS");
    return "";
  }
  std::string letters;
  if (const auto coords = r.required_text("COORDINATES", "the axis letters, e.g. XYZ")) {
    bool bad = false;
    for (char c : upper(*coords)) {
      if (c == ' ' || c == '\t') continue;
      if (std::string("XYZABC").find(c) == std::string::npos) {
        r.fail("COORDINATES", std::string("'") + c + "' is no axis: use letters of XYZABC");
        bad = true;
      } else if (letters.find(c) != std::string::npos) {
        r.fail("COORDINATES", std::string("axis ") + c + " given twice: one motor per axis");
        bad = true;
      } else {
        letters += c;
      }
    }
    if (letters.empty() && !bad) r.fail("COORDINATES", "no axis: give the axis letters, e.g. XYZ");
    if (letters.size() > size_t(x4step::axes)) {
      r.fail("COORDINATES", "'" + letters + "': a port drives at most 4 motors");
      letters.resize(size_t(x4step::axes));
    }
  }
  if (const auto u = units_of(r)) m.units = *u;
  if (const std::string *a = r.text("ANGULAR_UNITS"))
    if (upper(*a) != "DEGREE" && upper(*a) != "DEG")
      r.fail("ANGULAR_UNITS", "'" + *a + "': rotary axes are in degrees (degree)");
  if (r.has("MAX_LINEAR_VELOCITY"))
    m.max_linear_velocity = r.positive("MAX_LINEAR_VELOCITY", "the most along the path, units/s").value_or(0);
  m.no_force_homing = r.whole("NO_FORCE_HOMING", 0, 1).value_or(0) == 1;
  return letters;
}

// An axis as read: a value is absent when it could not be read.
struct axis_read {
  std::optional<double> min_limit, max_limit, max_velocity, max_acceleration, scale;
};

void read_axis(ini &f, char letter, axis &a, axis_read &got, int coord_line, int coord_col) {
  const std::string name = std::string("AXIS_") + letter;
  reader r(f, name);
  if (r.section_line() == 0) {
    f.add(coord_line, coord_col, "[TRAJ] COORDINATES",
          std::string("axis ") + letter + " has no [" + name + "] section: give its limits and speeds");
    return;
  }
  got.min_limit = r.required("MIN_LIMIT", "the soft limit at the negative end, machine units");
  got.max_limit = r.required("MAX_LIMIT", "the soft limit at the positive end, machine units");
  if (got.min_limit && got.max_limit && *got.min_limit >= *got.max_limit) {
    r.fail("MAX_LIMIT", "MAX_LIMIT " + number_text(*got.max_limit) + " must be above MIN_LIMIT " +
                            number_text(*got.min_limit));
    got.min_limit = got.max_limit = std::nullopt;
  }
  got.max_velocity = r.positive("MAX_VELOCITY", "the axis' top speed, units/s");
  got.max_acceleration = r.positive("MAX_ACCELERATION", "the axis' acceleration, units/s^2");
  a.min_limit = got.min_limit.value_or(0);
  a.max_limit = got.max_limit.value_or(0);
  a.max_velocity = got.max_velocity.value_or(0);
  a.max_acceleration = got.max_acceleration.value_or(0);
}

void read_homing(const reader &r, axis &a, const axis_read &got) {
  homing &h = a.home;
  const std::optional<double> search = r.number("HOME_SEARCH_VEL");
  h.search_vel = search.value_or(0);
  h.enabled = h.search_vel != 0;
  const char *needs_search[] = {"HOME_LATCH_VEL", "HOME_INPUT", "HOME_OFFSET", "HOME", "HOME_SEQUENCE"};
  if (!h.enabled) {
    if (search || !r.has("HOME_SEARCH_VEL"))
      for (const char *k : needs_search)
        if (r.has(k))
          r.fail(k, "no homing without HOME_SEARCH_VEL: give it (signed, toward the switch) or drop this");
    return;
  }
  const std::optional<double> latch =
      r.required("HOME_LATCH_VEL", "the speed that finds the switch's edge, units/s (signed)");
  h.latch_vel = latch.value_or(0);
  if (latch && h.latch_vel == 0) r.fail("HOME_LATCH_VEL", "must not be 0 while HOME_SEARCH_VEL is set");
  // LinuxCNC, given the same sign, backs off and latches where the switch trips on a second
  // approach; x4step would latch where it releases, the cam's length further: refused.
  if (latch && h.latch_vel != 0 && (h.latch_vel > 0) == (h.search_vel > 0))
    r.fail("HOME_LATCH_VEL", "HOME_LATCH_VEL " + number_text(h.latch_vel) +
                                 " has the sign of HOME_SEARCH_VEL " + number_text(h.search_vel) +
                                 ": x4step latches where the switch releases while moving away "
                                 "from it, so give HOME_LATCH_VEL the opposite sign of HOME_SEARCH_VEL");
  if (r.need("HOME_INPUT", "the home switch's input, 1..5"))
    h.input = static_cast<int>(r.whole("HOME_INPUT", 1, 5).value_or(0));
  const std::optional<double> offset = r.number("HOME_OFFSET"), home = r.number("HOME");
  h.offset = offset.value_or(0);
  h.home = home.value_or(0);
  h.sequence = static_cast<int>(r.whole("HOME_SEQUENCE", 0, 9).value_or(0));
  for (const char *k : {"HOME_SEARCH_VEL", "HOME_LATCH_VEL"}) {
    const bool search_key = k[5] == 'S';
    if (!search_key && !latch) continue;
    const double v = std::fabs(search_key ? h.search_vel : h.latch_vel);
    if (v == 0) continue;
    const std::string given = std::string(k) + " " + number_text(search_key ? h.search_vel : h.latch_vel);
    if (got.max_velocity && v > *got.max_velocity)
      r.fail(k, given + " is faster than the axis' MAX_VELOCITY " + number_text(*got.max_velocity));
    if (got.scale && v * std::fabs(*got.scale) > x4step::vel_max)
      r.fail(k, given + " is above 100000 steps/s at SCALE " + number_text(*got.scale));
    if (got.scale && v * std::fabs(*got.scale) < 1)
      r.fail(k, given + " is below 1 step/s at SCALE " + number_text(*got.scale));
  }
  if (!got.min_limit || !got.max_limit) return;
  const std::string limits = " is outside the axis' soft limits (MIN_LIMIT " + number_text(a.min_limit) +
                             " .. MAX_LIMIT " + number_text(a.max_limit) + ")";
  if (offset && (h.offset < a.min_limit || h.offset > a.max_limit))
    r.fail("HOME_OFFSET", "HOME_OFFSET " + number_text(h.offset) + limits);
  if (home && (h.home < a.min_limit || h.home > a.max_limit))
    r.fail("HOME", "HOME " + number_text(h.home) + limits);
}

void read_joint(ini &f, int n, char letter, axis &a, axis_read &got, int coord_line, int coord_col,
                std::array<int, x4step::axes> &motor_line, const machine &m) {
  const std::string name = "JOINT_" + std::to_string(n);
  reader r(f, name);
  if (r.section_line() == 0) {
    f.add(coord_line, coord_col, "[TRAJ] COORDINATES",
          std::string("axis ") + letter + " is joint " + std::to_string(n) + ": it needs a [" + name +
              "] section with MOTOR and SCALE");
    return;
  }
  if (r.need("MOTOR", "the motor (1..4) that drives axis " + std::string(1, letter))) {
    if (const auto motor = r.whole("MOTOR", 1, 4)) {
      a.motor = static_cast<int>(*motor) - 1;
      if (motor_line[size_t(a.motor)])
        r.fail("MOTOR", "motor " + std::to_string(a.motor + 1) + " drives another axis already (line " +
                            std::to_string(motor_line[size_t(a.motor)]) + "): one axis per motor");
      else
        motor_line[size_t(a.motor)] = r.line("MOTOR");
      if (a.motor == 3 && m.mode != output_mode::clock_dir)
        r.fail("MOTOR", "motor 4, but the SMC phase drive (OUTPUT_MODE) has motors 1..3 only");
    }
  }
  got.scale = r.required("SCALE", "steps per unit (negative reverses)");
  if (got.scale && *got.scale == 0) {
    r.fail("SCALE", "must not be 0: steps per unit, negative reverses");
    got.scale = std::nullopt;
  }
  if (got.scale) {
    a.scale = *got.scale;
    const double s = std::fabs(a.scale);
    const std::string at = " at SCALE " + number_text(a.scale);
    if (got.max_velocity && a.max_velocity * s > x4step::vel_max)
      r.fail("SCALE", "the axis' MAX_VELOCITY " + number_text(a.max_velocity) + " would be " +
                          std::to_string(long(a.max_velocity * s)) + " steps/s" + at +
                          ": the port steps at most 100000");
    if (got.max_acceleration && a.max_acceleration * s > x4step::acc_max)
      r.fail("SCALE", "the axis' MAX_ACCELERATION " + number_text(a.max_acceleration) + " would be " +
                          std::to_string(long(a.max_acceleration * s)) + " steps/s^2" + at +
                          ": at most 1000000");
    constexpr double coord_max = 2147483647.0;
    if (got.min_limit && got.max_limit &&
        (std::fabs(a.min_limit) * s > coord_max || std::fabs(a.max_limit) * s > coord_max))
      r.fail("SCALE", "the soft limits are beyond a motor's 32-bit step coordinate" + at);
  }
  read_homing(r, a, got);
}

// Axes homing at the same time on one input could not tell whose switch
// it was: the later one (in the file) of two such joints is refused.
void check_shared_inputs(ini &f, const machine &m, const std::string &letters) {
  for (size_t j = 0; j < letters.size(); j++)
    for (size_t i = 0; i < j; i++) {
      const std::optional<axis> &ai = m.axes[std::string("XYZABC").find(letters[i])];
      const std::optional<axis> &aj = m.axes[std::string("XYZABC").find(letters[j])];
      if (!ai || !aj) continue;
      const homing &a = ai->home, &b = aj->home;
      if (!a.enabled || !b.enabled || !a.input || a.input != b.input || a.sequence != b.sequence) continue;
      reader(f, "JOINT_" + std::to_string(j))
          .fail("HOME_SEQUENCE", "joint " + std::to_string(i) + " homes on input " + std::to_string(a.input) +
                                     " in sequence " + std::to_string(a.sequence) +
                                     " too: axes sharing a home switch input need different HOME_SEQUENCEs");
    }
}

std::string directory_of(const std::string &path) {
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}

// The names a section may have, for "did you mean".
std::vector<std::string> section_names() {
  std::vector<std::string> out;
  for (const key_name &k : x4step_keys)
    if (std::string(k.section).back() != '_' && !contains(out, k.section)) out.push_back(k.section);
  for (const char *s : linuxcnc_sections)
    if (std::string(s).back() != '_') out.push_back(s);
  return out;
}

}  // namespace

std::string nearest(const std::string &word, const std::vector<std::string> &names) {
  // Edit distance with swaps of neighbours (optimal string alignment).
  auto distance = [](const std::string &a, const std::string &b) {
    std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
    for (size_t i = 0; i <= a.size(); i++) d[i][0] = i;
    for (size_t j = 0; j <= b.size(); j++) d[0][j] = j;
    for (size_t i = 1; i <= a.size(); i++)
      for (size_t j = 1; j <= b.size(); j++) {
        d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] != b[j - 1])});
        if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
          d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    return d[a.size()][b.size()];
  };
  std::string best;
  size_t best_d = 0;
  for (const std::string &n : names) {
    if (n == word) continue;
    const size_t d = distance(word, n);
    // One edit in a short name, two in one of 6 letters or more.
    const size_t most = std::min(word.size(), n.size()) >= 6 ? 2 : 1;
    if (d <= most && (best.empty() || d < best_d)) {
      best = n;
      best_d = d;
    }
  }
  return best;
}

error::error(const std::string &file, int line, const std::string &key, const std::string &message)
    : error(file, std::vector<problem>{{line, 0, key, message}}) {}

namespace {
std::string problem_line(const std::string &file, const error::problem &p) {
  return where(file, p.line, p.col) + ": " + (p.key.empty() ? "" : p.key + ": ") + p.message;
}
std::string joined(const std::string &file, std::vector<error::problem> &problems) {
  std::stable_sort(problems.begin(), problems.end(), [](const error::problem &a, const error::problem &b) {
    return a.line != b.line ? a.line < b.line : a.col < b.col;
  });
  std::string out;
  for (const error::problem &p : problems) out += (out.empty() ? "" : "\n") + problem_line(file, p);
  return out;
}
}  // namespace

error::error(const std::string &file, std::vector<problem> problems)
    : std::runtime_error(joined(file, problems)), file_(file), problems_(std::move(problems)) {
  if (problems_.empty()) problems_.push_back({});
}

std::vector<std::string> error::lines() const {
  std::vector<std::string> out;
  for (const problem &p : problems_) out.push_back(problem_line(file_, p));
  return out;
}

std::string beyond_soft_limit(const machine &m, size_t a, double units) {
  const std::optional<axis> &ax = m.axes.at(a);
  if (!ax) return "";
  // The words are made only for a point beyond a limit.
  if (within_soft_limits(*ax, units)) return {};
  const bool below = units < ax->min_limit;
  auto text = [](double v) {
    std::ostringstream o;
    o << v;
    return o.str();
  };
  const std::string what = std::string(1, "XYZABC"[a]) + " " + text(units) +
                           " is beyond the soft limit [AXIS_" + "XYZABC"[a] + "] ";
  return below ? what + "MIN_LIMIT " + text(ax->min_limit) : what + "MAX_LIMIT " + text(ax->max_limit);
}

machine read(std::istream &in, const std::string &name) {
  ini f(in, name);
  machine m;
  // The names first: a misspelt key is the mistake to name, not the
  // required key it then lacks.
  std::vector<std::string> ignored_sections, ignored_keys;
  for (const std::string &s : f.order()) {
    const std::string kind = kind_of(s);
    const int line = f.find(s)->line;
    if (is_linuxcnc_section(kind)) {
      if (!is_x4step_section(kind)) ignored_sections.push_back("[" + s + "]");
    } else if (!is_x4step_section(kind)) {
      const std::string near = nearest(s, section_names());
      f.add(line, 1, "[" + s + "]",
            "unknown section" + (near.empty() ? "" : ": did you mean [" + near + "]?") +
                (near.empty() ? ": a machine file has EMC, EMCIO, RS274NGC, X4STEP, TRAJ, AXIS_<letter> and "
                                "JOINT_<n> (and LinuxCNC's own sections, which x4step ignores)"
                              : ""));
      continue;
    }
    std::vector<std::string> keys;
    reader(f, s).check_keys(keys);
    if (!keys.empty()) {
      std::string list = "[" + s + "]";
      for (const std::string &k : keys) list += " " + k;
      ignored_keys.push_back(list);
    }
  }
  reader emc(f, "EMC");
  if (const std::string *n = emc.text("MACHINE")) m.name = *n;
  reader io(f, "EMCIO");
  if (const std::string *t = io.text("TOOL_TABLE")) {
    if (t->empty())
      io.fail("TOOL_TABLE", "empty: give the tool table's file");
    else
      m.tool_table = (*t)[0] == '/' ? *t : directory_of(name) + *t;
  }
  reader ngc(f, "RS274NGC");
  if (const std::string *t = ngc.text("PARAMETER_FILE")) {
    if (t->empty())
      ngc.fail("PARAMETER_FILE", "empty: give the parameter file's name (e.g. x4step.var)");
    else
      m.parameter_file = (*t)[0] == '/' ? *t : directory_of(name) + *t;
  }

  read_x4step(f, m, !ignored_sections.empty());
  const std::string letters = read_traj(f, m);
  const reader traj(f, "TRAJ");
  const int coord_line = traj.line("COORDINATES"), coord_col = traj.col("COORDINATES");
  std::array<int, x4step::axes> motor_line{};
  for (size_t j = 0; j < letters.size(); j++) {
    const int a = static_cast<int>(std::string("XYZABC").find(letters[j]));
    axis ax;
    axis_read got;
    read_axis(f, letters[j], ax, got, coord_line, coord_col);
    read_joint(f, static_cast<int>(j), letters[j], ax, got, coord_line, coord_col, motor_line, m);
    m.axes[size_t(a)] = ax;
  }
  check_shared_inputs(f, m, letters);
  // Sections for axes or joints the machine does not have.
  for (const std::string &s : letters.empty() ? std::vector<std::string>{} : f.order()) {
    const int line = f.find(s)->line;
    if (kind_of(s) == "AXIS_" && (s.size() != 6 || letters.find(s[5]) == std::string::npos))
      f.add(line, 1, "[" + s + "]",
            "axis " + s.substr(5) + " is not in [TRAJ] COORDINATES (" + letters + "): add it or drop this");
    if (kind_of(s) == "JOINT_") {
      const char d = s[6];
      if (s.size() != 7 || d < '0' || d > '9' || size_t(d - '0') >= letters.size())
        f.add(line, 1, "[" + s + "]",
              "the machine has joints 0.." + std::to_string(letters.size() - 1) +
                  ", one per letter of [TRAJ] COORDINATES");
    }
  }
  if (!f.problems().empty()) throw error(name, std::move(f.problems()));
  // LinuxCNC's settings that x4step does not use, listed once.
  if (!ignored_sections.empty()) {
    std::string w = name + ": LinuxCNC sections x4step does not use, ignored:";
    for (const std::string &s : ignored_sections) w += " " + s;
    m.warnings.push_back(w);
  }
  if (!ignored_keys.empty()) {
    std::string w = name + ": LinuxCNC keys x4step does not use, ignored:";
    for (size_t i = 0; i < ignored_keys.size(); i++) w += (i ? "; " : " ") + ignored_keys[i];
    m.warnings.push_back(w);
  }
  return m;
}

machine read_file(const std::string &path) {
  std::ifstream in(path);
  if (!in) throw error(path, 0, "", "cannot read the machine file");
  return read(in, path);
}

}  // namespace x4step::machine
