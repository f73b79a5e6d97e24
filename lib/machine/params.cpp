// SPDX-License-Identifier: LGPL-2.1-or-later
// The parameter file (params.hpp): LinuxCNC's .var text, read whole and
// replaced whole under a lock file.
#include "params.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <sstream>

#include "files.hpp"

namespace x4step::machine {

namespace {

constexpr int g28_base = 5161, g30_base = 5181, g92_on = 5210, g92_base = 5211, system_param = 5220;
// LinuxCNC's groups have 9 axes (X Y Z A B C U V W) and it refuses a file
// that lacks one of them; the highest number it keeps is 5602.
constexpr int group_axes = 9, max_parameter = 5602;
int g5x_base(size_t system) { return 5221 + 20 * static_cast<int>(system); }

double get(const parameters &p, int n) {
  const auto it = p.find(n);
  return it == p.end() ? 0 : it->second;
}

}  // namespace

gcode::coordinate_state coordinates_of(const parameters &p) {
  gcode::coordinate_state c;
  for (size_t a = 0; a < gcode::n_axes; a++) {
    const int i = static_cast<int>(a);
    c.g28[a] = get(p, g28_base + i);
    c.g30[a] = get(p, g30_base + i);
    // LinuxCNC keeps the G92 values while 5210 says they do not apply (G92.2).
    c.g92[a] = p.count(g92_on) && get(p, g92_on) == 0 ? 0 : get(p, g92_base + i);
    for (size_t s = 0; s < c.g5x.size(); s++) c.g5x[s][a] = get(p, g5x_base(s) + i);
  }
  const double sys = get(p, system_param);
  c.system = sys >= 1 && sys <= 9 && sys == std::floor(sys) ? static_cast<int>(sys) - 1 : 0;
  return c;
}

void set_coordinates(parameters &p, const gcode::coordinate_state &c) {
  // U V W, which x4step does not have: as they are, or 0, so that
  // LinuxCNC finds every parameter it needs.
  for (int i = int(gcode::n_axes); i < group_axes; i++) {
    for (int base : {g28_base, g30_base, g92_base}) p.emplace(base + i, 0);
    for (size_t s = 0; s < c.g5x.size(); s++) p.emplace(g5x_base(s) + i, 0);
  }
  bool g92 = false;
  for (size_t a = 0; a < gcode::n_axes; a++) {
    const int i = static_cast<int>(a);
    p[g28_base + i] = c.g28[a];
    p[g30_base + i] = c.g30[a];
    p[g92_base + i] = c.g92[a];
    g92 = g92 || c.g92[a] != 0;
    for (size_t s = 0; s < c.g5x.size(); s++) p[g5x_base(s) + i] = c.g5x[s][a];
  }
  p[g92_on] = g92 ? 1 : 0;
  p[system_param] = c.system + 1;
}

void apply_changes(gcode::coordinate_state &into, const gcode::coordinate_state &before,
                   const gcode::coordinate_state &after) {
  auto pose = [](gcode::pose &i, const gcode::pose &b, const gcode::pose &a) {
    for (size_t n = 0; n < i.size(); n++)
      if (a[n] != b[n]) i[n] = a[n];
  };
  for (size_t s = 0; s < into.g5x.size(); s++) pose(into.g5x[s], before.g5x[s], after.g5x[s]);
  pose(into.g28, before.g28, after.g28);
  pose(into.g30, before.g30, after.g30);
  pose(into.g92, before.g92, after.g92);
  if (after.system != before.system) into.system = after.system;
}

// Numbers are written and read without the C locale's help: a program
// that set LC_NUMERIC to a decimal comma still writes LinuxCNC's points.
std::string format_parameters(const parameters &p) {
  std::string text;
  char buf[64];
  for (const auto &[n, v] : p) {
    const double value = std::fabs(v) < 5e-7 ? 0.0 : v;  // no "-0.000000"
    const auto r = std::to_chars(buf, buf + sizeof buf, value, std::chars_format::fixed, 6);
    text += std::to_string(n) + "\t" + std::string(buf, r.ptr) + "\n";
  }
  return text;
}

parameters parse_parameters(const std::string &text, const std::string &name) {
  parameters p;
  std::istringstream in(text);
  std::string l;
  for (int n = 1; std::getline(in, l); n++) {
    const auto blank = [&](size_t i) { return l.find_first_not_of(" \t\r", i); };
    if (blank(0) == std::string::npos) continue;
    const char *s = l.c_str() + blank(0), *end = l.c_str() + l.size();
    int number = 0;
    double value = 0;
    auto r = std::from_chars(s, end, number);
    const char *v = r.ptr;
    bool ok = r.ec == std::errc() && v != end && (*v == ' ' || *v == '\t');
    if (ok) {
      v = l.c_str() + blank(size_t(v - l.c_str()));
      if (*v == '+') v++;  // from_chars takes no plus sign
      r = std::from_chars(v, end, value);
      ok = r.ec == std::errc() && blank(size_t(r.ptr - l.c_str())) == std::string::npos;
    }
    const std::string at = name + ":" + std::to_string(n) + ": ";
    if (!ok || !std::isfinite(value))
      throw parameter_error(at + "'" + l +
                            "' is no parameter line: each line is NUMBER VALUE (5221 0.000000)");
    if (number < 1 || number > max_parameter)
      throw parameter_error(at + "parameter " + std::to_string(number) + " is outside 1.." +
                            std::to_string(max_parameter));
    if (!p.emplace(number, value).second)
      throw parameter_error(at + "parameter " + std::to_string(number) + " is given twice");
  }
  return p;
}

parameters parameter_file::read_all() const {
  try {
    return parse_parameters(read_text(path_, true, "cannot read the parameter file"), path_);
  } catch (const file_error &e) {
    throw parameter_error(e.what());
  }
}

gcode::coordinate_state parameter_file::update(
    const std::function<void(gcode::coordinate_state &)> &change) const {
  try {
    const file_lock lock(path_);
    parameters p = read_all();
    const gcode::coordinate_state before = coordinates_of(p);
    gcode::coordinate_state after = before;
    change(after);
    if (after == before) return after;
    set_coordinates(p, after);
    replace_file(path_, format_parameters(p));
    return after;
  } catch (const file_error &e) {
    throw parameter_error(e.what());
  }
}

}  // namespace x4step::machine
