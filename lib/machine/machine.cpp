// SPDX-License-Identifier: LGPL-2.1-or-later
// The machine file: read the INI text whole, then check every section and
// key against what x4step knows, so that nothing is skipped silently.
#include "machine.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <vector>

#include "x4step.hpp"

namespace x4step::machine {

namespace {

std::string where(const std::string &file, int line) {
  return line > 0 ? file + ":" + std::to_string(line) : file;
}

struct entry {
  std::string value;
  int line = 0;
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

// The whole file as sections of keys, each with its line; the syntax alone.
class ini {
 public:
  ini(std::istream &in, std::string file) : file_(std::move(file)) {
    std::string text;
    section *cur = nullptr;
    std::string cur_name;
    for (int n = 1; std::getline(in, text); n++) {
      const std::string t = trim(text);
      if (t.empty() || t[0] == '#' || t[0] == ';') continue;
      if (t[0] == '[') {
        if (t.back() != ']' || t.size() < 3)
          throw error(file_, n, "", "'" + t + "' is no section header: write [NAME]");
        cur_name = upper(trim(t.substr(1, t.size() - 2)));
        auto [it, fresh] = sections_.try_emplace(cur_name);
        if (!fresh)
          throw error(
              file_, n, "[" + cur_name + "]",
              "section given twice (first at line " + std::to_string(it->second.line) + "): merge them");
        it->second.line = n;
        cur = &it->second;
        order_.push_back(cur_name);
        continue;
      }
      const size_t eq = t.find('=');
      if (eq == std::string::npos)
        throw error(file_, n, cur ? "[" + cur_name + "]" : "", "'" + t + "': write KEY = VALUE");
      const std::string key = upper(trim(t.substr(0, eq)));
      if (!cur) throw error(file_, n, key, "a key before any [SECTION]: put it in its section");
      if (key.empty()) throw error(file_, n, "[" + cur_name + "]", "'" + t + "' has no key before '='");
      auto [it, fresh] = cur->keys.try_emplace(key);
      if (!fresh)
        throw error(file_, n, "[" + cur_name + "] " + key,
                    "given twice (first at line " + std::to_string(it->second.line) + "): keep one");
      it->second.value = trim(t.substr(eq + 1));
      it->second.line = n;
    }
    if (in.bad()) throw error(file_, 0, "", "read error");
  }

  const std::string &file() const { return file_; }
  const std::vector<std::string> &order() const { return order_; }
  section *find(const std::string &name) {
    auto it = sections_.find(name);
    return it == sections_.end() ? nullptr : &it->second;
  }

 private:
  std::string file_;
  std::map<std::string, section> sections_;
  std::vector<std::string> order_;
};

// The keys of one section, taken by name; unknown keys are refused at the end.
class reader {
 public:
  reader(const ini &f, std::string name, section *s) : f_(f), name_(std::move(name)), s_(s) {}

  bool has(const std::string &key) const { return s_ && s_->keys.count(key); }
  int line(const std::string &key) const { return has(key) ? s_->keys.at(key).line : section_line(); }
  int section_line() const { return s_ ? s_->line : 0; }

  [[noreturn]] void fail(const std::string &key, const std::string &what) const {
    throw error(f_.file(), line(key), "[" + name_ + "] " + key, what);
  }
  [[noreturn]] void fail_section(const std::string &what) const {
    throw error(f_.file(), section_line(), "[" + name_ + "]", what);
  }

  const std::string *text(const std::string &key) {
    if (!has(key)) return nullptr;
    return &s_->keys.at(key).value;
  }
  std::string required_text(const std::string &key, const std::string &what) {
    const std::string *t = text(key);
    if (!t) fail(key, "missing: give " + what);
    return *t;
  }

