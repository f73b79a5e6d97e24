// SPDX-License-Identifier: LGPL-2.1-or-later
// libx4step internals shared by its files (not installed): how it throws,
// and the end of a wait.
#ifndef X4STEP_DETAIL_HPP
#define X4STEP_DETAIL_HPP

#include <algorithm>
#include <chrono>
#include <climits>
#include <cstdint>
#include <string>

#include "port_io.hpp"
#include "x4step.hpp"

namespace x4step::detail {

[[noreturn]] void fail(errc e);

/// Steps for the kernel's checks (32 bits): beyond the range, a value they
/// also refuse.
inline std::int32_t narrow_steps(long s) {
  return static_cast<std::int32_t>(std::clamp<long>(s, -steps_max - 1, steps_max + 1));
}
/// An errno the library did not expect: std::system_category().
[[noreturn]] void fail_errno(int err, const std::string &what);
/// An ioctl's (or write's) errno as the X4Step error it means; `result`:
/// the X4Step code the kernel returned with EINVAL, if any.
[[noreturn]] void fail_ioctl(int err, const char *what, int result = 0);

// The end of a wait on the port's clock; a negative timeout never comes.
class deadline {
 public:
  deadline(std::chrono::milliseconds timeout, const port_io &io)
      : io_(io), forever_(timeout.count() < 0), end_(io.now() + timeout) {}
  bool expired() const { return !forever_ && io_.now() >= end_; }
  // Milliseconds for poll(): up to the end (rounded up, so that a timeout
  // has expired when poll() returns), at most cap if cap >= 0; -1 for ever.
  int poll_ms(int cap = -1) const {
    if (forever_) return cap;
    const auto left = std::chrono::ceil<std::chrono::milliseconds>(end_ - io_.now());
    const long long ms = std::max<long long>(0, left.count());
    return static_cast<int>(cap >= 0 ? std::min<long long>(ms, cap) : std::min<long long>(ms, INT_MAX));
  }

 private:
  const port_io &io_;
  bool forever_;
  std::chrono::steady_clock::time_point end_;
};

/// Library-internal access to a controller's port (paths use it).
struct access {
  static port_io &io(const controller &c);
};

}  // namespace x4step::detail

#endif  // X4STEP_DETAIL_HPP
