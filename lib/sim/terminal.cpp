// SPDX-License-Identifier: LGPL-2.1-or-later
// libx4step: the simulated port's keyboard (terminal.hpp).
#include "terminal.hpp"

#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <cstdlib>
#include <mutex>
#include <string>

#include "options.hpp"

namespace x4step::sim {
namespace {

// The terminal's mode before the simulator changed it, for exit().
std::mutex saved_lock;
bool saved_valid = false;
termios saved_at_exit{};

void restore_at_exit() {
  const std::lock_guard<std::mutex> l(saved_lock);
  if (saved_valid) tcsetattr(STDIN_FILENO, TCSANOW, &saved_at_exit);
}

// The key of an escape sequence's final byte (ESC [ A ...) or number (ESC [ 5 ~).
unsigned csi_key(char final, int number) {
  switch (final) {
    case 'A':
      return key_code("up");
    case 'B':
      return key_code("down");
    case 'C':
      return key_code("right");
    case 'D':
      return key_code("left");
    case 'H':
      return key_code("home");
    case 'F':
      return key_code("end");
    case '~':
      switch (number) {
        case 1:
        case 7:
          return key_code("home");
        case 2:
          return key_code("insert");
        case 3:
          return key_code("delete");
        case 4:
        case 8:
          return key_code("end");
        case 5:
          return key_code("pgup");
        case 6:
          return key_code("pgdn");
      }
  }
  return 0;
}

}  // namespace

std::vector<unsigned> terminal_keys(std::string_view b) {
  std::vector<unsigned> codes;
  for (std::size_t i = 0; i < b.size(); i++) {
    const char c = b[i];
    unsigned code = 0;
    if (c == '\033' && i + 1 < b.size() && (b[i + 1] == '[' || b[i + 1] == 'O')) {
      int number = 0;
      i += 2;
      while (i < b.size() && b[i] >= '0' && b[i] <= '9') number = number * 10 + (b[i++] - '0');
      while (i < b.size() && b[i] == ';') i++;  // modifiers: the key alone
      while (i < b.size() && b[i] >= '0' && b[i] <= '9') i++;
      if (i < b.size()) code = csi_key(b[i], number);
    } else if (c == '\033') {
      code = key_code("esc");
    } else if (c == '\r' || c == '\n') {
      code = key_code("enter");
    } else if (c == '\t') {
      code = key_code("tab");
    } else if (c == 0x7f || c == '\b') {
      code = key_code("backspace");
    } else if (c == ' ') {
      code = key_code("space");
    } else {
      code = key_code(std::string(1, c));
    }
    if (code) codes.push_back(code);
  }
  return codes;
}

bool terminal::available() { return isatty(STDIN_FILENO); }

terminal::terminal(std::function<bool()> moving, std::function<void(unsigned)> key)
    : moving_(std::move(moving)), key_(std::move(key)) {
  quit_fd_ = ::eventfd(0, EFD_CLOEXEC);
  if (quit_fd_ >= 0) thread_ = std::thread([this] { run(); });
}

terminal::~terminal() {
  if (thread_.joinable()) {
    const std::uint64_t one = 1;
    ssize_t n = ::write(quit_fd_, &one, sizeof one);
    (void)n;
    thread_.join();
  }
  if (quit_fd_ >= 0) ::close(quit_fd_);
}

// Keys unbuffered and unechoed; Ctrl-C stays a signal.
void terminal::raw(bool on) {
  if (on == raw_) return;
  if (on) {
    termios t;
    if (tcgetpgrp(STDIN_FILENO) != getpgrp()) return;                  // in the background
    if (tcgetattr(STDIN_FILENO, &t) || !(t.c_lflag & ICANON)) return;  // the program reads keys itself
    saved_ = t;
    {
      const std::lock_guard<std::mutex> l(saved_lock);
      static const bool registered = std::atexit(restore_at_exit) == 0;
      (void)registered;
      saved_at_exit = t;
      saved_valid = true;
    }
    t.c_lflag &= ~static_cast<tcflag_t>(ICANON | ECHO);
    t.c_cc[VMIN] = 0;
    t.c_cc[VTIME] = 0;
    raw_ = tcsetattr(STDIN_FILENO, TCSANOW, &t) == 0;
    return;
  }
  tcsetattr(STDIN_FILENO, TCSANOW, &saved_);
  const std::lock_guard<std::mutex> l(saved_lock);
  saved_valid = false;
  raw_ = false;
}

void terminal::run() {
  // A program that reads keys itself takes the terminal as its move
  // starts: look only once a move has run for 40 ms.
  int moving = 0;
  for (;;) {
    moving = moving_() ? moving + 1 : 0;
    raw(moving > 2);
    pollfd p[2] = {{quit_fd_, POLLIN, 0}, {STDIN_FILENO, static_cast<short>(raw_ ? POLLIN : 0), 0}};
    if (::poll(p, 2, 20) < 0) continue;  // 20 ms: how soon a move's start is seen
    if (p[0].revents) break;
    if (!(p[1].revents & POLLIN)) continue;
    char buf[64];
    const ssize_t n = ::read(STDIN_FILENO, buf, sizeof buf);
    if (n <= 0) continue;
    for (unsigned code : terminal_keys(std::string_view(buf, static_cast<std::size_t>(n)))) {
      key_(code);
      key_(code + 128);
    }
  }
  raw(false);
}

}  // namespace x4step::sim
