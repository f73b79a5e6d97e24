// SPDX-License-Identifier: GPL-2.0
// The guest test programs' one assertion: a PASS or FAIL line per check
// (run-suite.sh shows the FAIL lines), and the count for the exit status.
#pragma once

#include <fcntl.h>
#include <poll.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

#if __has_include("x4step.hpp")  // programs built against the library
#include "x4step.hpp"
#define GUEST_CHECK_X4STEP
#endif

namespace guest {

inline int failures = 0;

// printf into a string, for the checks' texts.
inline std::string F(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
inline std::string F(const char *fmt, ...) {
  char buf[1024];
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(buf, sizeof(buf), fmt, ap);
  va_end(ap);
  return buf;
}

inline void Check(bool ok, const std::string &what) {
  std::printf("%s %s\n", ok ? "PASS" : "FAIL", what.c_str());
  if (!ok) failures++;
}

// Checks of edge timing to microseconds. A debug kernel (lockdep, KASAN)
// fires timers about 16 us late with as much jitter: there such a check is
// printed as SKIP, with its outcome, and does not count.
inline bool timing_checks = true;

inline void CheckTiming(bool ok, const std::string &what) {
  if (timing_checks) return Check(ok, what);
  std::printf("SKIP %s [%s; not checked on a debug kernel]\n", what.c_str(), ok ? "held" : "did not hold");
}

// A guest test's arguments: none, or --no-timing (on a debug kernel) to
// turn the timing checks off. False, after a usage line, on anything else.
inline bool TimingArgs(int argc, char **argv, const char *program) {
  if (argc == 2 && std::strcmp(argv[1], "--no-timing") == 0) {
    timing_checks = false;
    return true;
  }
  if (argc == 1) return true;
  std::fprintf(stderr, "usage: %s [--no-timing]\n", program);
  return false;
}

// Wait until a controller may open the device: poll() on a read-only
// descriptor reports POLLIN once no move runs and the module has ended the
// brake of a controller that closed (or was killed) while its moves ran.
// False on timeout.
inline bool WaitFree(const char *dev, int timeout_ms) {
  const int fd = open(dev, O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  bool free = false;
  for (;;) {
    pollfd p{fd, POLLIN, 0};
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now());
    if (poll(&p, 1, static_cast<int>(std::max<long long>(0, left.count()))) == 1) {
      free = (p.revents & POLLIN) != 0;
      break;
    }
    if (left.count() <= 0) break;
  }
  close(fd);
  return free;
}

// CLOCK_MONOTONIC in ns: the clock of the module's time stamps and of
// x4vport's trace (under -icount, guest time).
inline uint64_t NowNs() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return uint64_t(ts.tv_sec) * 1000000000u + uint64_t(ts.tv_nsec);
}

// Milliseconds since t.
inline double MsSince(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t).count();
}

// Waits until pred() holds, polling every 2 ms, up to timeout_ms; false on
// timeout. For a state or a count a test needs before its next step (a
// move at speed, some steps made), instead of a fixed sleep: without
// -icount the guest's time follows the host's clock, and a loaded host
// lets the guest do less in it.
template <typename Pred>
inline bool WaitFor(Pred pred, int timeout_ms = 10000) {
  const auto t0 = std::chrono::steady_clock::now();
  while (!pred()) {
    if (MsSince(t0) > timeout_ms) return false;
    usleep(2000);
  }
  return true;
}

// A file's whole text (debugfs and sysfs files); empty if unreadable.
inline std::string Slurp(const std::string &path) {
  std::string s;
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return s;
  char buf[65536];
  for (ssize_t n; (n = ::read(fd, buf, sizeof buf)) > 0;) s.append(buf, size_t(n));
  ::close(fd);
  return s;
}

// One write(2) of text; false if the file refused it.
inline bool Put(const std::string &path, const std::string &text) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool ok = ::write(fd, text.data(), text.size()) == ssize_t(text.size());
  return ::close(fd) == 0 && ok;
}

// Print the closing line; the program's exit status.
inline int Finish(const char *program) {
  std::printf("%s: %d failed\n", program, failures);
  return failures ? 1 : 0;
}

#ifdef GUEST_CHECK_X4STEP
// The x4step error code a C++ API call throws, errc::ok if none.
template <typename F>
x4step::errc Throws(F &&f) {
  try {
    f();
  } catch (const x4step::error &e) {
    return static_cast<x4step::errc>(e.code().value());
  }
  return x4step::errc::ok;
}
#endif

}  // namespace guest
