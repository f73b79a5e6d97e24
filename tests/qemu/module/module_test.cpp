// SPDX-License-Identifier: GPL-2.0
// In-guest test of the x4step module's ioctl interface, run in QEMU
// against Debian's parport_pc. Moves print `SEG s1 s2 s3 s4 [braked]`:
// the host checks each against the AKTIV-framed segment of QEMU's port
// trace (tests/qemu/common/check-segments.sh). Checks print PASS/FAIL lines.
#include <fcntl.h>
#include <linux/x4step.h>
#include <poll.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

#include "check.hpp"

namespace {

using guest::Check;

const char *dev_path = "/dev/x4step0";

int OpenCtl() { return open(dev_path, O_RDWR | O_CLOEXEC); }

x4step_status Status(int fd) {
  x4step_status st{};
  if (ioctl(fd, X4STEP_GET_STATUS, &st)) std::perror("GET_STATUS");
  return st;
}

void WaitIdle(int fd) {
  pollfd p{fd, POLLIN, 0};
  while (poll(&p, 1, 10000) == 1 && !(p.revents & POLLIN)) {
  }
}

// ioctl result: 0 or errno.
int Ioctl(int fd, unsigned long cmd, void *arg = nullptr) { return ioctl(fd, cmd, arg) ? errno : 0; }

int Load(int fd, int s1, int s2, int s3, int s4, int freq, int ramp, int *result = nullptr) {
  x4step_move m{{s1, s2, s3, s4}, freq, ramp, 0, -1};
  const int err = Ioctl(fd, X4STEP_LOAD, &m);
  if (result) *result = m.result;
  return err;
}

int Endless(int fd, int axis, int dir, int freq, int ramp, int *result = nullptr) {
  x4step_endless e{axis, dir, freq, ramp, 0, -1, {0, 0}};
  const int err = Ioctl(fd, X4STEP_MOVE_ENDLESS, &e);
  if (result) *result = e.result;
  return err;
}

void PrintSeg(const x4step_status &st, const char *extra = "") {
  std::printf("SEG %lld %lld %lld %lld%s\n", (long long)st.steps[0], (long long)st.steps[1],
              (long long)st.steps[2], (long long)st.steps[3], extra);
}

void TestExampleAndPreload(int fd) {
  Check(Load(fd, 1000, 800, 600, 400, 1000, 50) == 0, "load manual example");
  Check(Status(fd).flags & X4STEP_ST_LOADED, "status shows loaded");
  Check(Ioctl(fd, X4STEP_START) == 0, "start");
  Check(Status(fd).flags & X4STEP_ST_ACTIVE, "status shows active");
  Check(Load(fd, -1000, -800, -600, -400, 1000, 50) == 0, "preload the way back");
  Check(Ioctl(fd, X4STEP_START) == EBUSY, "start while running: EBUSY (IsActive)");
  WaitIdle(fd);
  x4step_status st = Status(fd);
  Check(!(st.flags & X4STEP_ST_ACTIVE) && st.steps[0] == 1000 && st.steps[3] == 400, "first move done");
  Check(!(st.outputs & X4STEP_OUT_AKTIV), "AKTIV low after the move");
  PrintSeg(st);
  Check(Ioctl(fd, X4STEP_START) == 0, "start preloaded move");
  WaitIdle(fd);
  st = Status(fd);
  Check(st.steps[0] == -1000 && st.steps[1] == -800 && st.steps[2] == -600 && st.steps[3] == -400,
        "preloaded move done");
  PrintSeg(st);
  Check(Ioctl(fd, X4STEP_START) == ENODATA, "start with nothing loaded: ENODATA (NotLoaded)");
}

// Counts the tests wait for before braking or stopping (not fixed sleeps:
// without -icount a loaded host lets the guest do less in its time).
bool Moved(int fd, int axis, long long past) {
  return guest::WaitFor([&] {
    const long long s = Status(fd).steps[axis];
    return past < 0 ? s < past : s > past;
  });
}

void TestBrakeAndStop(int fd) {
  Check(Endless(fd, 2, 1, 2000, 100) == 0, "endless axis 2");
  Check(Moved(fd, 1, 700), "endless axis 2 makes 700 steps (its ramp, then at speed; 400 ms)");
  Check(Ioctl(fd, X4STEP_BRAKE) == 0, "brake");
  WaitIdle(fd);
  x4step_status st = Status(fd);
  Check(st.steps[1] > 100, "braked after moving");
  PrintSeg(st, " braked");
  Check(Ioctl(fd, X4STEP_BRAKE) == ESRCH, "brake while idle: ESRCH (NotActive)");

  Check(Endless(fd, 3, -1, 1000, 0) == 0, "endless axis 3 negative");
  Check(Moved(fd, 2, -300), "endless axis 3 makes 300 steps (300 ms)");
  Check(Ioctl(fd, X4STEP_STOP) == 0, "stop");
  st = Status(fd);
  Check(!(st.flags & X4STEP_ST_ACTIVE), "idle right after stop");
  Check((st.data & 0xaa) == 0, "no clock left high");
  Check(st.steps[2] < -10, "stopped after moving");
  PrintSeg(st);
  Check(Ioctl(fd, X4STEP_STOP) == ESRCH, "stop while idle: ESRCH (NotActive)");
}

void TestBadInput(int fd) {
  int result = 0;
  const struct {
    int s1, freq, ramp, code;
  } bad[] = {{0, 1000, 50, 1},         {1, 20001, 0, 2}, {1, 9, 0, 3},
             {1, 2000, 1001, 4},       {1, 10, 50, 5},   {16777217, 1000, 0, 13},
             {-16777217, 1000, 0, 13}, {1, 100, -1, 8}};
  for (const auto &b : bad) {
    const int err = Load(fd, b.s1, 0, 0, 0, b.freq, b.ramp, &result);
    Check(err == EINVAL && result == b.code, "load " + std::to_string(b.s1) + "/" + std::to_string(b.freq) +
                                                 "/" + std::to_string(b.ramp) + ": EINVAL, result " +
                                                 std::to_string(b.code) + " (got " + std::to_string(err) +
                                                 ", " + std::to_string(result) + ")");
  }
  Check(!(Status(fd).flags & X4STEP_ST_LOADED), "nothing loaded after bad loads");
  x4step_move flagged{{1, 0, 0, 0}, 1000, 0, 1, 0};
  Check(Ioctl(fd, X4STEP_LOAD, &flagged) == EINVAL, "load with unknown flags: EINVAL");
  Check(Endless(fd, 0, 1, 1000, 0, &result) == EINVAL && result == 8, "endless axis 0: ParamFail");
  Check(Endless(fd, 5, 1, 1000, 0, &result) == EINVAL && result == 8, "endless axis 5: ParamFail");
  Check(Endless(fd, 1, 0, 1000, 0, &result) == EINVAL && result == 8, "endless direction 0: ParamFail");
  Check(Endless(fd, 1, 1, 30000, 0, &result) == EINVAL && result == 2, "endless 30 kHz: FreqTooHigh");
  Check(Endless(fd, 1, 1, 100, 200, &result) == EINVAL && result == 5, "endless ramp > freq: RampFreq");
  Check(Ioctl(fd, _IO(X4STEP_IOC_MAGIC, 0x7f)) == ENOTTY, "unknown ioctl: ENOTTY");
  Check(Ioctl(fd, _IOW(X4STEP_IOC_MAGIC, 0x01, int)) == ENOTTY, "load with the wrong size: ENOTTY");
  Check(Ioctl(fd, X4STEP_LOAD, reinterpret_cast<void *>(8)) == EFAULT, "load from a bad pointer: EFAULT");
  x4step_output out{3, 1};
  Check(Ioctl(fd, X4STEP_SET_OUTPUT, &out) == EINVAL, "output 3: EINVAL");
  x4step_brake_codes codes{};
  codes.count = 21;
  Check(Ioctl(fd, X4STEP_SET_BRAKE_CODES, &codes) == EINVAL, "21 brake codes: EINVAL");
  codes.count = 1;
  codes.codes[0] = 256;
  Check(Ioctl(fd, X4STEP_SET_BRAKE_CODES, &codes) == EINVAL, "brake code 256: EINVAL");
  x4step_config cfg{};
  cfg.reserved[3] = 1;
  Check(Ioctl(fd, X4STEP_SET_CONFIG, &cfg) == EINVAL, "config reserved field set: EINVAL");

  Check(OpenCtl() < 0 && errno == EBUSY, "second controller: EBUSY");
  const int ro = open(dev_path, O_RDONLY | O_CLOEXEC);
  Check(ro >= 0, "read-only monitor opens");
  Check(Load(ro, 1, 0, 0, 0, 1000, 0) == EBADF, "load on a read-only fd: EBADF");
  x4step_outputs ro_out{X4STEP_OUT_SIGNAL1, X4STEP_OUT_SIGNAL1, 0, {}};
  Check(Ioctl(ro, X4STEP_SET_OUTPUTS, &ro_out) == EBADF, "SET_OUTPUTS on a read-only fd: EBADF");
  Check(Ioctl(ro, X4STEP_START) == EBADF, "start on a read-only fd: EBADF");
  Check(Ioctl(ro, X4STEP_STOP) == EBADF, "stop on a read-only fd: EBADF");
  x4step_status st;
  std::memset(&st, 0xa5, sizeof st);
  Check(Ioctl(ro, X4STEP_GET_STATUS, &st) == 0 && (st.flags & X4STEP_ST_CONTROLLED),
        "status on a read-only fd");
  Check(st.reserved0 == 0 && !(st.flags & X4STEP_ST_INPUTS_STALE) && st.inputs_time_ns,
        "status: reserved field zeroed; inputs live beside a controller, with their time");
  x4step_info info;
  Check(Ioctl(ro, X4STEP_GET_INFO, &info) == 0 && info.abi_version == X4STEP_ABI_VERSION && info.axes == 4,
        "info");
  close(ro);
}

void TestOutputs(int fd) {
  x4step_output on1{X4STEP_OUT_SIGNAL1, 1}, on2{X4STEP_OUT_SIGNAL2, 1}, off1{X4STEP_OUT_SIGNAL1, 0};
  Check(Ioctl(fd, X4STEP_SET_OUTPUT, &on1) == 0, "signal 1 on");
  Check(Ioctl(fd, X4STEP_SET_OUTPUT, &on2) == 0, "signal 2 on");
  Check(Ioctl(fd, X4STEP_SET_OUTPUT, &off1) == 0, "signal 1 off");
  Check((Status(fd).outputs & 3) == X4STEP_OUT_SIGNAL2, "outputs read back");
  x4step_output off2{X4STEP_OUT_SIGNAL2, 0};
  Ioctl(fd, X4STEP_SET_OUTPUT, &off2);

  // ABI 4: both signals in one call; flags and reserved words must be 0.
  x4step_outputs both{};
  both.mask = X4STEP_OUT_SIGNAL1 | X4STEP_OUT_SIGNAL2;
  both.levels = both.mask;
  Check(Ioctl(fd, X4STEP_SET_OUTPUTS, &both) == 0 && (Status(fd).outputs & 3) == 3, "SET_OUTPUTS: both on");
  both.levels = X4STEP_OUT_SIGNAL2;
  Check(Ioctl(fd, X4STEP_SET_OUTPUTS, &both) == 0 && (Status(fd).outputs & 3) == 2,
        "SET_OUTPUTS: signal 1 off, 2 on");
  x4step_outputs one{};
  one.mask = X4STEP_OUT_SIGNAL1;
  one.levels = X4STEP_OUT_SIGNAL1;
  Check(Ioctl(fd, X4STEP_SET_OUTPUTS, &one) == 0 && (Status(fd).outputs & 3) == 3,
        "SET_OUTPUTS: signal 1 alone, signal 2 kept");
  const struct {
    uint32_t mask, levels, flags, reserved4;
    const char *what;
  } bad[] = {{0, 0, 0, 0, "empty mask"},
             {4, 0, 0, 0, "mask beyond the signals (BOOST)"},
             {1, 2, 0, 0, "level outside the mask"},
             {3, 3, 1, 0, "flags"},
             {3, 0, 0, 1, "last reserved word"}};
  for (const auto &b : bad) {
    x4step_outputs o{};
    o.mask = b.mask;
    o.levels = b.levels;
    o.flags = b.flags;
    o.reserved[4] = b.reserved4;
    Check(Ioctl(fd, X4STEP_SET_OUTPUTS, &o) == EINVAL && (Status(fd).outputs & 3) == 3,
          std::string("SET_OUTPUTS refused, nothing changed: ") + b.what);
  }
  both.levels = 0;
  Check(Ioctl(fd, X4STEP_SET_OUTPUTS, &both) == 0 && (Status(fd).outputs & 3) == 0, "SET_OUTPUTS: both off");
}

// A controller killed mid-move: the module brakes the motor, then lets go
// of the port (close() does not wait for the brake: poll() says when).
// Killed at speed (1000 steps/s, after the 200 ms ramp, at 500 steps: what
// 600 ms gave): the move started (the child says so) and its steps seen on
// a read-only descriptor, not a fixed sleep.
void TestKilledController() {
  int started[2];
  if (pipe(started)) return;
  const pid_t child = fork();
  if (child == 0) {
    const int fd = OpenCtl();
    if (fd < 0 || Endless(fd, 1, 1, 1000, 200) || write(started[1], "s", 1) != 1) _exit(1);
    for (;;) pause();
  }
  close(started[1]);
  char c = 0;
  const bool running = read(started[0], &c, 1) == 1;
  close(started[0]);
  const int ro = open(dev_path, O_RDONLY | O_CLOEXEC);
  Check(running && ro >= 0 && Moved(ro, 0, 500), "the controller's endless move makes 500 steps");
  if (ro >= 0) close(ro);
  kill(child, SIGKILL);
  int status = 0;
  waitpid(child, &status, 0);
  Check(WIFSIGNALED(status), "controller killed mid-move");
  Check(guest::WaitFree(dev_path, 10000), "the port is free once the module has braked");
  const int fd = OpenCtl();
  Check(fd >= 0, "next controller opens after the kill");
  if (fd < 0) return;
  const x4step_status st = Status(fd);
  Check(!(st.flags & X4STEP_ST_ACTIVE), "nothing runs after the kill");
  std::printf("SEG ? 0 0 0 braked\n");
  close(fd);
}

}  // namespace

int main(int argc, char **argv) {
  if (argc > 1) dev_path = argv[1];
  setvbuf(stdout, nullptr, _IOLBF, 0);
  const int fd = OpenCtl();
  Check(fd >= 0, std::string("open ") + dev_path);
  if (fd < 0) return 1;
  TestBadInput(fd);
  TestOutputs(fd);
  TestExampleAndPreload(fd);
  TestBrakeAndStop(fd);
  close(fd);
  TestKilledController();
  return guest::Finish("module_test");
}
