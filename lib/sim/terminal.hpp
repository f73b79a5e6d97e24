// SPDX-License-Identifier: LGPL-2.1-or-later
// The simulated port's keyboard: keys typed on the program's terminal
// brake its moves as the module's input handler does (kmod/x4step_keys.c).
// Internal to libx4step.
#ifndef X4STEP_SIM_TERMINAL_HPP
#define X4STEP_SIM_TERMINAL_HPP

#include <termios.h>

#include <functional>
#include <string_view>
#include <thread>
#include <vector>

namespace x4step::sim {

/// The set-1 make codes of the keys in bytes a terminal sent, by the
/// module's default key map: ESC 1, Enter 28, Space 57, the cursor keys
/// 72/75/77/80, Home 71, End 79, PgUp 73, PgDn 81, Insert 82, Delete 83,
/// and the main keyboard's characters (US layout: a 30, 1 2, ...).
/// Bytes of no key are left out.
std::vector<unsigned> terminal_keys(std::string_view bytes);

/// While `moving()` says a move runs (for 40 ms: a program that reads keys
/// itself has taken the terminal by then) and stdin is the foreground's
/// terminal in canonical mode (the program is not reading keys), reads stdin without
/// echo or line buffering and hands each key to `key` as a press and a
/// release (make code, then + 128); the terminal's mode is restored when
/// the move ends, when this ends, and at exit.
class terminal {
 public:
  terminal(std::function<bool()> moving, std::function<void(unsigned)> key);
  terminal(const terminal &) = delete;
  terminal &operator=(const terminal &) = delete;
  ~terminal();
  /// stdin is a terminal.
  static bool available();

 private:
  void run();
  void raw(bool on);

  std::function<bool()> moving_;
  std::function<void(unsigned)> key_;
  int quit_fd_ = -1;
  bool raw_ = false;
  termios saved_{};
  std::thread thread_;
};

}  // namespace x4step::sim

#endif  // X4STEP_SIM_TERMINAL_HPP
