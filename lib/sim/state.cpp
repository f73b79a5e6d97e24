// SPDX-License-Identifier: LGPL-2.1-or-later
// The simulated port's state between programs (X4STEP_SIM_STATE): what the
// module keeps while it stays loaded — each axis' coordinate and whether
// it is synchronized — and where the simulated machine's axes stand, so
// that separate x4ctl --sim runs (home, jog, touch off, run) rehearse one
// machine. Text, one line per axis of a port:
//
//   sim:0 axis 1 coordinate 1200 synced 1 machine 1200
//
// read when the port is made (lines of other ports are kept), written
// when the last descriptor of the port closes, atomically (temporary file
// and rename, under a flock()ed FILE.lock): only the axes this port changed
// since it read them, so that a monitor that closes after another
// program's moves does not put back what it read.
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "port.hpp"
#include "x4step.hpp"

namespace x4step::sim {
namespace {

[[noreturn]] void refuse(const std::string &what) { throw error(make_error_code(errc::lpt_not_found), what); }

struct axis_line {
  int port = 0, axis = 0;  // axis 1..4
  long long coordinate = 0, machine = 0;
  int synced = 0;
};

// Every line of the file; none if it does not exist.
std::vector<axis_line> read_lines(const std::string &path) {
  std::vector<axis_line> r;
  std::ifstream f(path);
  if (!f) {
    if (errno == ENOENT) return r;
    refuse("X4STEP_SIM_STATE=" + path + ": cannot read it: " + std::strerror(errno));
  }
  std::string l;
  for (int n = 1; std::getline(f, l); n++) {
    if (l.empty() || l[0] == '#') continue;
    axis_line a;
    char tail = 0;
    if (std::sscanf(l.c_str(), "sim:%d axis %d coordinate %lld synced %d machine %lld %c", &a.port, &a.axis,
                    &a.coordinate, &a.synced, &a.machine, &tail) != 5 ||
        a.port < 0 || a.port > 3 || a.axis < 1 || a.axis > 4 || (a.synced != 0 && a.synced != 1))
      refuse("X4STEP_SIM_STATE=" + path + ":" + std::to_string(n) + ": '" + l +
             "' is no state line (sim:N axis 1..4 coordinate C synced 0|1 machine M): remove the file to "
             "start afresh");
    r.push_back(a);
  }
  return r;
}

class lock_file {
 public:
  explicit lock_file(const std::string &path)
      : fd_(::open((path + ".lock").c_str(), O_RDONLY | O_CREAT | O_CLOEXEC, 0666)) {
    if (fd_ < 0) refuse("X4STEP_SIM_STATE=" + path + ": cannot open its lock file: " + std::strerror(errno));
    while (::flock(fd_, LOCK_EX) < 0 && errno != ENOSYS)  // ENOSYS: a kernel without file locks
      if (errno != EINTR) refuse("X4STEP_SIM_STATE=" + path + ": cannot lock: " + std::strerror(errno));
  }
  ~lock_file() {
    if (fd_ >= 0) ::close(fd_);
  }
  lock_file(const lock_file &) = delete;
  lock_file &operator=(const lock_file &) = delete;

 private:
  int fd_;
};

}  // namespace

void port::load_state_locked() {
  if (opt_.state.empty()) return;
  const lock_file l(opt_.state);
  s32 coord[X4_AXES] = {};
  std::array<std::int64_t, 4> pos = machine_.positions();
  u8 synced = 0;
  bool any = false;
  for (const axis_line &a : read_lines(opt_.state)) {
    if (a.port != number_) continue;
    const size_t i = size_t(a.axis - 1);
    kept_[i] = {a.coordinate, a.machine, a.synced};
    coord[i] = static_cast<s32>(a.coordinate);
    pos[i] = a.machine;
    if (a.synced) synced |= static_cast<u8>(1u << i);
    any = true;
  }
  if (!any) return;
  x4_engine_set_position(&eng_, 0x0f, coord);
  eng_.sync = synced;
  machine_.set_positions(pos);
}

// No throw: a destructor calls it. A state that cannot be kept is said.
void port::save_state_locked() {
  if (opt_.state.empty()) return;
  try {
    std::array<kept_axis, 4> now{};
    for (int i = 0; i < X4_AXES; i++) {
      x4_axis_state st{};
      x4_status_axis(&eng_, i, &st);
      now[size_t(i)] = {st.position, machine_.positions()[size_t(i)], (st.state & X4_AX_SYNC) ? 1 : 0};
    }
    if (now == kept_) return;  // nothing of this port's changed
    const lock_file l(opt_.state);
    std::vector<axis_line> lines = read_lines(opt_.state);
    for (int i = 0; i < X4_AXES; i++) {
      if (now[size_t(i)] == kept_[size_t(i)]) continue;  // the file's, whoever wrote it
      const kept_axis &k = now[size_t(i)];
      const axis_line mine{number_, i + 1, k.coordinate, k.machine, k.synced};
      auto it = std::find_if(lines.begin(), lines.end(),
                             [&](const axis_line &a) { return a.port == number_ && a.axis == i + 1; });
      if (it == lines.end())
        lines.push_back(mine);
      else
        *it = mine;
    }
    std::ostringstream text;
    text << "# x4step simulated port state (X4STEP_SIM_STATE); remove the file to start afresh\n";
    for (const axis_line &a : lines)
      text << "sim:" << a.port << " axis " << a.axis << " coordinate " << a.coordinate << " synced "
           << a.synced << " machine " << a.machine << "\n";
    const std::string tmp = opt_.state + ".tmp" + std::to_string(::getpid());
    {
      std::ofstream f(tmp);
      f << text.str();
      f.flush();
      if (!f) throw std::runtime_error("cannot write " + tmp + ": " + std::strerror(errno));
    }
    if (std::rename(tmp.c_str(), opt_.state.c_str()) < 0) {
      const std::string why = std::strerror(errno);
      std::remove(tmp.c_str());
      throw std::runtime_error("cannot replace it: " + why);
    }
  } catch (const std::exception &e) {
    std::fprintf(stderr, "X4STEP_SIM_STATE=%s: the simulated port's state is not kept: %s\n",
                 opt_.state.c_str(), e.what());
  }
}

}  // namespace x4step::sim