  std::optional<double> number(const std::string &key) {
    const std::string *t = text(key);
    if (!t) return std::nullopt;
    char *end = nullptr;
    errno = 0;
    const double v = std::strtod(t->c_str(), &end);
    if (t->empty() || *end || errno || !std::isfinite(v)) fail(key, "'" + *t + "' is no number");
    return v;
  }
  double required(const std::string &key, const std::string &what) {
    if (!has(key)) fail(key, "missing: give " + what);
    return *number(key);
  }
  double positive(const std::string &key, const std::string &what) {
    const double v = required(key, what);
    if (v <= 0) fail(key, "'" + *text(key) + "': must be above 0 (" + what + ")");
    return v;
  }
  std::optional<long> whole(const std::string &key, long min, long max) {
    const std::optional<double> v = number(key);
    if (!v) return std::nullopt;
    if (*v != std::floor(*v) || *v < min || *v > max)
      fail(key,
           "'" + *text(key) + "': use a whole number " + std::to_string(min) + ".." + std::to_string(max));
    return static_cast<long>(*v);
  }

  // Unknown keys first: a misspelt key is the mistake to name, not the
  // required key it then lacks. known: "A, B and C".
  void refuse_unknown(const std::string &known) const {
    if (!s_) return;
    std::string list = known;
    for (size_t p; (p = list.find(" and ")) != std::string::npos;) list.replace(p, 5, ", ");
    const std::string keys = ", " + list + ", ";
    for (const auto &[key, e] : s_->keys)
      if (keys.find(", " + key + ", ") == std::string::npos)
        fail(key, "unknown key: [" + name_ + "] takes " + known);
  }

