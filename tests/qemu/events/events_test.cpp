// SPDX-License-Identifier: GPL-2.0
// In-guest test of the event stream (ABI 4: read() and POLLPRI on any
// descriptor) and of status reads that leave a port x4step has not claimed
// alone, on the test-only virtual port tests/qemu/fixtures/x4vport (a machine with
// switches, and a count of register reads). Through the UAPI only.
// Prints PASS/FAIL lines.
#include <fcntl.h>
#include <linux/ppdev.h>
#include <linux/x4step.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "check.hpp"
#include "keyboard.hpp"

namespace {

using guest::Check;
using guest::F;
using guest::Put;
using guest::Slurp;

const std::string kV = "/sys/kernel/debug/x4vport/";
std::string dev;  // /dev/x4stepN of the virtual port
int port = -1;    // N

int Ioctl(int fd, unsigned long cmd, void *arg = nullptr) { return ioctl(fd, cmd, arg) ? errno : 0; }

unsigned long Reads() { return std::strtoul(Slurp(kV + "reads").c_str(), nullptr, 10); }

// ---- events ----------------------------------------------------------------

const char *TypeName(uint32_t t) {
  static const char *const names[] = {"?", "STARTED", "ENDED", "BRAKE", "SWITCH", "CONTROLLER", "GONE"};
  return t < 7 ? names[t] : "?";
}

std::string Str(const x4step_event &e) {
  return F("#%llu %s axes 0x%x how %u value %u flags 0x%x at %d %d %d %d", (unsigned long long)e.seq,
           TypeName(e.type), e.axes, e.how, e.value, e.flags, e.position[0], e.position[1], e.position[2],
           e.position[3]);
}

std::string Str(const std::vector<x4step_event> &v) {
  std::string s;
  for (const auto &e : v) s += (s.empty() ? "" : " | ") + Str(e);
  return s.empty() ? "none" : s;
}

// One descriptor's stream: every event read, checked as it comes (the
// fields of each, and against the one before: seq + 1, time not back).
struct Stream {
  int fd = -1;
  uint64_t last_seq = 0;
  uint64_t last_ns = 0;
  unsigned bad = 0;
  std::string why;

  void Note(const x4step_event &e, bool gap_ok = false) {
    std::string w;
    if (last_seq && !gap_ok && e.seq != last_seq + 1)
      w = F("seq %llu after %llu", (unsigned long long)e.seq, (unsigned long long)last_seq);
    if (last_seq && e.seq <= last_seq) w = "seq not increasing";
    if (e.timestamp_ns < last_ns) w = "time went back";
    if (e.type < X4STEP_EV_MOVE_STARTED || e.type > X4STEP_EV_PORT_GONE) w = "unknown type";
    if (e.flags & ~X4STEP_EVF_AMBIGUOUS) w = "unknown flags";
    if (e.reserved[0] || e.reserved[1] || e.reserved[2]) w = "reserved not zero";
    if (e.axes > 0xf) w = "axes beyond 4";
    if (!w.empty()) {
      bad++;
      if (why.empty()) why = w + ": " + Str(e);
    }
    last_seq = e.seq;
    last_ns = e.timestamp_ns;
  }

