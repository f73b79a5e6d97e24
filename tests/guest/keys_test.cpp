// SPDX-License-Identifier: GPL-2.0
// In-guest test of the brake keys: a uinput keyboard types, the module's
// input handler brakes. Prints PASS/FAIL lines and the brake latency.
#include <fcntl.h>
#include <linux/uinput.h>
#include <linux/x4step.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "check.hpp"

namespace {

using guest::Check;

uint64_t NowNs() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return uint64_t(ts.tv_sec) * 1000000000u + ts.tv_nsec;
}

class Keyboard {
 public:
  Keyboard() : fd_(open("/dev/uinput", O_WRONLY | O_NONBLOCK)) {
    ioctl(fd_, UI_SET_EVBIT, EV_KEY);
    for (int k = 1; k < 128; k++) ioctl(fd_, UI_SET_KEYBIT, k);
    uinput_setup setup{};
    setup.id.bustype = BUS_VIRTUAL;
    std::strcpy(setup.name, "x4step test keyboard");
    ioctl(fd_, UI_DEV_SETUP, &setup);
    ioctl(fd_, UI_DEV_CREATE);
    usleep(200000);  // let the handlers connect
  }
  ~Keyboard() {
    ioctl(fd_, UI_DEV_DESTROY);
    close(fd_);
  }
  bool ok() const { return fd_ >= 0; }
  // value: 1 press, 0 release, 2 auto-repeat. Returns the time before writing.
  uint64_t Key(int code, int value) {
    input_event ev[2] = {};
    ev[0].type = EV_KEY;
    ev[0].code = code;
    ev[0].value = value;
    ev[1].type = EV_SYN;
    ev[1].code = SYN_REPORT;
    const uint64_t t = NowNs();
    if (write(fd_, ev, sizeof ev) != sizeof ev) std::perror("uinput write");
    return t;
  }

 private:
  int fd_;
};

x4step_status Status(int fd) {
  x4step_status st{};
  ioctl(fd, X4STEP_GET_STATUS, &st);
  return st;
}

bool Active(int fd) { return Status(fd).flags & X4STEP_ST_ACTIVE; }

bool WaitIdle(int fd, int ms) {
  pollfd p{fd, POLLIN, 0};
  return poll(&p, 1, ms) == 1 && (p.revents & POLLIN);
}

void SetCodes(int fd, std::vector<int> codes) {
  x4step_brake_codes bc{};
  for (int c : codes) bc.codes[bc.count++] = c;
  if (ioctl(fd, X4STEP_SET_BRAKE_CODES, &bc)) std::perror("SET_BRAKE_CODES");
}

void Endless(int fd) {
  x4step_endless e{1, 1, 1000, 50, 0, 0, {0, 0}};
  if (ioctl(fd, X4STEP_MOVE_ENDLESS, &e)) std::perror("MOVE_ENDLESS");
  usleep(150000);
}

std::vector<uint64_t> latencies;

// A key event that must brake with `code`.
void ExpectBrake(int fd, Keyboard &kb, int key, int value, int code, const std::string &what) {
  const uint64_t t = kb.Key(key, value);
  const bool idle = WaitIdle(fd, 3000);
  const x4step_status st = Status(fd);
  Check(idle && st.last_brake_code == unsigned(code), what + " brakes with code " + std::to_string(code) +
                                                          " (got " + std::to_string(st.last_brake_code) +
                                                          ")");
  if (st.brake_time_ns > t) latencies.push_back(st.brake_time_ns - t);
  std::printf("SEG ? 0 0 0 braked\n");
}

}  // namespace

int main() {
  setvbuf(stdout, nullptr, _IOLBF, 0);
  Keyboard kb;
  Check(kb.ok(), "uinput keyboard");
  const int fd = open("/dev/x4step0", O_RDWR | O_CLOEXEC);
  Check(fd >= 0, "open controller");
  if (fd < 0 || !kb.ok()) return 1;

  // ESC always brakes, without being configured.
  SetCodes(fd, {});
  Endless(fd);
  kb.Key(KEY_A, 1);
  kb.Key(KEY_A, 0);
  usleep(100000);
  Check(Active(fd), "a key that is no brake code does not brake");
  ExpectBrake(fd, kb, KEY_ESC, 1, 1, "ESC");
  kb.Key(KEY_ESC, 0);

  // Make code: ENTER (28), as in the manual's X4BrakeCodes example.
  SetCodes(fd, {28});
  Endless(fd);
  ExpectBrake(fd, kb, KEY_ENTER, 1, 28, "ENTER press");
  kb.Key(KEY_ENTER, 0);

  // Break code: the manual's example 7, move while held, brake on release.
  SetCodes(fd, {30 + 128});
  Endless(fd);
  kb.Key(KEY_A, 1);
  kb.Key(KEY_A, 2);  // auto-repeat is no new press
  usleep(100000);
  Check(Active(fd), "press and auto-repeat of a break-code key do not brake");
  ExpectBrake(fd, kb, KEY_A, 0, 158, "release of A");

  // Extended keys as the MF2 table prints them.
  const struct {
    int key, code;
    const char *name;
  } mf2[] = {{KEY_UP, 72, "UP"},      {KEY_LEFT, 75, "LEFT"},       {KEY_RIGHT, 77, "RIGHT"},
             {KEY_DOWN, 80, "DOWN"},  {KEY_HOME, 71, "HOME"},       {KEY_PAGEUP, 73, "PGUP"},
             {KEY_END, 79, "END"},    {KEY_PAGEDOWN, 81, "PGDN"},   {KEY_INSERT, 82, "INS"},
             {KEY_DELETE, 83, "DEL"}, {KEY_KPENTER, 28, "KP ENTER"}};
  for (const auto &k : mf2) {
    SetCodes(fd, {k.code});
    Endless(fd);
    ExpectBrake(fd, kb, k.key, 1, k.code, k.name);
    kb.Key(k.key, 0);
  }

  // Cleared at the next start; 0 when braked otherwise.
  Endless(fd);
  Check(Status(fd).last_brake_code == 0, "last brake code cleared by the next start");
  ioctl(fd, X4STEP_BRAKE);
  WaitIdle(fd, 3000);
  std::printf("SEG ? 0 0 0 braked\n");
  Check(Status(fd).last_brake_code == 0, "last brake code 0 after an ioctl brake");

  // 20 codes accepted, the 20th works.
  std::vector<int> many;
  for (int c = 2; c < 22; c++) many.push_back(c);
  SetCodes(fd, many);
  Endless(fd);
  ExpectBrake(fd, kb, 21, 1, 21, "20th brake code");
  kb.Key(21, 0);

  std::sort(latencies.begin(), latencies.end());
  if (!latencies.empty())
    std::printf(
        "brake-key latency (uinput write -> engine braking): median %llu ns, max %llu ns over %zu keys\n",
        (unsigned long long)latencies[latencies.size() / 2], (unsigned long long)latencies.back(),
        latencies.size());
  close(fd);
  return guest::Finish("keys_test");
}