 private:
  const ini &f_;
  std::string name_;
  section *s_;
};

gcode::units units_of(reader &r) {
  const std::string u = upper(r.required_text("LINEAR_UNITS", "mm or inch"));
  if (u == "MM" || u == "METRIC") return gcode::units::mm;
  if (u == "INCH" || u == "IN" || u == "IMPERIAL") return gcode::units::inch;
  r.fail("LINEAR_UNITS", "'" + u + "': use mm or inch");
}

pin pin_of(reader &r, const std::string &key) {
  const std::string *t = r.text(key);
  if (!t || upper(*t) == "NONE") return pin::none;
  if (*t == "1") return pin::pin1;
  if (*t == "14") return pin::pin14;
  r.fail(key, "'" + *t + "': use 1 (signal 1), 14 (signal 2) or none");
}

void read_x4step(ini &f, machine &m) {
  reader r(f, "X4STEP", f.find("X4STEP"));
  r.refuse_unknown(
      "PORT, OUTPUT_MODE, ARC_TOLERANCE, JUNCTION_DEVIATION, SPINDLE_PIN, FLOOD_PIN and MIST_PIN");
  if (r.section_line() == 0)
    throw error(f.file(), 0, "[X4STEP]",
                "no [X4STEP] section: it needs ARC_TOLERANCE and JUNCTION_DEVIATION");
  if (const std::string *p = r.text("PORT")) {
    const std::string u = upper(*p);
    if (u.size() != 4 || u.compare(0, 3, "LPT") || u[3] < '1' || u[3] > '4')
      r.fail("PORT", "'" + *p + "': use LPT1, LPT2, LPT3 or LPT4");
    m.port = u;
  }
  if (const std::string *o = r.text("OUTPUT_MODE")) {
    if (*o == "step-dir")
      m.mode = output_mode::step_dir;
    else if (*o == "smc-phase")
      m.mode = output_mode::smc_phase;
    else if (*o == "smc-hold")
      m.mode = output_mode::smc_hold;
    else
      r.fail("OUTPUT_MODE", "'" + *o + "': use step-dir, smc-phase or smc-hold");
  }
  m.arc_tolerance = r.positive("ARC_TOLERANCE", "the most a chord may leave an arc, in machine units");
  m.junction_deviation = r.required("JUNCTION_DEVIATION", "GRBL's junction deviation, in machine units");
  if (m.junction_deviation < 0) r.fail("JUNCTION_DEVIATION", "must be 0 (stop at every corner) or more");
  m.spindle = pin_of(r, "SPINDLE_PIN");
  m.flood = pin_of(r, "FLOOD_PIN");
  m.mist = pin_of(r, "MIST_PIN");
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

// [TRAJ]: the axis letters in joint order.
std::string read_traj(ini &f, machine &m) {
  reader r(f, "TRAJ", f.find("TRAJ"));
  r.refuse_unknown("COORDINATES, LINEAR_UNITS, ANGULAR_UNITS, MAX_LINEAR_VELOCITY and NO_FORCE_HOMING");
  if (r.section_line() == 0)
    throw error(f.file(), 0, "[TRAJ]", "no [TRAJ] section: it needs COORDINATES and LINEAR_UNITS");
  const std::string coords = upper(r.required_text("COORDINATES", "the axis letters, e.g. XYZ"));
  std::string letters;
  for (char c : coords) {
    if (c == ' ' || c == '\t') continue;
    if (std::string("XYZABC").find(c) == std::string::npos)
      r.fail("COORDINATES", std::string("'") + c + "' is no axis: use letters of XYZABC");
    if (letters.find(c) != std::string::npos)
      r.fail("COORDINATES", std::string("axis ") + c + " given twice: one motor per axis");
    letters += c;
  }
  if (letters.empty()) r.fail("COORDINATES", "no axis: give the axis letters, e.g. XYZ");
  if (letters.size() > size_t(x4step::axes))
    r.fail("COORDINATES", "'" + letters + "': a port drives at most 4 motors");
  m.units = units_of(r);
  if (const std::string *a = r.text("ANGULAR_UNITS"))
    if (upper(*a) != "DEGREE" && upper(*a) != "DEG")
      r.fail("ANGULAR_UNITS", "'" + *a + "': rotary axes are in degrees (degree)");
  if (r.has("MAX_LINEAR_VELOCITY"))
    m.max_linear_velocity = r.positive("MAX_LINEAR_VELOCITY", "the most along the path, units/s");
  m.no_force_homing = r.whole("NO_FORCE_HOMING", 0, 1).value_or(0) == 1;
  return letters;
}

void read_axis(ini &f, char letter, axis &a, int coord_line, const std::string &file) {
  const std::string name = std::string("AXIS_") + letter;
  reader r(f, name, f.find(name));
  if (r.section_line() == 0)
    throw error(file, coord_line, "[TRAJ] COORDINATES",
                std::string("axis ") + letter + " has no [" + name + "] section: give its limits and speeds");
  r.refuse_unknown("MIN_LIMIT, MAX_LIMIT, MAX_VELOCITY and MAX_ACCELERATION");
  a.min_limit = r.required("MIN_LIMIT", "the soft limit at the negative end, machine units");
  a.max_limit = r.required("MAX_LIMIT", "the soft limit at the positive end, machine units");
  if (a.min_limit >= a.max_limit) r.fail("MAX_LIMIT", "must be above MIN_LIMIT");
  a.max_velocity = r.positive("MAX_VELOCITY", "the axis' top speed, units/s");
  a.max_acceleration = r.positive("MAX_ACCELERATION", "the axis' acceleration, units/s^2");
}

void read_homing(reader &r, axis &a) {
  homing &h = a.home;
  h.search_vel = r.number("HOME_SEARCH_VEL").value_or(0);
  h.enabled = h.search_vel != 0;
  const char *needs_search[] = {"HOME_LATCH_VEL", "HOME_INPUT", "HOME_OFFSET", "HOME", "HOME_SEQUENCE"};
  if (!h.enabled) {
    for (const char *k : needs_search)
      if (r.has(k))
        r.fail(k, "no homing without HOME_SEARCH_VEL: give it (signed, toward the switch) or drop this");
    return;
  }
  h.latch_vel = r.required("HOME_LATCH_VEL", "the speed that finds the switch's edge, units/s (signed)");
  if (h.latch_vel == 0) r.fail("HOME_LATCH_VEL", "must not be 0 while HOME_SEARCH_VEL is set");
  // LinuxCNC, given the same sign, backs off and latches where the switch trips on a second
  // approach; x4step would latch where it releases, the cam's length further: refused.
  if ((h.latch_vel > 0) == (h.search_vel > 0))
    r.fail("HOME_LATCH_VEL",
           "has the sign of HOME_SEARCH_VEL: x4step latches where the switch releases while moving away "
           "from it, so give HOME_LATCH_VEL the opposite sign of HOME_SEARCH_VEL");
  if (!r.has("HOME_INPUT")) r.fail("HOME_INPUT", "missing: give the home switch's input, 1..5");
  h.input = static_cast<int>(*r.whole("HOME_INPUT", 1, 5));
  h.offset = r.number("HOME_OFFSET").value_or(0);
  h.home = r.number("HOME").value_or(0);
  h.sequence = static_cast<int>(r.whole("HOME_SEQUENCE", 0, 9).value_or(0));
  for (const char *k : {"HOME_SEARCH_VEL", "HOME_LATCH_VEL"}) {
    const double v = std::fabs(k[5] == 'S' ? h.search_vel : h.latch_vel);
    if (v > a.max_velocity) r.fail(k, "faster than the axis' MAX_VELOCITY");
    if (v * std::fabs(a.scale) > x4step::vel_max) r.fail(k, "above 100000 steps/s at this SCALE");
    if (v * std::fabs(a.scale) < 1) r.fail(k, "below 1 step/s at this SCALE");
  }
  if (h.offset < a.min_limit || h.offset > a.max_limit)
    r.fail("HOME_OFFSET", "outside the axis' soft limits (MIN_LIMIT..MAX_LIMIT)");
  if (h.home < a.min_limit || h.home > a.max_limit)
    r.fail("HOME", "outside the axis' soft limits (MIN_LIMIT..MAX_LIMIT)");
}

void read_joint(ini &f, int n, char letter, axis &a, int coord_line, const std::string &file,
                std::array<int, x4step::axes> &motor_line, machine &m) {
  const std::string name = "JOINT_" + std::to_string(n);
  reader r(f, name, f.find(name));
  if (r.section_line() == 0)
    throw error(file, coord_line, "[TRAJ] COORDINATES",
                std::string("axis ") + letter + " is joint " + std::to_string(n) + ": it needs a [" + name +
                    "] section with MOTOR and SCALE");
  r.refuse_unknown(
      "MOTOR, SCALE, HOME_SEARCH_VEL, HOME_LATCH_VEL, HOME_INPUT, HOME_OFFSET, HOME and HOME_SEQUENCE");
  if (!r.has("MOTOR"))
    r.fail("MOTOR", "missing: give the motor (1..4) that drives axis " + std::string(1, letter));
  a.motor = static_cast<int>(*r.whole("MOTOR", 1, 4)) - 1;
  if (motor_line[size_t(a.motor)])
    r.fail("MOTOR", "motor " + std::to_string(a.motor + 1) + " drives another axis already (line " +
                        std::to_string(motor_line[size_t(a.motor)]) + "): one axis per motor");
  motor_line[size_t(a.motor)] = r.line("MOTOR");
  if (a.motor == 3 && m.mode != output_mode::step_dir)
    r.fail("MOTOR", "the SMC phase drive (OUTPUT_MODE) has motors 1..3 only");
  a.scale = r.required("SCALE", "steps per unit (negative reverses)");
  if (a.scale == 0) r.fail("SCALE", "must not be 0: steps per unit, negative reverses");
  const double s = std::fabs(a.scale);
  if (a.max_velocity * s > x4step::vel_max)
    r.fail("SCALE", "the axis' MAX_VELOCITY would be " + std::to_string(long(a.max_velocity * s)) +
                        " steps/s: the port steps at most 100000");
  if (a.max_acceleration * s > x4step::acc_max)
    r.fail("SCALE", "the axis' MAX_ACCELERATION would be " + std::to_string(long(a.max_acceleration * s)) +
                        " steps/s^2: at most 1000000");
  constexpr double coord_max = 2147483647.0;
  if (std::fabs(a.min_limit) * s > coord_max || std::fabs(a.max_limit) * s > coord_max)
    r.fail("SCALE", "the soft limits are beyond a motor's 32-bit step coordinate");
  read_homing(r, a);
}

// Axes homing at the same time on one input could not tell whose switch
// it was: the later one (in the file) of two such joints is refused.
void check_shared_inputs(ini &f, const machine &m, const std::string &letters) {
  for (size_t j = 0; j < letters.size(); j++)
    for (size_t i = 0; i < j; i++) {
      const homing &a = m.axes[std::string("XYZABC").find(letters[i])]->home;
      const homing &b = m.axes[std::string("XYZABC").find(letters[j])]->home;
      if (!a.enabled || !b.enabled || a.input != b.input || a.sequence != b.sequence) continue;
      const std::string name = "JOINT_" + std::to_string(j);
      reader(f, name, f.find(name))
          .fail("HOME_SEQUENCE", "joint " + std::to_string(i) + " homes on input " + std::to_string(a.input) +
                                     " in sequence " + std::to_string(a.sequence) +
                                     " too: axes sharing a home switch input need different HOME_SEQUENCEs");
    }
}

std::string directory_of(const std::string &path) {
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}

}  // namespace

error::error(const std::string &file, int line, const std::string &key, const std::string &message)
    : std::runtime_error(where(file, line) + ": " + (key.empty() ? "" : key + ": ") + message),
      line_(line),
      key_(key) {}

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
  for (const std::string &s : f.order()) {
    const bool known = s == "EMC" || s == "EMCIO" || s == "RS274NGC" || s == "X4STEP" || s == "TRAJ" ||
                       (s.size() == 6 && s.compare(0, 5, "AXIS_") == 0) ||
                       (s.size() == 7 && s.compare(0, 6, "JOINT_") == 0);
    if (!known)
      throw error(name, f.find(s)->line, "[" + s + "]",
                  "unknown section: a machine file has EMC, EMCIO, RS274NGC, X4STEP, TRAJ, AXIS_<letter> and "
                  "JOINT_<n>");
  }
  reader emc(f, "EMC", f.find("EMC"));
  emc.refuse_unknown("MACHINE");
  if (const std::string *n = emc.text("MACHINE")) m.name = *n;
  reader io(f, "EMCIO", f.find("EMCIO"));
  io.refuse_unknown("TOOL_TABLE");
  if (const std::string *t = io.text("TOOL_TABLE")) {
    if (t->empty()) io.fail("TOOL_TABLE", "empty: give the tool table's file");
    m.tool_table = (*t)[0] == '/' ? *t : directory_of(name) + *t;
  }
  reader ngc(f, "RS274NGC", f.find("RS274NGC"));
  ngc.refuse_unknown("PARAMETER_FILE");
  if (const std::string *t = ngc.text("PARAMETER_FILE")) {
    if (t->empty()) ngc.fail("PARAMETER_FILE", "empty: give the parameter file's name (e.g. x4step.var)");
    m.parameter_file = (*t)[0] == '/' ? *t : directory_of(name) + *t;
  }