  // Events until `done` says so (inclusive), or timeout_ms passed.
  std::vector<x4step_event> Until(const std::function<bool(const x4step_event &)> &done,
                                  int timeout_ms = 5000) {
    std::vector<x4step_event> got;
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
    for (;;) {
      x4step_event e;
      const ssize_t n = read(fd, &e, sizeof e);
      if (n == sizeof e) {
        Note(e);
        got.push_back(e);
        if (done(e)) return got;
        continue;
      }
      const int left =
          int(std::chrono::duration_cast<std::chrono::milliseconds>(end - std::chrono::steady_clock::now())
                  .count());
      if (left <= 0) return got;
      pollfd p{fd, POLLPRI, 0};
      poll(&p, 1, left);
    }
  }
  // Everything there now (none left to read after it).
  std::vector<x4step_event> Now() {
    return Until([](const x4step_event &) { return false; }, 0);
  }
};

bool Is(const x4step_event &e, uint32_t type, uint32_t how, uint32_t axes) {
  return e.type == type && e.how == how && e.axes == axes;
}

// The events, in order, are these (type, how, axes).
struct Want {
  uint32_t type, how, axes;
};
bool Match(const std::vector<x4step_event> &got, std::initializer_list<Want> want) {
  if (got.size() != want.size()) return false;
  size_t i = 0;
  for (const Want &w : want)
    if (!Is(got[i++], w.type, w.how, w.axes)) return false;
  return true;
}

auto EndOf(uint32_t axes) {
  return [axes](const x4step_event &e) { return e.type == X4STEP_EV_MOVE_ENDED && e.axes == axes; };
}

// ---- the controller --------------------------------------------------------

int OpenCtl() { return open(dev.c_str(), O_RDWR | O_CLOEXEC); }

void WaitIdle(int fd) {
  pollfd p{fd, POLLIN, 0};
  for (int i = 0; i < 100 && !(poll(&p, 1, 100) == 1 && (p.revents & POLLIN)); i++) {
  }
}

x4step_axes Axes(int fd) {
  x4step_axes a{};
  ioctl(fd, X4STEP_GET_AXES, &a);
  return a;
}

// Waits (guest::WaitFor, up to 10 s) until axis i (0-based) satisfies `ok`.
template <typename Pred>
bool WaitAxis(int fd, int i, Pred ok) {
  return guest::WaitFor([&] { return ok(Axes(fd).axis[i]); });
}

int Endless(int fd, int axis, int dir, int freq, int ramp) {
  x4step_endless e{axis, dir, freq, ramp, 0, -1, {0, 0}};
  return Ioctl(fd, X4STEP_MOVE_ENDLESS, &e);
}

int Goto(int fd, unsigned axes, std::initializer_list<int> target) {
  x4step_goto g{};
  g.axes = axes;
  int i = 0;
  for (int t : target) g.target[i++] = t;
  return Ioctl(fd, X4STEP_GOTO, &g);
}

int Zero(int fd) {
  x4step_position p{0xf, 0, {0, 0, 0, 0}};
  return Ioctl(fd, X4STEP_SET_POSITION, &p);
}

// ---- 1: a port x4step has not claimed is left alone -------------------------

void StatusLeavesThePortAlone() {
  const int ro = open(dev.c_str(), O_RDONLY | O_CLOEXEC);
  x4step_status st{};
  x4step_axes ax{};
  Put(kV + "clear", "1\n");
  int err = 0;
  for (int i = 0; i < 3; i++) err |= Ioctl(ro, X4STEP_GET_STATUS, &st) | Ioctl(ro, X4STEP_GET_AXES, &ax);
  unsigned long n = Reads();
  Check(!err && n == 0 && (st.flags & X4STEP_ST_INPUTS_STALE) && (ax.flags & X4STEP_ST_INPUTS_STALE) &&
            !(st.flags & X4STEP_ST_CONTROLLED),
        F("no controller: GET_STATUS and GET_AXES read no register (reads %lu), inputs flagged stale "
          "(flags 0x%x, 0x%x)",
          n, st.flags, ax.flags));

  // Another parport client (ppdev) has claimed the port: it is that
  // client's now, and x4step must not touch it.
  const int pp = open(F("/dev/parport%d", port).c_str(), O_RDWR | O_CLOEXEC);
  if (pp < 0 && errno == ENOENT) {
    std::printf("SKIP ppdev holds the port: no ppdev in this kernel (the debug kernel)\n");
  } else if (pp < 0 || ioctl(pp, PPCLAIM)) {
    Check(false, F("ppdev claims parport%d: %s", port, std::strerror(errno)));
  } else {
    Put(kV + "clear", "1\n");
    err = 0;
    for (int i = 0; i < 3; i++) err |= Ioctl(ro, X4STEP_GET_STATUS, &st) | Ioctl(ro, X4STEP_GET_AXES, &ax);
    n = Reads();
    const int c = OpenCtl();
    const int c_err = errno;
    Check(!err && n == 0 && (st.flags & X4STEP_ST_INPUTS_STALE) && c < 0 && c_err == EBUSY,
          F("ppdev holds the port: a read-only status read reads no register (reads %lu), stale; "
            "a controller's open is refused (%s)",
            n, c < 0 ? std::strerror(c_err) : "opened"));
    if (c >= 0) close(c);
    ioctl(pp, PPRELEASE);
  }
  if (pp >= 0) close(pp);

  // With a controller the port is x4step's: live inputs.
  Put(kV + "pins", "0x0a\n");
  const int c = OpenCtl();
  Put(kV + "clear", "1\n");
  err = Ioctl(ro, X4STEP_GET_STATUS, &st) | Ioctl(ro, X4STEP_GET_AXES, &ax);
  n = Reads();
  Check(c >= 0 && !err && n >= 2 && !(st.flags & X4STEP_ST_INPUTS_STALE) && !ax.flags && st.inputs == 0x0a &&
            ax.inputs == 0x0a && st.inputs_time_ns,
        F("beside a controller: read from the port (reads %lu), live (flags 0x%x, inputs 0x%x)", n, st.flags,
          st.inputs));
  close(c);
  Put(kV + "pins", "0x1f\n");
  Put(kV + "clear", "1\n");
  err = Ioctl(ro, X4STEP_GET_STATUS, &st);
  n = Reads();
  Check(!err && n == 0 && st.inputs == 0x0a && (st.flags & X4STEP_ST_INPUTS_STALE),
        F("after the controller closed: the last levels read (0x%x), stale, no read (reads %lu)", st.inputs,
          n));
  close(ro);
}

// ---- 3: the event stream ---------------------------------------------------

void Basics(Stream &mon) {
  x4step_info info{};
  const int ierr = Ioctl(mon.fd, X4STEP_GET_INFO, &info);
  Check(!ierr && info.abi_version == X4STEP_ABI_VERSION && info.event_buffer == 256,
        F("GET_INFO: ABI %u, %u events kept", info.abi_version, info.event_buffer));
  x4step_event e;
  Check(read(mon.fd, &e, sizeof e) < 0 && errno == EAGAIN, "nothing to read, O_NONBLOCK: EAGAIN");
  Check(read(mon.fd, &e, sizeof e - 1) < 0 && errno == EINVAL, "a buffer smaller than an event: EINVAL");
  pollfd p{mon.fd, POLLIN | POLLPRI, 0};
  const int n = poll(&p, 1, 0);
  Check(n == 1 && p.revents == POLLIN, F("idle, no event: POLLIN only (revents 0x%x)", p.revents));
}

// read() copies whole events only and nothing beyond them; a fault
// consumes nothing.
void Buffers(Stream &mon) {
  int c = OpenCtl();
  close(c);  // OPENED, CLOSED, RELEASED
  WaitIdle(mon.fd);
  unsigned char buf[3 * sizeof(x4step_event) + 40];
  std::memset(buf, 0xa5, sizeof buf);
  pollfd p{mon.fd, POLLPRI, 0};
  poll(&p, 1, 1000);
  usleep(20000);
  // A bad pointer first: EFAULT, the event is still there.
  void *bad = mmap(nullptr, 4096, PROT_READ, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  const ssize_t nf = read(mon.fd, bad, sizeof(x4step_event));
  const int ef = errno;
  munmap(bad, 4096);
  const ssize_t n = read(mon.fd, buf, sizeof buf);
  bool tail = true;
  for (size_t i = 3 * sizeof(x4step_event); i < sizeof buf; i++) tail &= buf[i] == 0xa5;
  std::vector<x4step_event> got(n > 0 ? size_t(n) / sizeof(x4step_event) : 0);
  std::memcpy(got.data(), buf, got.size() * sizeof(x4step_event));
  for (const auto &e : got) mon.Note(e);
  Check(nf < 0 && ef == EFAULT, F("read into a read-only page: EFAULT (%zd, %s)", nf, std::strerror(ef)));
  Check(n == 3 * ssize_t(sizeof(x4step_event)) && tail &&
            Match(got, {{X4STEP_EV_CONTROLLER, X4STEP_CTL_OPENED, 0},
                        {X4STEP_EV_CONTROLLER, X4STEP_CTL_CLOSED, 0},
                        {X4STEP_EV_CONTROLLER, X4STEP_CTL_RELEASED, 0}}),
        F("a buffer for 3.6 events: the 3 there (the faulted one too), whole, nothing written after them "
          "(%zd bytes; %s)",
          n, Str(got).c_str()));
}

void Moves(Stream &mon, int c) {
  auto ev = mon.Until([](const x4step_event &e) { return e.type == X4STEP_EV_CONTROLLER; });
  Check(Match(ev, {{X4STEP_EV_CONTROLLER, X4STEP_CTL_OPENED, 0}}), "controller opened: " + Str(ev));
  Zero(c);

  // 400 ms at 500 steps/s: the polls below come a few ms after the start,
  // and must see the move running; the guest's time follows the host's
  // clock (plain TCG), so a loaded host may delay them: the move is asked
  // to be running still after them (else the polls saw nothing to test).
  x4step_move m{{200, 0, 0, 0}, 500, 0, 0, -1};
  Ioctl(c, X4STEP_LOAD, &m);
  Ioctl(c, X4STEP_START);
  usleep(5000);
  // Old programs wait for POLLIN (idle): the pending event must not wake them.
  pollfd p{mon.fd, POLLIN, 0};
  const int in = poll(&p, 1, 0);
  pollfd pp{mon.fd, POLLPRI, 0};
  const int pri = poll(&pp, 1, 0);
  const bool still = Axes(c).axis[0].state & X4STEP_AX_RUN;
  Check(in == 0 && pri == 1 && pp.revents == POLLPRI && still,
        F("move running, event pending: poll(POLLIN) %d, poll(POLLPRI) %d (0x%x), the move %s", in, pri,
          pp.revents, still ? "still running" : "already ended"));
  ev = mon.Until(EndOf(1));
  Check(Match(ev, {{X4STEP_EV_MOVE_STARTED, X4STEP_KIND_LOADED, 1},
                   {X4STEP_EV_MOVE_ENDED, X4STEP_END_COMPLETED, 1}}) &&
            ev[0].position[0] == 0 && ev[1].position[0] == 200,
        "X4Step move: started (at 0), completed (at 200): " + Str(ev));

  Endless(c, 2, 1, 2000, 100);
  Check(WaitAxis(c, 1, [](const x4step_axis &a) { return a.position > 50; }),
        "endless move of axis 2: past 50 steps");
  Ioctl(c, X4STEP_BRAKE);
  ev = mon.Until(EndOf(2));
  Check(Match(ev, {{X4STEP_EV_MOVE_STARTED, X4STEP_KIND_ENDLESS, 2},
                   {X4STEP_EV_BRAKE, X4STEP_SRC_IOCTL, 2},
                   {X4STEP_EV_MOVE_ENDED, X4STEP_END_BRAKED, 2}}) &&
            ev[2].position[1] == Axes(c).axis[1].position && ev[2].position[1] > 50,
        "endless move braked by X4STEP_BRAKE: " + Str(ev));

  Endless(c, 3, -1, 2000, 0);
  usleep(50000);
  Ioctl(c, X4STEP_STOP);
  ev = mon.Until(EndOf(4));
  Check(Match(ev, {{X4STEP_EV_MOVE_STARTED, X4STEP_KIND_ENDLESS, 4},
                   {X4STEP_EV_MOVE_ENDED, X4STEP_END_STOPPED, 4}}),
        "endless move stopped: " + Str(ev));

  // Two axes of their own; one braked by HALT, the other completes.
  x4step_profile pr{1, 0, 0, 2000, 20000, 20000, {0, 0}};
  Ioctl(c, X4STEP_SET_PROFILE, &pr);
  pr.axis = 4;
  Ioctl(c, X4STEP_SET_PROFILE, &pr);
  Goto(c, 0x9, {400, 0, 0, 3000});
  usleep(100000);
  x4step_halt h{0x8, X4STEP_HALT_BRAKE, {0, 0}};
  Ioctl(c, X4STEP_HALT, &h);
  std::vector<x4step_event> ends;
  ev = mon.Until([&](const x4step_event &e) {
    if (e.type == X4STEP_EV_MOVE_ENDED) ends.push_back(e);
    return ends.size() == 2;
  });
  bool ok = ev.size() == 5 && Is(ev[0], X4STEP_EV_MOVE_STARTED, X4STEP_KIND_GOTO, 1) &&
            Is(ev[1], X4STEP_EV_MOVE_STARTED, X4STEP_KIND_GOTO, 8);
  int braked = 0, completed = 0;
  for (const auto &e : ev) {
    braked += Is(e, X4STEP_EV_BRAKE, X4STEP_SRC_IOCTL, 8) + Is(e, X4STEP_EV_MOVE_ENDED, X4STEP_END_BRAKED, 8);
    completed += Is(e, X4STEP_EV_MOVE_ENDED, X4STEP_END_COMPLETED, 1);
  }
  const x4step_axes a = Axes(c);
  Check(ok && braked == 2 && completed == 1 && ends.size() == 2 &&
            (ends[0].axes == 1 ? ends[0] : ends[1]).position[0] == 400 &&
            (ends[0].axes == 8 ? ends[0] : ends[1]).position[3] == a.axis[3].position,
        "two gotos, one braked by HALT: a start each, the brake of axis 4, their ends: " + Str(ev));
}

void Switches(Stream &mon, int c) {
  // E+ of axis 1 on input 1: the machine's switch is active from 300 on.
  Put(kV + "positions", "0 0 0 0\n");
  Put(kV + "switches", "clear; add 1 0 above 300 0 no\n");
  Zero(c);
  mon.Now();
  x4step_switches sw{};
  sw.plus[0] = 1;
  sw.ref[1] = 2;
  Check(Ioctl(c, X4STEP_SET_SWITCHES, &sw) == 0, "switches: E+ 1 on input 1, REF 2 on input 2");
  Goto(c, 1, {1000});
  auto ev = mon.Until(EndOf(1));
  Check(Match(ev, {{X4STEP_EV_MOVE_STARTED, X4STEP_KIND_GOTO, 1},
                   {X4STEP_EV_SWITCH, X4STEP_SW_LIMIT_POS, 1},
                   {X4STEP_EV_MOVE_ENDED, X4STEP_END_LIMIT, 1}}) &&
            ev[1].value == 1 && !ev[1].flags && ev[2].position[0] >= 299 && ev[2].position[0] <= 301,
        "goto onto E+: the switch (input 1), the end at the limit: " + Str(ev));

  // A reference run of axis 2: REF active at -200 and below, 5 steps of hysteresis.
  Put(kV + "switches", "clear; add 2 1 below -200 5 no\n");
  // Phase 1 brakes past REF along the axis' ae before phase 2: 45 steps.
  x4step_profile prof{2, 0, 0, 1000, 1000, 100000, {0, 0}};
  Check(Ioctl(c, X4STEP_SET_PROFILE, &prof) == 0, "axis 2 brakes with 100000 steps/s^2");
  x4step_home hm{2, X4STEP_HOME_AUTO, -3000, 300, 10000, -1, {0, 0}};
  Ioctl(c, X4STEP_HOME, &hm);
  ev = mon.Until(EndOf(2), 10000);
  Check(Match(ev, {{X4STEP_EV_MOVE_STARTED, X4STEP_KIND_HOME, 2},
                   {X4STEP_EV_SWITCH, X4STEP_SW_REF, 2},
                   {X4STEP_EV_SWITCH, X4STEP_SW_REF, 2},
                   {X4STEP_EV_MOVE_ENDED, X4STEP_END_HOMED, 2}}) &&
            ev[1].value == 2 && ev[3].position[1] == 0 && ev[1].position[1] <= -200,
        "reference run: REF ends phase 1 and phase 2, homed at 0: " + Str(ev));

  hm.phases = X4STEP_HOME_PHASE1;
  Ioctl(c, X4STEP_HOME, &hm);
  ev = mon.Until(EndOf(2), 10000);
  Check(Match(ev, {{X4STEP_EV_MOVE_STARTED, X4STEP_KIND_HOME, 2},
                   {X4STEP_EV_SWITCH, X4STEP_SW_REF, 2},
                   {X4STEP_EV_MOVE_ENDED, X4STEP_END_REF_FOUND, 2}}),
        "phase 1 alone: REF found: " + Str(ev));

  // Phase 2 deeper into the active switch: it never changes within sref.
  hm.phases = X4STEP_HOME_PHASE2;
  hm.vref2 = -300;
  hm.sref = 50;
  Ioctl(c, X4STEP_HOME, &hm);
  ev = mon.Until(EndOf(2), 10000);
  Check(Match(ev, {{X4STEP_EV_MOVE_STARTED, X4STEP_KIND_HOME, 2},
                   {X4STEP_EV_MOVE_ENDED, X4STEP_END_REF_TRAVEL, 2}}),
        "phase 2 beyond sref: reference travel: " + Str(ev));

  Put(kV + "switches", "clear\n");
  sw = {};
  Ioctl(c, X4STEP_SET_SWITCHES, &sw);
}

void Keys(Stream &mon, int c) {
  guest::Keyboard kb("x4step events test keyboard");
  if (!kb.ok()) {
    Check(false, "uinput keyboard");
    return;
  }
  Endless(c, 1, 1, 1000, 50);
  usleep(100000);
  kb.Tap(KEY_ESC);
  auto ev = mon.Until(EndOf(1));
  Check(Match(ev, {{X4STEP_EV_MOVE_STARTED, X4STEP_KIND_ENDLESS, 1},
                   {X4STEP_EV_BRAKE, X4STEP_SRC_KEY, 1},
                   {X4STEP_EV_MOVE_ENDED, X4STEP_END_BRAKED, 1}}) &&
            ev[1].value == 1,
        "ESC brakes: the brake by key code 1: " + Str(ev));
}

int EStop(int fd, uint32_t how, uint32_t flags = 0, uint32_t reserved = 0) {
  x4step_estop e{how, flags, {reserved, 0}};
  return Ioctl(fd, X4STEP_ESTOP, &e);
}

// The machine's coordinate of axis i, counted by the virtual port from the edges.
long long Machine(int i) {
  std::istringstream in(Slurp(kV + "positions"));
  long long p[4] = {};
  for (auto &v : p) in >> v;
  return p[i];
}

// X4STEP_ESTOP on a read-only descriptor halts the controller's moves:
// brakes along the ramp, stops at once (no edge after it); a bad argument halts nothing.
void EmergencyHalt(Stream &mon, int c) {
  const int ro = open(dev.c_str(), O_RDONLY | O_CLOEXEC);
  Check(EStop(ro, X4STEP_HALT_BRAKE) == ESRCH, "ESTOP with no move running: ESRCH");
  Endless(c, 3, 1, 1000, 50);
  usleep(100000);
  Check(EStop(ro, 2) == EINVAL && EStop(ro, X4STEP_HALT_STOP, 1) == EINVAL &&
            EStop(ro, X4STEP_HALT_STOP, 0, 1) == EINVAL && Ioctl(ro, X4STEP_ESTOP, nullptr) == EFAULT,
        "ESTOP with a bad how, flags, reserved word or pointer: EINVAL, EFAULT");
  Check(Axes(ro).axis[2].state & X4STEP_AX_RUN, "... and the move runs on");
  Check(Ioctl(ro, X4STEP_BRAKE) == EBADF, "X4STEP_BRAKE stays the controller's (EBADF read-only)");
  Check(EStop(ro, X4STEP_HALT_BRAKE) == 0, "a read-only descriptor's ESTOP brakes the controller's move");
  auto ev = mon.Until(EndOf(4));
  Check(Match(ev, {{X4STEP_EV_MOVE_STARTED, X4STEP_KIND_ENDLESS, 4},
                   {X4STEP_EV_BRAKE, X4STEP_SRC_ESTOP, 4},
                   {X4STEP_EV_MOVE_ENDED, X4STEP_END_BRAKED, 4}}) &&
            ev[1].value == X4STEP_HALT_BRAKE,
        "the emergency brake's events: its source and how, the move braked: " + Str(ev));

  Endless(c, 3, -1, 1000, 50);
  usleep(300000);
  Check(EStop(ro, X4STEP_HALT_STOP) == 0, "a read-only descriptor's ESTOP stops the controller's move");
  const long long at = Machine(2);
  ev = mon.Until(EndOf(4));
  Check(Match(ev, {{X4STEP_EV_MOVE_STARTED, X4STEP_KIND_ENDLESS, 4},
                   {X4STEP_EV_BRAKE, X4STEP_SRC_ESTOP, 4},
                   {X4STEP_EV_MOVE_ENDED, X4STEP_END_STOPPED, 4}}) &&
            ev[1].value == X4STEP_HALT_STOP,
        "the emergency stop's events: its source and how, the move stopped: " + Str(ev));
  usleep(200000);
  const x4step_axes a = Axes(ro);
  Check(!(a.axis[2].state & X4STEP_AX_RUN) && Machine(2) == at && a.axis[2].position == at,
        F("no edge after the emergency stop: the machine at %lld, then %lld, the coordinate %d", at,
          Machine(2), a.axis[2].position));
  close(ro);
}

// The module's brake of a controller that closed: a monitor stops it.
void EmergencyHaltAfterClose(Stream &mon) {
  const int ro = open(dev.c_str(), O_RDONLY | O_CLOEXEC);
  const int c2 = OpenCtl();
  Check(c2 >= 0, "a controller opens again");
  // At 600 steps/s or more the close's brake takes 600 ms or more (of guest
  // time; late timers only stretch it): waited for by the axis' speed, and
  // the ESTOP follows once the axis is seen braking, not after fixed times
  // (the guest's time is the loaded host's under plain TCG).
  Endless(c2, 3, 1, 1000, 1000);
  Check(WaitAxis(ro, 2, [](const x4step_axis &a) { return a.velocity >= 600; }),
        "the endless move reaches 600 steps/s");
  close(c2);
  const bool braking = WaitAxis(ro, 2, [](const x4step_axis &a) { return (a.state & X4STEP_AX_DECEL) != 0; });
  Check(braking && EStop(ro, X4STEP_HALT_STOP) == 0,
        "ESTOP stops the module's brake of a closed controller's move");
  const auto ev = mon.Until(
      [](const x4step_event &e) { return e.type == X4STEP_EV_CONTROLLER && e.how == X4STEP_CTL_RELEASED; },
      3000);
  Check(!ev.empty() && Is(ev.back(), X4STEP_EV_CONTROLLER, X4STEP_CTL_RELEASED, 0) && ev.size() >= 2 &&
            Is(ev[ev.size() - 2], X4STEP_EV_MOVE_ENDED, X4STEP_END_STOPPED, 4),
        "... it ends stopped, and the port is released: " + Str(ev));
  close(ro);
}

void CloseWhileMoving(Stream &mon, int c) {
  Endless(c, 2, -1, 2000, 200);
  usleep(300000);
  close(c);
  auto ev = mon.Until(
      [](const x4step_event &e) { return e.type == X4STEP_EV_CONTROLLER && e.how == X4STEP_CTL_RELEASED; });
  Check(Match(ev, {{X4STEP_EV_MOVE_STARTED, X4STEP_KIND_ENDLESS, 2},
                   {X4STEP_EV_CONTROLLER, X4STEP_CTL_CLOSED, 0},
                   {X4STEP_EV_BRAKE, X4STEP_SRC_CLOSE, 2},
                   {X4STEP_EV_MOVE_ENDED, X4STEP_END_BRAKED, 2},
                   {X4STEP_EV_CONTROLLER, X4STEP_CTL_RELEASED, 0}}),
        "the controller closes while moving: closed, the module's brake, the end, the release: " + Str(ev));
}

// A reader that fell behind resumes at the oldest event kept, the gap visible.
void Overrun(Stream &mon) {
  Stream lag;
  lag.fd = open(dev.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  const uint64_t first = mon.last_seq + 1;  // lag's first event
  std::vector<x4step_event> mine;
  for (int k = 0; k < 3; k++) {                     // 450 events, the monitor reading between
    for (int i = 0; i < 50; i++) close(OpenCtl());  // 3 events each
    const auto got = mon.Until([&](const x4step_event &e) { return e.seq == first + 150 * k + 149; });
    mine.insert(mine.end(), got.begin(), got.end());
  }
  x4step_event e{};
  const ssize_t n = read(lag.fd, &e, sizeof e);
  lag.last_seq = e.seq;
  lag.last_ns = e.timestamp_ns;
  const auto rest = lag.Now();
  Check(mine.size() == 450 && mon.last_seq == first + 449,
        F("a reader that keeps up: all 450 (%zu)", mine.size()));
  Check(
      n == sizeof e && e.seq == first + 450 - 256 && rest.size() == 255 && !lag.bad &&
          rest.back().seq == first + 449,
      F("a reader 450 behind: resumes at #%llu, the oldest of 256 kept (%zu read, gap of %llu from #%llu)%s",
        (unsigned long long)e.seq, rest.size() + 1, (unsigned long long)(e.seq - first),
        (unsigned long long)first, lag.why.c_str()));
  close(lag.fd);
}

// A blocking read() sleeps until an event comes.
void Blocking() {
  const int fd = open(dev.c_str(), O_RDONLY | O_CLOEXEC);
  std::atomic<bool> done{false};
  x4step_event e{};
  ssize_t n = 0;
  std::thread t([&] {
    n = read(fd, &e, sizeof e);
    done = true;
  });
  usleep(300000);
  const bool early = done;
  const auto t0 = std::chrono::steady_clock::now();
  close(OpenCtl());
  while (!done && guest::MsSince(t0) < 2000) usleep(1000);
  const double ms = guest::MsSince(t0);
  if (!done) close(OpenCtl());  // unblock it
  t.join();
  Check(!early && n == sizeof e && e.type == X4STEP_EV_CONTROLLER && e.how == X4STEP_CTL_OPENED,
        F("blocking read: sleeps (%s after 300 ms), returns the next event %.1f ms after it happened: %s",
          early ? "returned" : "still waiting", ms, Str(e).c_str()));
  close(fd);
}

// The port goes away: its last event, then ENODEV; POLLERR | POLLHUP.
void PortGone(Stream &mon) {
  const int blocked = open(dev.c_str(), O_RDONLY | O_CLOEXEC);
  ssize_t bn = 0;
  x4step_event be{};
  std::thread t([&] { bn = read(blocked, &be, sizeof be); });
  usleep(200000);
  const int rc = std::system("rmmod x4vport");
  t.join();
  auto ev = mon.Until([](const x4step_event &e) { return e.type == X4STEP_EV_PORT_GONE; });
  x4step_event e;
  const ssize_t n = read(mon.fd, &e, sizeof e);
  const int err = errno;
  pollfd p{mon.fd, POLLIN | POLLPRI, 0};
  poll(&p, 1, 0);
  Check(rc == 0 && !ev.empty() && ev.back().type == X4STEP_EV_PORT_GONE && n < 0 && err == ENODEV &&
            p.revents == (POLLERR | POLLHUP),
        F("port removed: %s, then read fails with %s, poll 0x%x", Str(ev).c_str(), std::strerror(err),
          p.revents));
  Check(bn == sizeof be && be.type == X4STEP_EV_PORT_GONE,
        "a blocked reader wakes with the port-gone event: " + Str(be));
  close(blocked);
}

}  // namespace

int main() {
  setvbuf(stdout, nullptr, _IOLBF, 0);
  port = std::atoi(Slurp(kV + "port").c_str());
  dev = F("/dev/x4step%d", port);
  if (Slurp(kV + "port").empty() || access(dev.c_str(), F_OK)) {
    Check(false, "x4vport and " + dev);
    return guest::Finish("events_test");
  }
  StatusLeavesThePortAlone();

  Stream mon;
  mon.fd = open(dev.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  Basics(mon);
  Buffers(mon);
  int c = OpenCtl();
  Check(c >= 0, "controller opens");
  Moves(mon, c);
  Switches(mon, c);
  Keys(mon, c);
  EmergencyHalt(mon, c);
  CloseWhileMoving(mon, c);
  EmergencyHaltAfterClose(mon);
  Overrun(mon);
  Blocking();
  mon.Now();
  Check(!mon.bad,
        F("the monitor's whole stream: seq without gaps, times monotonic, fields sane, up to #%llu%s",
          (unsigned long long)mon.last_seq, mon.why.empty() ? "" : (": " + mon.why).c_str()));
  PortGone(mon);
  close(mon.fd);
  return guest::Finish("events_test");
}
