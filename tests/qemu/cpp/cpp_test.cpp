// SPDX-License-Identifier: LGPL-2.1-or-later
// In-guest test of the C++ API against the module.
#include <fcntl.h>
#include <linux/ppdev.h>
#include <linux/x4step.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "check.hpp"
#include "x4step.hpp"
#include "x4step_path.hpp"

using namespace std::chrono_literals;

namespace {

using guest::Check;
using guest::Throws;
using Clock = std::chrono::steady_clock;

// What opening a controller throws, "" if it opens.
std::string OpenError(const std::string &path) {
  try {
    x4step::controller c(path);
  } catch (const x4step::error &e) {
    return e.what();
  }
  return "";
}

// Axis 1 at 9000 steps/s braking at 1500 steps/s^2: a 6 s brake once at
// speed, which it returns at (after 405 steps, 90 ms; and 3000 steps, some
// 300 ms of it: what 400 ms gave): waited for by the axis' speed and
// position, not a fixed sleep (without -icount the guest's time follows the
// host's clock, and a loaded host lets the guest do less in it).
bool StartLongBrakeMove(x4step::controller &c) {
  c.set_profile(x4step::axis{1}, x4step::profile{}.top_speed(9000).accel(100000).decel(1500));
  c.zero(x4step::axis{1});
  c.move_by(x4step::axis{1}, 1000000);
  return guest::WaitFor([&] {
    const x4step::axis_status a = c.get_axis(x4step::axis{1});
    return a.velocity >= 8910 && a.position >= 3000;  // 99 %: 1e9 / interval may round down
  });
}

// close() waits for the whole brake, however long it takes (here 6 s, more
// than the 5 s the library used to wait), so that the next controller
// opens at once, and the axis stays synchronized (braked, not stopped).
void CloseWaitsForTheBrake() {
  x4step::controller c(1);
  Check(StartLongBrakeMove(c), "axis 1 at 9000 steps/s");
  // The brake from there lasts 6 s of guest time at least (a late timer
  // only stretches it): close() taking over 5.5 s is implied by waiting.
  const auto t = Clock::now();
  c.close();
  const double s = guest::MsSince(t) / 1000;
  x4step::axis_status a;
  const x4step::errc e = Throws([&] {
    x4step::controller next(1);
    a = next.get_axis(x4step::axis{1});
  });
  std::printf("close() during a 6 s brake took %.1f s; axis 1 at %ld\n", s, a.position);
  Check(e == x4step::errc::ok && s > 5.5 && !a.running && a.synced,
        "close() waits for a 6 s brake; then the next controller opens, the axis synchronized");
  std::printf("SEG %ld 0 0 0 braked\n", a.position);
}

// Who holds a busy port: the error names ppdev when a program has claimed
// the port through /dev/parport0 (ppdev loaded by cpp.sh).
void BusyByPpdev() {
  const int pp = open("/dev/parport0", O_RDWR | O_CLOEXEC);
  if (pp < 0) {
    std::printf("SKIP busy by ppdev: no /dev/parport0\n");
    return;
  }
  if (ioctl(pp, PPCLAIM)) {
    Check(false, std::string("ppdev claims parport0: ") + std::strerror(errno));
    close(pp);
    return;
  }
  const std::string msg = OpenError("/dev/x4step0");
  Check(msg.find("parport0 is claimed by ppdev0") != std::string::npos,
        "controller refused while ppdev holds the port, naming it: " + msg);
  ioctl(pp, PPRELEASE);
  close(pp);
}

// A controller's destructor waits for the brake; when the port goes away
// meanwhile (here the virtual port's module is removed, cpp.sh loads it as
// parport1) the destructor returns, nothing thrown (std::terminate would
// abort the process).
void PortGoesAwayInDestructor() {
  const char *dev = "/dev/x4step1";
  if (access(dev, F_OK)) {
    std::printf("SKIP port going away: no %s (x4vport)\n", dev);
    return;
  }
  int started[2];
  if (pipe(started)) return;
  const pid_t child = fork();
  if (child == 0) {
    {
      x4step::controller v{std::string(dev)};
      // at speed: braking takes 6 s
      if (!StartLongBrakeMove(v) || !v.get_axis(x4step::axis{1}).running || write(started[1], "s", 1) != 1)
        _exit(2);
    }  // the destructor brakes and waits: the port vanishes meanwhile
    _exit(0);
  }
  close(started[1]);
  char c = 0;
  const bool ok = read(started[0], &c, 1) == 1;
  close(started[0]);
  std::this_thread::sleep_for(300ms);
  const auto t = Clock::now();
  const int rc = std::system("rmmod x4vport");
  int status = 0;
  while (waitpid(child, &status, WNOHANG) == 0 && guest::MsSince(t) < 5000) std::this_thread::sleep_for(10ms);
  if (guest::MsSince(t) >= 5000) {
    kill(child, SIGKILL);
    waitpid(child, &status, 0);
  }
  std::printf("port going away: rmmod status %d, controller process status 0x%x after %.0f ms\n", rc, status,
              guest::MsSince(t));
  Check(ok && rc == 0 && WIFEXITED(status) && WEXITSTATUS(status) == 0,
        "the destructor returns, nothing thrown, when the port goes away during its brake");
}

// The event stream through the library: a monitor reads what a
// controller's session did, in order, numbered without gaps.
void EventsThroughTheLibrary() {
  using x4step::event_type;
  x4step::monitor mon(1);
  Check(!mon.read_event(0ms), "monitor: no event before anything happens");
  {
    x4step::controller c(1);
    c.load({{50, 0, 0, 0}, 2000, 0ms});
    c.start();
    c.wait(5s);
  }
  std::printf("SEG 50 0 0 0\n");
  std::vector<x4step::event> got;
  while (auto e = mon.read_event(2000ms)) {
    got.push_back(*e);
    if (e->type == event_type::controller &&
        e->how == static_cast<unsigned>(x4step::controller_change::released))
      break;
  }
  std::string all;
  bool seq = true;
  for (size_t i = 0; i < got.size(); i++) {
    std::ostringstream o;
    o << got[i];
    all += (i ? " | " : "") + o.str();
    seq &= i == 0 || got[i].seq == got[i - 1].seq + 1;
  }
  const auto is = [&](size_t i, event_type t, unsigned how) {
    return i < got.size() && got[i].type == t && got[i].how == how;
  };
  Check(got.size() == 5 && seq && is(0, event_type::controller, 1) && is(1, event_type::move_started, 1) &&
            is(2, event_type::move_ended, 1) && is(3, event_type::controller, 2) &&
            is(4, event_type::controller, 3) && got[2].axes == x4step::axis{1} &&
            got[2].position[0] == got[1].position[0] + 50,
        "monitor::read_event: opened, started, completed (+50 steps), closed, released: " + all);
  Check(all.find("move ended: axes 1, completed, at ") != std::string::npos,
        "operator<< of an event: " + all);
}

// SIGALRM: abort the path on abort_fd (an ioctl: async-signal-safe).
int abort_fd = -1;
void AbortPath(int) {
  x4step_path_ctl k{};
  k.cmd = X4STEP_PATH_ABORT;
  ::ioctl(abort_fd, X4STEP_PATH_CTL, &k);
}

// x4step::path on the virtual port: a path held with a full queue frees
// no room, so append() says so instead of waiting for ever; after a resume
// it waits for room, and the path ends where an uninterrupted one would.
void PathAppendWhileHeld() {
  const char *dev = "/dev/x4step1";
  if (access(dev, F_OK)) {
    std::printf("SKIP path held with a full queue: no %s (x4vport)\n", dev);
    return;
  }
  x4step::controller c{std::string(dev)};
  x4step::path p(c);
  const auto one =
      x4step::segment{}.steps(x4step::axis::x, 10).length(10).top_speed(2000).entry_speed(2000).accel(20000);
  const std::vector<x4step::segment> all(300, one);
  const auto done0 = p.status().done;  // since the module was loaded
  const long x0 = c.get_axes()[x4step::axis::x].position;
  const std::size_t queued = p.try_append(all.data(), all.size());
  const std::vector<x4step::segment> rest(all.begin() + long(queued), all.end());
  p.hold();
  Check(queued == 256 && p.wait(5s) && p.status().state == x4step::path_state::held,
        guest::F("path: %zu of 300 segments fit, then held", queued));
  // Segments that ended before the hold made room for some of the rest:
  // done + queued counts what the module took.
  const auto took = [&] {
    const x4step::path_status st = p.status();
    return st.done + st.queued;
  };
  const auto took0 = took();
  // Were it to wait for room, an abort from SIGALRM ends the wait (no
  // second thread: the test stays a single-threaded program).
  abort_fd = c.fd();
  struct sigaction sa {
  }, old{};
  sa.sa_handler = AbortPath;
  sigaction(SIGALRM, &sa, &old);
  alarm(3);
  std::string what = "returned";
  try {
    p.append(rest);
  } catch (const x4step::error &e) {
    what = std::to_string(e.code().value()) + " " + e.what();
  }
  Check(alarm(0) > 0, "path: append() to a held, full path returns within 3 s");
  sigaction(SIGALRM, &old, nullptr);
  Check(what.rfind("7 ", 0) == 0 && what.find("held and its queue is full: resume()") != std::string::npos,
        "path: append() to a held, full path throws not_active and says to resume: " + what);
  const std::size_t more = std::size_t(took() - took0);
  p.resume();
  p.append(std::vector<x4step::segment>(rest.begin() + long(more), rest.end()));
  const x4step::path_status st = p.status();
  // 3000 steps at 2000 steps/s: 1.5 s; 60 s only bounds a path that never
  // ends (without -icount a loaded host stretches the guest's moves).
  const bool ended = p.wait(60s);
  const auto done = p.status().done - done0;
  const long moved = c.get_axes()[x4step::axis::x].position - x0;
  const x4step::path_status end = p.status();
  Check(ended && done == 300 && moved == 3000,
        guest::F("path: resumed, the rest appended as room came: %llu segments done, %ld steps, state %d, %u "
                 "queued, speed %u, override %u, starved %llu, active %d",
                 static_cast<unsigned long long>(done), moved, int(end.state), unsigned(end.queued),
                 unsigned(end.speed), unsigned(end.override_percent), (unsigned long long)end.starved,
                 int(c.get_status().active)));
  Check(st.state == x4step::path_state::running, "path: running while the rest was appended");
}

}  // namespace