  read_x4step(f, m);
  const std::string letters = read_traj(f, m);
  const int coord_line = reader(f, "TRAJ", f.find("TRAJ")).line("COORDINATES");
  std::array<int, x4step::axes> motor_line{};
  for (size_t j = 0; j < letters.size(); j++) {
    const int a = static_cast<int>(std::string("XYZABC").find(letters[j]));
    axis ax;
    read_axis(f, letters[j], ax, coord_line, name);
    read_joint(f, static_cast<int>(j), letters[j], ax, coord_line, name, motor_line, m);
    m.axes[size_t(a)] = ax;
  }
  check_shared_inputs(f, m, letters);
  // Sections for axes or joints the machine does not have.
  for (const std::string &s : f.order()) {
    if (s.compare(0, 5, "AXIS_") == 0 && letters.find(s[5]) == std::string::npos)
      throw error(
          name, f.find(s)->line, "[" + s + "]",
          "axis " + s.substr(5) + " is not in [TRAJ] COORDINATES (" + letters + "): add it or drop this");
    if (s.compare(0, 6, "JOINT_") == 0) {
      const char d = s[6];
      if (d < '0' || d > '9' || size_t(d - '0') >= letters.size())
        throw error(name, f.find(s)->line, "[" + s + "]",
                    "the machine has joints 0.." + std::to_string(letters.size() - 1) +
                        ", one per letter of [TRAJ] COORDINATES");
    }
  }
  return m;
}

machine read_file(const std::string &path) {
  std::ifstream in(path);
  if (!in) throw error(path, 0, "", "cannot read the machine file");
  return read(in, path);
}

}  // namespace x4step::machine
