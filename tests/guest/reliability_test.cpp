// SPDX-License-Identifier: GPL-2.0
// In-guest reliability and access tests of the module: open/close cycles
// without leaks, a stress run whose step counts the host compares with the
// port trace, no kernel memory in what ioctls copy out, and no access for
// users outside the device's group.
#include <fcntl.h>
#include <linux/x4step.h>
#include <poll.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/utsname.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "check.hpp"

namespace {

using guest::Check;

const char *kDev = "/dev/x4step0";

long ReadLong(const char *path, const char *key = nullptr) {
  std::ifstream f(path);
  std::string word;
  long v = -1;
  if (!key) {
    f >> v;
    return v;
  }
  while (f >> word)
    if (word == key) {
      f >> v;
      break;
    }
  return v;
}

void OpenCloseCycles() {
  const long slab_before = ReadLong("/proc/meminfo", "Slab:");
  int bad = 0;
  for (int i = 0; i < 10000; i++) {
    const int fd = open(kDev, (i & 1) ? O_RDONLY : O_RDWR);
    if (fd < 0) {
      bad++;
      continue;
    }
    if (i % 100 == 0) {
      x4step_status st;
      ioctl(fd, X4STEP_GET_STATUS, &st);
    }
    close(fd);
  }
  const long slab_after = ReadLong("/proc/meminfo", "Slab:");
  std::printf("open/close: 10000 cycles, %d failed opens, slab %ld kB -> %ld kB\n", bad, slab_before,
              slab_after);
  Check(bad == 0, "10000 open/close cycles");
  Check(ReadLong("/sys/module/x4step/refcnt") == 0, "module reference count back to 0");
  // KASAN (the debug kernel) holds freed objects back: slab only grows.
  utsname u{};
  uname(&u);
  if (!std::strstr(u.release, "x4debug"))
    Check(slab_after - slab_before < 256, "no slab growth over 10000 cycles (< 256 kB)");
}

// Every byte an ioctl copies out is written by the kernel: read into a
// buffer filled with 0xa5, then with 0x5a; a byte that kept the pattern
// both times was not written (padding, a short copy). Fields that must
// be zero are checked too. `prepare` sets what an _IOWR command reads.
template <typename T>
bool ReadFilled(int fd, unsigned long cmd, T &out, const char *name, void (*prepare)(T &) = nullptr) {
  alignas(T) unsigned char a[sizeof(T)];
  alignas(T) unsigned char b[sizeof(T)];
  bool ok = true;
  for (unsigned char pattern : {0xa5, 0x5a}) {
    unsigned char *buf = pattern == 0xa5 ? a : b;
    std::memset(buf, pattern, sizeof(T));
    if (prepare) prepare(*reinterpret_cast<T *>(buf));
    ok &= ioctl(fd, cmd, buf) == 0;
  }
  Check(ok, std::string(name) + " reads");
  size_t kept = 0;
  for (size_t i = 0; i < sizeof(T); i++) kept += a[i] == 0xa5 && b[i] == 0x5a;
  Check(ok && !kept, std::string(name) + ": every byte written by the kernel (" + std::to_string(kept) +
                         " of " + std::to_string(sizeof(T)) + " kept the pattern)");
  std::memcpy(&out, b, sizeof(T));
  return ok;
}

template <typename R>
bool AllZero(const R &reserved) {
  for (auto r : reserved)
    if (r) return false;
  return true;
}

void NoKernelMemory() {
  const int fd = open(kDev, O_RDWR);
  x4step_info info;
  if (ReadFilled(fd, X4STEP_GET_INFO, info, "GET_INFO"))
    Check(AllZero(info.reserved), "GET_INFO reserved fields are zero");
  x4step_status st;
  if (ReadFilled(fd, X4STEP_GET_STATUS, st, "GET_STATUS"))
    Check(st.reserved0 == 0 && AllZero(st.reserved), "GET_STATUS reserved fields are zero");
  x4step_config cfg;
  if (ReadFilled(fd, X4STEP_GET_CONFIG, cfg, "GET_CONFIG"))
    Check(AllZero(cfg.reserved), "GET_CONFIG reserved fields are zero");
  x4step_step_timing stt;
  if (ReadFilled(fd, X4STEP_GET_STEP_TIMING, stt, "GET_STEP_TIMING"))
    Check(AllZero(stt.reserved), "GET_STEP_TIMING reserved fields are zero");
  x4step_timing tim;
  if (ReadFilled(fd, X4STEP_GET_TIMING, tim, "GET_TIMING"))
    Check(tim.reserved == 0, "GET_TIMING reserved field is zero");
  x4step_profile pr;
  if (ReadFilled(
          fd, X4STEP_GET_PROFILE, pr, "GET_PROFILE", +[](x4step_profile &p) { p.axis = 2; }))
    Check(pr.axis == 2 && AllZero(pr.reserved), "GET_PROFILE: the axis asked for, reserved fields are zero");
  x4step_switches sw;
  if (ReadFilled(fd, X4STEP_GET_SWITCHES, sw, "GET_SWITCHES"))
    Check(AllZero(sw.reserved), "GET_SWITCHES reserved fields are zero");
  x4step_axes ax;
  if (ReadFilled(fd, X4STEP_GET_AXES, ax, "GET_AXES"))
    Check(AllZero(ax.reserved), "GET_AXES reserved fields are zero");
  close(fd);
}

// Four axes at 20 kHz while a monitor polls the status in a tight loop
// and another thread floods the controller with refused ioctls.
void Stress() {
  const int fd = open(kDev, O_RDWR);
  std::atomic<bool> done{false};
  std::atomic<long> polls{0}, floods{0};
  std::thread monitor([&] {
    const int ro = open(kDev, O_RDONLY);
    x4step_status st;
    while (!done) {
      ioctl(ro, X4STEP_GET_STATUS, &st);
      polls++;
    }
    close(ro);
  });
  std::thread flood([&] {
    x4step_move bad{{0, 0, 0, 0}, 1000, 0, 0, 0};
    while (!done) {
      ioctl(fd, X4STEP_LOAD, &bad);            // NoSteps
      ioctl(fd, _IO(X4STEP_IOC_MAGIC, 0x7e));  // unknown
      floods += 2;
    }
  });
  x4step_move m{{20000, -20000, 15000, -5000}, 20000, 20, 0, 0};
  pollfd p{fd, POLLIN, 0};
  const bool ok = ioctl(fd, X4STEP_LOAD, &m) == 0 && ioctl(fd, X4STEP_START) == 0 && poll(&p, 1, 30000) == 1;
  done = true;
  monitor.join();
  flood.join();
  x4step_status st{};
  ioctl(fd, X4STEP_GET_STATUS, &st);
  std::printf("stress: %ld status reads and %ld refused ioctls during the move; steps %lld %lld %lld %lld\n",
              polls.load(), floods.load(), (long long)st.steps[0], (long long)st.steps[1],
              (long long)st.steps[2], (long long)st.steps[3]);
  Check(ok && st.steps[0] == 20000 && st.steps[1] == -20000 && st.steps[2] == 15000 && st.steps[3] == -5000,
        "4 axes at 20 kHz under load: every step made");
  std::printf("SEG 20000 -20000 15000 -5000\n");
  close(fd);
}

// The node is 0660 root:root here (no udev in the guest; the rule gives
// group lp): another user gets neither read-write nor read-only access.
void Access() {
  struct stat sb;
  Check(stat(kDev, &sb) == 0 && (sb.st_mode & 0777) == 0660, "device node mode 0660");
  const pid_t pid = fork();
  if (pid == 0) {
    if (setgid(1000) || setuid(1000)) _exit(2);
    const int rw = open(kDev, O_RDWR), rw_err = errno;
    const int ro = open(kDev, O_RDONLY), ro_err = errno;
    _exit(rw < 0 && rw_err == EACCES && ro < 0 && ro_err == EACCES ? 0 : 1);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  Check(WIFEXITED(status) && WEXITSTATUS(status) == 0, "an unprivileged user cannot open the device");
}

// The controller killed at random points of moves: each time the module
// brakes, lets go of the port, and the next controller opens.
void KilledAtRandomPoints() {
  unsigned seed = 12345;
  int ok = 0;
  for (int i = 0; i < 20; i++) {
    seed = seed * 1103515245 + 12345;
    const useconds_t delay = (seed >> 8) % 300000;
    int started[2];
    if (pipe(started)) return;
    const pid_t child = fork();
    if (child == 0) {
      const int fd = open(kDev, O_RDWR);
      x4step_move m{{4000, -3000, 2000, 1000}, 4000, 100, 0, 0};
      if (fd < 0 || ioctl(fd, X4STEP_LOAD, &m) || ioctl(fd, X4STEP_START)) _exit(1);
      if (write(started[1], "s", 1) != 1) _exit(1);
      for (;;) pause();
    }
    char c;
    const bool running = read(started[0], &c, 1) == 1;  // the move has started
    close(started[0]);
    close(started[1]);
    usleep(delay);
    kill(child, SIGKILL);
    waitpid(child, nullptr, 0);
    const int fd = open(kDev, O_RDWR);
    x4step_status st{};
    if (running && fd >= 0 && ioctl(fd, X4STEP_GET_STATUS, &st) == 0 && !(st.flags & X4STEP_ST_ACTIVE)) ok++;
    if (fd >= 0) close(fd);
    std::printf("SEG ? ? ? ?\n");
  }
  Check(ok == 20,
        "20 controllers killed at random points: braked, port free, next opens (" + std::to_string(ok) + ")");
}

}  // namespace

int main() {
  setvbuf(stdout, nullptr, _IOLBF, 0);
  OpenCloseCycles();
  NoKernelMemory();
  Access();
  Stress();
  KilledAtRandomPoints();
  return guest::Finish("reliability_test");
}