int main() {
  setvbuf(stdout, nullptr, _IOLBF, 0);
  using x4step::errc;
  {
    x4step::controller c(1);
    Check(static_cast<bool>(c) && c.path() == "/dev/x4step0", "controller on LPT1");
    Check(Throws([] { x4step::controller second(1); }) == errc::lpt_not_found, "second controller refused");
    const std::string busy = OpenError("/dev/x4step0");
    Check(busy.find("another x4step controller has parport0") != std::string::npos,
          "second controller: the message says who has the port: " + busy);
    x4step::monitor mon(1);
    Check(mon.get_status().controlled, "monitor sees the controller");

    c.load({{300, -200, 100, 0}, 2000, 20ms});
    Check(Throws([&] { c.load({{1, 0, 0, 0}, 2000, 20ms}); }) == errc::is_loaded, "second load: is_loaded");
    Check(Throws([&] {
            c.load({{1, 0, 0, 0}, 30000, 20ms});
          }) == errc::freq_too_high,
          "bad load: freq_too_high");
    c.start();
    Check(!mon.wait(0ms), "monitor: move running");
    Check(c.wait(5s) && mon.wait(0ms), "wait for the end with poll");
    const x4step::status st = c.get_status();
    Check(st.steps[0] == 300 && st.steps[1] == -200 && st.steps[2] == 100 && !st.active,
          "steps after the move");
    std::printf("SEG 300 -200 100 0\n");
    Check(Throws([&] { c.brake(); }) == errc::not_active, "brake idle: not_active");
    Check(Throws([&] { c.start(); }) == errc::not_loaded, "start: not_loaded");

    c.set_output(x4step::signal::two, true);
    Check((c.get_status().outputs & 2) == 2, "signal 2 on");
    c.set_output(x4step::signal::two, false);

    x4step::controller moved = std::move(c);
    Check(!c && static_cast<bool>(moved), "controller moves");
    Check(Throws([&] { c.start(); }) == errc::init_not_done, "moved-from controller: init_not_done");
    moved.move_endless(x4step::axis{4}, x4step::direction::negative, 3000, 30ms);
    Check(moved.active(), "endless move runs");
    // Steps made before the destructor (800: what 300 ms gave): a count
    // waited for, not a fixed sleep.
    Check(guest::WaitFor([&] { return moved.get_status().steps[3] < -800; }), "endless move: 800 steps");
  }  // destructor brakes, waits, releases
  {
    x4step::controller again(1);
    Check(!again.active() && again.get_status().steps[3] < -10, "destructor braked the endless move");
  }
  std::printf("SEG 0 0 0 ? braked\n");
  EventsThroughTheLibrary();
  CloseWaitsForTheBrake();
  BusyByPpdev();
  PathAppendWhileHeld();
  PortGoesAwayInDestructor();
  return guest::Finish("cpp_test");
}
