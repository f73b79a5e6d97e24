// SPDX-License-Identifier: GPL-2.0
// x4ctl: the terminal (raw mode, ESC and cursor keys) and signals.
#ifndef X4CTL_TERM_HPP
#define X4CTL_TERM_HPP

#include <sys/types.h>
#include <termios.h>

#include <iostream>
#include <memory>
#include <string>
#include <string_view>

#include "io.hpp"

namespace x4ctl {

/// Signals become requests that the consoles report as keys:
/// SIGINT: interrupt (brake, a second one stops) and quit;
/// SIGTERM, SIGHUP: brake and quit; SIGUSR1: brake (`x4ctl brake`);
/// SIGUSR2: stop (`x4ctl stop`). A SIGUSR1 or SIGUSR2 sent by sigqueue()
/// carries an axis mask: the axes to halt (`x4ctl halt`); else all.
void install_signal_handlers();
/// The oldest pending request, each signal once; key::none if there is none.
key take_signal();
/// The axes of the brake or stop request take_signal returned last.
x4step::axis_set taken_axes();
/// Asks the x4ctl pid to brake (SIGUSR1) or stop (SIGUSR2) the axes.
/// False with errno set if it cannot be signalled.
bool send_request(pid_t pid, bool stop, x4step::axis_set axes);
/// SIGINT, SIGTERM or SIGHUP came: end after the current move.
bool quit_requested();

/// The width of the terminal on fd in columns (TIOCGWINSZ), else
/// $COLUMNS, else 80: what a line redrawn in place may take.
size_t terminal_columns(int fd);

/// Waits up to timeout, less if a signal comes.
void nap(milliseconds timeout);

/// Non-canonical input without echo and without signal keys (Ctrl-C is
/// read as a key) for as long as it lives; nothing if fd is no terminal.
class raw_mode {
 public:
  explicit raw_mode(int fd);
  ~raw_mode();
  raw_mode(const raw_mode &) = delete;
  raw_mode &operator=(const raw_mode &) = delete;

 private:
  int fd_;
  bool active_ = false;
  termios saved_{};
};

/// One key decoded from the start of bytes; used = 0 when more bytes are
/// needed (an ESC could begin a cursor key's sequence). With complete,
/// nothing more will come: a lone ESC is the ESC key.
struct decoded {
  key k = key::none;
  size_t used = 0;
  char ch = 0;  ///< a key of one byte: that byte (a letter, Enter, Backspace); else 0
};
decoded decode_key(std::string_view bytes, bool complete);

/// A typed line without escape sequences and control characters: an ESC
/// pressed just after a move ended (the module brakes on the key itself)
/// lands in the next line, as do cursor keys pressed at the prompt.
std::string strip_keys(std::string_view line);

/// The console of a program run from a shell: standard output, and keys
/// from standard input when it is a terminal and keyboard is wanted.
class std_console : public console {
 public:
  explicit std_console(bool keyboard);
  std::ostream &out() override { return std::cout; }
  bool live() const override { return live_; }
  bool has_keyboard() const override { return keyboard_; }
  void keys_on() override;
  void keys_off() override;
  key read_key(milliseconds timeout) override;
  x4step::axis_set requested_axes() const override { return taken_axes(); }
  /// The byte of the last key read if it was one byte ('q', '\r', ...), else 0.
  char last_char() const { return last_char_; }
  /// The terminal hung up (end of input): no key will come any more.
  bool gone() const { return gone_; }

 private:
  bool live_;
  bool keyboard_;
  int depth_ = 0;
  bool gone_ = false;  // the terminal hung up
  std::unique_ptr<raw_mode> raw_;
  std::string pending_;  // bytes read but not decoded yet
  char last_char_ = 0;
};

}  // namespace x4ctl

#endif  // X4CTL_TERM_HPP
