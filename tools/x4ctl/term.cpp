// SPDX-License-Identifier: GPL-2.0
// x4ctl: terminal and signals.
#include "term.hpp"

#include <poll.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdlib>

namespace x4ctl {
namespace {

volatile sig_atomic_t g_interrupts = 0;  // SIGINTs so far; take_signal counts what it took
volatile sig_atomic_t g_quit = 0;
sig_atomic_t g_interrupts_taken = 0;
// The axes that brake and stop requests ask for, until taken.
std::atomic<unsigned> g_brake{0};
std::atomic<unsigned> g_stop{0};
static_assert(std::atomic<unsigned>::is_always_lock_free, "used in a signal handler");
// Every axis, as the mask a signal carries.
constexpr unsigned all_mask = all_axes.mask();
unsigned g_taken = all_mask;

void on_signal(int sig, siginfo_t *info, void *) {
  // sigqueue() from `x4ctl halt` names the axes; anything else means all.
  const unsigned axes = info && info->si_code == SI_QUEUE ? info->si_value.sival_int & all_mask : all_mask;
  switch (sig) {
    case SIGINT:
      g_interrupts = g_interrupts + 1;
      g_quit = 1;
      break;
    case SIGTERM:
    case SIGHUP:
      g_brake |= all_mask;
      g_quit = 1;
      break;
    case SIGUSR1:
      g_brake |= axes;
      break;
    case SIGUSR2:
      g_stop |= axes;
      break;
    default:
      break;
  }
}

// How long the rest of a cursor key's escape sequence may take to arrive
// after its ESC (ssh and slow terminals split them).
constexpr milliseconds sequence_gap{40};

}  // namespace

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_sigaction = on_signal;
  sa.sa_flags = SA_SIGINFO;
  sigemptyset(&sa.sa_mask);
  // SIGINT, SIGTERM and SIGHUP end a blocking read (the prompt) ...
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &sa, nullptr);
  // ... `x4ctl brake` and `x4ctl stop` must not.
  sa.sa_flags = SA_SIGINFO | SA_RESTART;
  for (int sig : {SIGUSR1, SIGUSR2}) sigaction(sig, &sa, nullptr);
}

key take_signal() {
  if (const unsigned axes = g_stop.exchange(0)) {
    g_taken = axes;
    return key::stop_request;
  }
  if (g_interrupts != g_interrupts_taken) {
    g_interrupts_taken = g_interrupts_taken + 1;
    return key::interrupt;
  }
  if (const unsigned axes = g_brake.exchange(0)) {
    g_taken = axes;
    return key::brake_request;
  }
  return key::none;
}

x4step::axis_set taken_axes() { return x4step::axis_set(g_taken); }

bool send_request(pid_t pid, bool stop, x4step::axis_set axes) {
  sigval v{};
  v.sival_int = static_cast<int>(axes.mask());
  return ::sigqueue(pid, stop ? SIGUSR2 : SIGUSR1, v) == 0;
}

bool quit_requested() { return g_quit != 0; }

size_t terminal_columns(int fd) {
  winsize w{};
  if (::ioctl(fd, TIOCGWINSZ, &w) == 0 && w.ws_col > 0) return w.ws_col;
  if (const char *c = std::getenv("COLUMNS")) {
    char *end = nullptr;
    const long n = std::strtol(c, &end, 10);
    if (end != c && *end == '\0' && n > 0 && n < 10000) return size_t(n);
  }
  return 80;
}

void nap(milliseconds timeout) {
  if (timeout.count() > 0) ::poll(nullptr, 0, static_cast<int>(timeout.count()));
}

raw_mode::raw_mode(int fd) : fd_(fd) {
  if (!::isatty(fd) || ::tcgetattr(fd, &saved_) != 0) return;
  termios t = saved_;
  t.c_lflag &= ~(ICANON | ECHO | ISIG);
  t.c_cc[VMIN] = 1;
  t.c_cc[VTIME] = 0;
  active_ = ::tcsetattr(fd, TCSANOW, &t) == 0;
}

raw_mode::~raw_mode() {
  if (active_) ::tcsetattr(fd_, TCSANOW, &saved_);
}

decoded decode_key(std::string_view b, bool complete) {
  if (b.empty()) return {};
  const unsigned char c = static_cast<unsigned char>(b[0]);
  if (c == 0x03) return {key::interrupt, 1, b[0]};  // Ctrl-C in raw mode
  if (c == ' ') return {key::space, 1, b[0]};
  if (c == '+' || c == '=') return {key::plus, 1, b[0]};
  if (c == '-') return {key::minus, 1, b[0]};
  if (c != 0x1b) return {key::other, 1, b[0]};
  if (b.size() == 1) return complete ? decoded{key::esc, 1} : decoded{};
  if (b[1] != '[' && b[1] != 'O') return {key::esc, 1};  // ESC, then another key
  // CSI or SS3 sequence: parameters, then a final byte 0x40..0x7e.
  for (size_t i = 2; i < b.size(); i++) {
    const unsigned char f = static_cast<unsigned char>(b[i]);
    if (f >= 0x40 && f <= 0x7e) {
      const std::string_view param = b.substr(2, i - 2);
      const key k = f == 'A'                   ? key::up
                    : f == 'B'                 ? key::down
                    : f == 'C'                 ? key::right
                    : f == 'D'                 ? key::left
                    : f == '~' && param == "5" ? key::page_up
                    : f == '~' && param == "6" ? key::page_down
                                               : key::other;
      return {k, i + 1};
    }
  }
  return complete ? decoded{key::other, b.size()} : decoded{};
}

std::string strip_keys(std::string_view line) {
  std::string r;
  for (size_t i = 0; i < line.size();) {
    const unsigned char c = static_cast<unsigned char>(line[i]);
    if (c == 0x1b)
      i += std::max<size_t>(decode_key(line.substr(i), true).used, 1);
    else if (c < 0x20 && c != '\t')
      i++;
    else
      r += line[i++];
  }
  return r;
}

std_console::std_console(bool keyboard)
    : live_(::isatty(STDOUT_FILENO)), keyboard_(keyboard && ::isatty(STDIN_FILENO)) {}

void std_console::keys_on() {
  if (keyboard_ && depth_++ == 0) {
    raw_ = std::make_unique<raw_mode>(STDIN_FILENO);
    pending_.clear();
  }
}

void std_console::keys_off() {
  if (keyboard_ && --depth_ == 0) raw_.reset();
}

key std_console::read_key(milliseconds timeout) {
  last_char_ = 0;  // a signal, a timeout or a hang-up reads no character
  if (const key s = take_signal(); s != key::none) return s;
  if (!raw_ || gone_) {
    nap(timeout);
    const key s = take_signal();
    return s == key::none && gone_ ? key::brake_request : s;  // no terminal, nobody to let go of a key
  }
  auto read_more = [&](milliseconds t) {
    pollfd p{STDIN_FILENO, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(t.count())) <= 0) return false;
    char buf[64];
    const ssize_t n = ::read(STDIN_FILENO, buf, sizeof buf);
    if (n == 0 || (n < 0 && errno != EINTR && errno != EAGAIN)) gone_ = true;
    if (n <= 0) return false;
    pending_.append(buf, static_cast<size_t>(n));
    return true;
  };
  if (pending_.empty() && !read_more(timeout)) return take_signal();
  decoded d = decode_key(pending_, false);
  while (d.used == 0) {  // an ESC that may start a sequence
    const bool more = read_more(sequence_gap);
    d = decode_key(pending_, !more);
  }
  pending_.erase(0, d.used);
  last_char_ = d.ch;
  return d.k;
}

}  // namespace x4ctl
