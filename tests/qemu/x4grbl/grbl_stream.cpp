// SPDX-License-Identifier: GPL-2.0
// grbl_stream: the G-code sender of the QEMU test of x4grbl (x4grbl.sh), as
// small as a sender can be. It opens the bridge's pseudo-terminal, waits for
// the welcome line, checks the machine is Idle, and streams a program with
// GRBL's character counting: at most 128 bytes sent and not yet answered,
// one `ok` or `error:N` per line, in order. After --hold-after N lines it
// waits for Run, sends a feed hold (`!`), waits for Hold:0, checks that the
// position stands still, resumes (`~`) and sees the motion go on; then it
// streams the rest, polls `?` until Idle and prints the final MPos.
//
// Output (console lines, read by check-grbl.sh on the host):
//   PASS|FAIL NAME [why]
//   X4GRBL hold MPos:x,y,z,a         where the hold stopped
//   X4GRBL lines N ok K error E      the program's lines and their answers
//   X4GRBL final MPos:x,y,z,a        the last status report, Idle
// Exit status 0 when every check passed.
//
//   grbl_stream TTY PROGRAM [--hold-after N]
#include <fcntl.h>
#include <poll.h>
#include <termios.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <fstream>
#include <string>
#include <vector>

namespace {

constexpr size_t kRxBuffer = 128;  // GRBL's serial receive buffer
bool failed = false;

void check(const std::string &name, bool ok, const std::string &why = "") {
  std::printf("%s %s%s%s\n", ok ? "PASS" : "FAIL", name.c_str(), ok || why.empty() ? "" : ": ",
              ok ? "" : why.c_str());
  std::fflush(stdout);
  failed |= !ok;
}

[[noreturn]] void die(const std::string &why) {
  check("grbl-stream", false, why);
  std::printf("X4GRBL aborted\n");
  std::exit(1);
}

int64_t now_ms() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return int64_t{ts.tv_sec} * 1000 + ts.tv_nsec / 1000000;
}

// The connection: bytes out, lines in. Every line read goes through
// take(), which answers the counting (ok/error), keeps the last status
// report and fails on an alarm.
class Sender {
 public:
  explicit Sender(const std::string &tty) {
    for (int i = 0; i < 100 && fd_ < 0; i++) {  // the link appears when x4grbl is up
      fd_ = open(tty.c_str(), O_RDWR | O_NOCTTY);
      if (fd_ < 0) usleep(100000);
    }
    if (fd_ < 0) die("open " + tty + ": " + std::strerror(errno));
    termios t{};
    if (tcgetattr(fd_, &t) == 0) {
      cfmakeraw(&t);
      tcsetattr(fd_, TCSANOW, &t);
    }
  }
  ~Sender() { close(fd_); }
  Sender(const Sender &) = delete;
  Sender &operator=(const Sender &) = delete;

  void write_all(const std::string &s) {
    size_t done = 0;
    while (done < s.size()) {
      const ssize_t n = write(fd_, s.data() + done, s.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) die(std::string("write: ") + std::strerror(errno));
      done += static_cast<size_t>(n);
    }
  }

  // The next line, without its line end; false after TIMEOUT_MS.
  bool line(std::string &out, int timeout_ms) {
    const int64_t end = now_ms() + timeout_ms;
    for (;;) {
      const size_t nl = buf_.find('\n');
      if (nl != std::string::npos) {
        out = buf_.substr(0, nl);
        buf_.erase(0, nl + 1);
        if (!out.empty() && out.back() == '\r') out.pop_back();
        if (out.empty()) continue;
        take(out);
        return true;
      }
      const int64_t left = end - now_ms();
      if (left <= 0) return false;
      pollfd p{fd_, POLLIN, 0};
      const int r = poll(&p, 1, static_cast<int>(left));
      if (r < 0 && errno != EINTR) die(std::string("poll: ") + std::strerror(errno));
      if (r <= 0) continue;
      char b[512];
      const ssize_t n = read(fd_, b, sizeof b);
      if (n < 0 && (errno == EINTR || errno == EAGAIN)) continue;
      if (n <= 0) die("the bridge closed the connection");
      buf_.append(b, static_cast<size_t>(n));
    }
  }

  // A line of the program: sent once the 128 bytes have room for it.
  void send_line(const std::string &l) {
    const std::string s = l + "\n";
    if (s.size() > kRxBuffer) die("line longer than the receive buffer: " + l);
    while (inflight_ + s.size() > kRxBuffer) wait_answer();
    write_all(s);
    pending_.push_back(s.size());
    inflight_ += s.size();
    sent_++;
  }

  void wait_answer() {
    const size_t before = pending_.size();
    std::string l;
    while (pending_.size() == before)
      if (!line(l, 30000)) die("no ok/error for 30 s, " + std::to_string(before) + " lines unanswered");
  }
  void drain() {
    while (!pending_.empty()) wait_answer();
  }

