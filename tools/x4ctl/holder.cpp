// SPDX-License-Identifier: GPL-2.0
// x4ctl: finding a port's controller; holding a port in the background.
#include "holder.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <memory>
#include <string>

#include "cli.hpp"
#include "term.hpp"

namespace x4ctl {
namespace {

struct dir_closer {
  void operator()(DIR *d) const { ::closedir(d); }
};
using dir_ptr = std::unique_ptr<DIR, dir_closer>;

bool all_digits(const char *s) { return *s && std::strspn(s, "0123456789") == std::strlen(s); }

std::string canonical(const std::string &path) {
  char buf[PATH_MAX];
  return ::realpath(path.c_str(), buf) ? std::string(buf) : path;
}

// The open flags of /proc/PID/fd/FD, from its fdinfo ("flags:\t0100002").
int open_flags(const std::string &pid, const std::string &fd) {
  std::ifstream in("/proc/" + pid + "/fdinfo/" + fd);
  std::string name, value;
  while (in >> name >> value)
    if (name == "flags:") return static_cast<int>(std::strtol(value.c_str(), nullptr, 8));
  return 0;
}

}  // namespace

std::optional<holder> find_controller(const std::string &device) {
  const std::string want = canonical(device);
  const std::string self = std::to_string(::getpid());
  dir_ptr proc(::opendir("/proc"));
  if (!proc) return std::nullopt;
  while (const dirent *p = ::readdir(proc.get())) {
    if (!all_digits(p->d_name) || self == p->d_name) continue;
    const std::string pid = p->d_name;
    dir_ptr fds(::opendir(("/proc/" + pid + "/fd").c_str()));
    if (!fds) continue;  // gone, or another user's
    while (const dirent *f = ::readdir(fds.get())) {
      if (!all_digits(f->d_name)) continue;
      char target[PATH_MAX];
      const ssize_t n = ::readlink(("/proc/" + pid + "/fd/" + f->d_name).c_str(), target, sizeof target - 1);
      if (n <= 0 || want != std::string(target, static_cast<size_t>(n))) continue;
      if ((open_flags(pid, f->d_name) & O_ACCMODE) == O_RDONLY) continue;  // a monitor
      holder h;
      h.pid = static_cast<pid_t>(std::atol(pid.c_str()));
      std::ifstream("/proc/" + pid + "/comm") >> h.name;
      return h;
    }
  }
  return std::nullopt;
}

std::string parport_claimant(int parport) {
  std::ifstream active("/proc/sys/dev/parport/parport" + std::to_string(parport) + "/devices/active");
  std::string name;
  if (!(active >> name) || name == "none") return "";
  return name;
}

std::optional<holder> parport_user(const std::string &device) {
  struct stat sb {};
  if (::stat(device.c_str(), &sb) || !S_ISCHR(sb.st_mode)) return std::nullopt;
  return find_controller("/dev/parport" + std::to_string(minor(sb.st_rdev)));
}

std::vector<std::string> x4step_devices() {
  std::vector<int> numbers;
  dir_ptr dev(::opendir("/dev"));
  if (!dev) return {};
  while (const dirent *d = ::readdir(dev.get())) {
    const std::string name = d->d_name;
    if (name.rfind("x4step", 0) == 0 && all_digits(name.c_str() + 6))
      numbers.push_back(std::atoi(name.c_str() + 6));
  }
  std::sort(numbers.begin(), numbers.end());
  std::vector<std::string> paths;
  for (int n : numbers) paths.push_back("/dev/x4step" + std::to_string(n));
  return paths;
}

void hold_in_background(port &p, const std::function<void(console &)> &follow_it) {
  std::cout.flush();
  std::cerr.flush();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int err = errno;
    brake_quietly(p);
    throw failure(std::string("cannot go to the background: ") + std::strerror(err) +
                  "; the move was braked");
  }
  if (pid > 0) {
    std::cout << "running in the background as PID " << pid << "; 'x4ctl brake' ends it early\n"
              << std::flush;
    ::_exit(0);  // not exit(): the controller must stay open for the child
  }
  // The child: no terminal, so that a shell's hangup or Ctrl-C does not reach it.
  ::setsid();
  const int null = ::open("/dev/null", O_RDWR);
  if (null >= 0) {
    for (int fd = 0; fd <= 2; fd++) ::dup2(null, fd);
    if (null > 2) ::close(null);
  }
  std_console con(false);
  follow_it(con);
}

}  // namespace x4ctl
