// SPDX-License-Identifier: GPL-2.0
// x4ctl: when a held key counts as let go. A terminal reports no key
// release, only the key again and again while it is held (auto-repeat):
// the first repeat comes after the terminal's repeat delay (250 ms on the
// Linux console, 500-660 ms in X terminals), the next 25-33 times a
// second. So a key counts as held until no repeat has come for that long.
#ifndef X4CTL_HELD_KEY_HPP
#define X4CTL_HELD_KEY_HPP

#include <chrono>

namespace x4ctl {

class held_key {
 public:
  using time_point = std::chrono::steady_clock::time_point;
  /// The longest wait for the first repeat, and then between repeats.
  static constexpr std::chrono::milliseconds first_repeat{700}, repeat_gap{100};

  explicit held_key(time_point pressed) : last_(pressed) {}
  /// The key came again at t (once let go, it stays let go).
  void repeat(time_point t) {
    repeated_ = true;
    last_ = t;
  }
  /// Nothing came up to t: true once (and from then on) the key is let go.
  bool let_go(time_point t) {
    let_go_ = let_go_ || t - last_ > (repeated_ ? repeat_gap : first_repeat);
    return let_go_;
  }

 private:
  time_point last_;  // of the press or its latest repeat
  bool repeated_ = false, let_go_ = false;
};

}  // namespace x4ctl

#endif  // X4CTL_HELD_KEY_HPP