  // `?` and its report ("<Idle|MPos:...|...>").
  std::string status() {
    write_all("?");
    const uint64_t want = ++asked_status_;
    std::string l;
    while (answered_status_ < want)
      if (!line(l, 5000)) die("no status report for 5 s");
    return last_status_;
  }

  bool welcomed() const { return welcomed_; }
  int sent() const { return sent_; }
  int oks() const { return oks_; }
  int errors() const { return errors_; }

 private:
  void take(const std::string &l) {
    if (l == "ok" || l.rfind("error:", 0) == 0) {
      if (pending_.empty()) {
        check("answer-expected", false, "'" + l + "' with no line waiting");
        return;
      }
      inflight_ -= pending_.front();
      pending_.pop_front();
      if (l == "ok") {
        oks_++;
      } else {
        errors_++;
        check("line-" + std::to_string(oks_ + errors_), false, l);
      }
    } else if (l[0] == '<') {
      last_status_ = l;
      answered_status_++;
    } else if (l.rfind("ALARM:", 0) == 0) {
      check("no-alarm", false, l);
    } else {
      std::printf("grbl: %s\n", l.c_str());  // welcome, [MSG:...]
      if (l.rfind("Grbl 1.1", 0) == 0) welcomed_ = true;
    }
  }

  int fd_ = -1;
  std::string buf_;
  std::deque<size_t> pending_;  // the sizes of the lines not yet answered
  size_t inflight_ = 0;
  int sent_ = 0, oks_ = 0, errors_ = 0;
  bool welcomed_ = false;
  std::string last_status_;
  uint64_t asked_status_ = 0, answered_status_ = 0;
};

std::string state_of(const std::string &report) {  // "<Hold:0|..." -> "Hold:0"
  const size_t bar = report.find('|');
  return report.substr(1, bar == std::string::npos ? std::string::npos : bar - 1);
}

std::string mpos_of(const std::string &report) {  // "MPos:1.000,2.000,..."
  const size_t at = report.find("MPos:");
  if (at == std::string::npos) return "";
  const size_t end = report.find_first_of("|>", at);
  return report.substr(at, end - at);
}

// Polls `?` every 50 ms until the state starts with WANT; the last report.
std::string until_state(Sender &s, const std::string &want, int timeout_ms) {
  const int64_t end = now_ms() + timeout_ms;
  std::string r;
  for (;;) {
    r = s.status();
    if (state_of(r).rfind(want, 0) == 0) return r;
    if (now_ms() > end) die("no " + want + " within " + std::to_string(timeout_ms) + " ms, last " + r);
    usleep(50000);
  }
}

}  // namespace

int main(int argc, char **argv) {
  if (argc != 3 && !(argc == 5 && std::strcmp(argv[3], "--hold-after") == 0)) {
    std::fprintf(stderr, "usage: grbl_stream TTY PROGRAM [--hold-after N]\n");
    return 2;
  }
  const int hold_after = argc == 5 ? std::atoi(argv[4]) : -1;
  std::vector<std::string> program;
  {
    std::ifstream in(argv[2]);
    if (!in) die(std::string("cannot read ") + argv[2]);
    for (std::string l; std::getline(in, l);)
      if (!l.empty()) program.push_back(l);
  }
  std::setvbuf(stdout, nullptr, _IOLBF, 0);

  Sender s(argv[1]);
  std::string l;
  const int64_t end = now_ms() + 10000;
  while (!s.welcomed() && now_ms() < end) s.line(l, 1000);
  check("welcome", s.welcomed(), "no 'Grbl 1.1' line within 10 s");
  const std::string first = s.status();
  check("idle-at-start", state_of(first) == "Idle", first);

  for (size_t i = 0; i < program.size(); i++) {
    if (static_cast<int>(i) == hold_after) {
      // Mid-path: the lines so far are in the planner, the rest unsent.
      until_state(s, "Run", 10000);
      usleep(300000);
      const std::string run = s.status();
      check("hold-while-running", state_of(run) == "Run", run);
      s.write_all("!");
      const std::string held = until_state(s, "Hold:0", 10000);
      std::printf("X4GRBL hold %s\n", mpos_of(held).c_str());
      usleep(300000);
      const std::string still = s.status();
      check("hold-stands-still", state_of(still) == "Hold:0" && mpos_of(still) == mpos_of(held),
            held + " then " + still);
      s.write_all("~");
      until_state(s, "Run", 5000);
      usleep(100000);
      const std::string moving = s.status();
      check("resume-moves-on", mpos_of(moving) != mpos_of(held), held + " then " + moving);
    }
    s.send_line(program[i]);
  }
  s.drain();
  const std::string last = until_state(s, "Idle", 60000);
  std::printf("X4GRBL lines %zu ok %d error %d\n", program.size(), s.oks(), s.errors());
  check("every-line-ok", s.oks() == static_cast<int>(program.size()) && s.errors() == 0,
        std::to_string(s.oks()) + " ok of " + std::to_string(program.size()));
  std::printf("X4GRBL final %s\n", mpos_of(last).c_str());
  check("final-mpos", !mpos_of(last).empty(), last);
  return failed ? 1 : 0;
}
