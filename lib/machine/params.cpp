// SPDX-License-Identifier: LGPL-2.1-or-later
// The parameter file (params.hpp): LinuxCNC's .var text, read whole and
// replaced whole under a lock file.
#include "params.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace x4step::machine {

namespace {

constexpr int g28_base = 5161, g30_base = 5181, g92_on = 5210, g92_base = 5211, system_param = 5220;
int g5x_base(size_t system) { return 5221 + 20 * static_cast<int>(system); }

double get(const parameters &p, int n) {
  const auto it = p.find(n);
  return it == p.end() ? 0 : it->second;
}

std::string sys_error(const std::string &what, const std::string &path) {
  return path + ": " + what + ": " + std::strerror(errno);
}

// An open descriptor, closed however the scope ends.
class fd_guard {
 public:
  explicit fd_guard(int fd) : fd_(fd) {}
  ~fd_guard() {
    if (fd_ >= 0) ::close(fd_);
  }
  fd_guard(const fd_guard &) = delete;
  fd_guard &operator=(const fd_guard &) = delete;
  int get() const noexcept { return fd_; }
  int release() noexcept {
    const int f = fd_;
    fd_ = -1;
    return f;
  }

 private:
  int fd_;
};

void write_all(int fd, const std::string &text, const std::string &path) {
  for (size_t done = 0; done < text.size();) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw parameter_error(sys_error("cannot write", path));
    done += size_t(n);
  }
}

std::string directory_of(const std::string &path) {
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? "." : path.substr(0, slash + 1);
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

std::string format_parameters(const parameters &p) {
  std::string text;
  char line[64];
  for (const auto &[n, v] : p) {
    std::snprintf(line, sizeof line, "%d\t%.6f\n", n, v == 0 ? 0.0 : v);  // no "-0.000000"
    text += line;
  }
  return text;
}

parameters parse_parameters(const std::string &text, const std::string &name) {
  parameters p;
  std::istringstream in(text);
  std::string l;
  for (int n = 1; std::getline(in, l); n++) {
    if (l.find_first_not_of(" \t\r") == std::string::npos) continue;
    const char *s = l.c_str();
    char *end = nullptr;
    errno = 0;
    const long number = std::strtol(s, &end, 10);
    const char *v = end;
    double value = 0;
    if (end != s && !errno && (*v == ' ' || *v == '\t')) value = std::strtod(v, &end);
    if (end == v || end == s || errno || number < 1 || !std::isfinite(value))
      throw parameter_error(name + ":" + std::to_string(n) + ": '" + l +
                            "' is no parameter line: each line is NUMBER VALUE (5221 0.000000)");
    p[static_cast<int>(number)] = value;
  }
  return p;
}

parameters parameter_file::read_all() const {
  std::ifstream f(path_, std::ios::binary);
  if (!f) {
    if (errno == ENOENT) return {};
    throw parameter_error(sys_error("cannot read the parameter file", path_));
  }
  std::ostringstream text;
  text << f.rdbuf();
  if (f.bad()) throw parameter_error(sys_error("cannot read the parameter file", path_));
  return parse_parameters(text.str(), path_);
}

gcode::coordinate_state parameter_file::update(
    const std::function<void(gcode::coordinate_state &)> &change) const {
  const std::string lock_path = path_ + ".lock";
  const fd_guard lock(::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644));
  if (lock.get() < 0) throw parameter_error(sys_error("cannot create the lock file", lock_path));
  while (::flock(lock.get(), LOCK_EX) < 0)
    if (errno != EINTR) throw parameter_error(sys_error("cannot lock", lock_path));
  parameters p = read_all();
  const gcode::coordinate_state before = coordinates_of(p);
  gcode::coordinate_state after = before;
  change(after);
  if (after == before) return after;
  set_coordinates(p, after);
  // A new file beside the old one, then renamed over it: atomic.
  std::string tmp = path_ + ".XXXXXX";
  fd_guard out(::mkostemp(&tmp[0], O_CLOEXEC));
  if (out.get() < 0) throw parameter_error(sys_error("cannot write in " + directory_of(path_), path_));
  try {
    write_all(out.get(), format_parameters(p), tmp);
    if (::fchmod(out.get(), 0644) < 0 || ::fsync(out.get()) < 0)
      throw parameter_error(sys_error("cannot write", tmp));
    if (::close(out.release()) < 0) throw parameter_error(sys_error("cannot write", tmp));
    if (::rename(tmp.c_str(), path_.c_str()) < 0) throw parameter_error(sys_error("cannot replace", path_));
  } catch (...) {
    ::unlink(tmp.c_str());
    throw;
  }
  return after;
}

}  // namespace x4step::machine
