// SPDX-License-Identifier: GPL-2.0
// In-guest test of the brake keys: a uinput keyboard types, the module's
// input handler brakes. Prints PASS/FAIL lines and the brake latency.
// With X4STEP_CFG_KEYS_SWALLOW an evdev reader of the same keyboard checks
// that a key's press and release are swallowed together.
#include <fcntl.h>
#include <linux/x4step.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "check.hpp"
#include "keyboard.hpp"

namespace {

using guest::Check;
using guest::Keyboard;

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

// An endless move at its speed (after its 50 ms ramp) for some 100 steps
// (125 in all: what 150 ms gave), seen from the axis' speed and the move's
// steps rather than after a fixed sleep (without -icount a loaded host lets
// the guest do less in its time): the brakes below start at speed.
void Endless(int fd) {
  x4step_endless e{1, 1, 1000, 50, 0, 0, {0, 0}};
  if (ioctl(fd, X4STEP_MOVE_ENDLESS, &e)) std::perror("MOVE_ENDLESS");
  const bool at_speed = guest::WaitFor([&] {
    x4step_axes a{};
    return ioctl(fd, X4STEP_GET_AXES, &a) == 0 &&
           a.axis[0].velocity >= 990 &&  // 1e9 / interval may round down
           Status(fd).steps[0] >= 125;
  });
  if (!at_speed) Check(false, "endless move at 1000 steps/s, 125 steps");
}

bool SetSwallow(int fd, bool on) {
  x4step_config cfg{};
  if (ioctl(fd, X4STEP_GET_CONFIG, &cfg)) return false;
  cfg.flags = on ? cfg.flags | X4STEP_CFG_KEYS_SWALLOW : cfg.flags & ~X4STEP_CFG_KEYS_SWALLOW;
  return ioctl(fd, X4STEP_SET_CONFIG, &cfg) == 0;
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

  // Swallowed keys: an application reading the keyboard sees a key's press
  // and release together or not at all, never a key stuck down (a press
  // without its release) nor a release without its press.
  Check(kb.OpenEvdev() >= 0, "evdev reader of the test keyboard");
  Check(SetSwallow(fd, true), "keys swallowed (X4STEP_CFG_KEYS_SWALLOW)");
  kb.Seen(KEY_ENTER);

  // Not swallowed while no move runs.
  SetCodes(fd, {28});
  kb.Key(KEY_ENTER, 1);
  kb.Key(KEY_ENTER, 0);
  Check(kb.Seen(KEY_ENTER) == "+-", "swallow: a brake key passes while no move runs");

  // Make code: the press brakes and is swallowed, and so are its
  // auto-repeat and its release (the move has ended by then).
  Endless(fd);
  ExpectBrake(fd, kb, KEY_ENTER, 1, 28, "swallow: ENTER press");
  kb.Key(KEY_ENTER, 2);
  kb.Key(KEY_ENTER, 0);
  std::string seen = kb.Seen(KEY_ENTER);
  Check(seen.empty(),
        "swallow, make code: press, auto-repeat and release all swallowed (seen '" + seen + "')");

  // Break code: the press (no brake code) reaches the application while a
  // move runs, so its release must too, although it brakes.
  SetCodes(fd, {28 + 128});
  Endless(fd);
  kb.Key(KEY_ENTER, 1);
  usleep(100000);
  Check(Active(fd), "swallow, break code: the press does not brake");
  ExpectBrake(fd, kb, KEY_ENTER, 0, 156, "swallow: ENTER release");
  seen = kb.Seen(KEY_ENTER);
  Check(seen == "+-" || seen.empty(),
        "swallow, break code: press and release seen together or not at all (seen '" + seen + "')");
  Check(seen == "+-", "swallow, break code: the passed press's release passes though it brakes");

  // Break code of a key held since before the move (the manual's example 7).
  kb.Key(KEY_ENTER, 1);
  Endless(fd);
  ExpectBrake(fd, kb, KEY_ENTER, 0, 156, "swallow: release of a key held before the move");
  seen = kb.Seen(KEY_ENTER);
  Check(seen == "+-", "swallow, key held before the move: press and release seen (seen '" + seen + "')");

  // Make and break code: the press brakes, both are swallowed.
  SetCodes(fd, {28, 28 + 128});
  Endless(fd);
  ExpectBrake(fd, kb, KEY_ENTER, 1, 28, "swallow: ENTER press (make and break code)");
  kb.Key(KEY_ENTER, 0);
  seen = kb.Seen(KEY_ENTER);
  Check(seen.empty(), "swallow, make and break code: press and release swallowed (seen '" + seen + "')");

  // ESC, always a brake code.
  SetCodes(fd, {});
  Endless(fd);
  ExpectBrake(fd, kb, KEY_ESC, 1, 1, "swallow: ESC");
  kb.Key(KEY_ESC, 0);
  seen = kb.Seen(KEY_ESC);
  Check(seen.empty(), "swallow: ESC press and release swallowed (seen '" + seen + "')");

  // A process that grabs the keyboard (EVIOCGRAB) takes its keys, ESC too,
  // away from x4step's handler: the input core then delivers to the grab
  // only. Documented in docs/interface.md (Brake keys).
  Endless(fd);
  Check(kb.Grab(true), "EVIOCGRAB of the test keyboard");
  kb.Key(KEY_ESC, 1);
  kb.Key(KEY_ESC, 0);
  usleep(100000);
  Check(Active(fd), "ESC on a grabbed keyboard does not brake (documented)");
  seen = kb.Seen(KEY_ESC);
  Check(seen == "+-", "the grabbing reader gets ESC's press and release (seen '" + seen + "')");
  kb.Grab(false);
  ExpectBrake(fd, kb, KEY_ESC, 1, 1, "ESC after the grab ends");
  kb.Key(KEY_ESC, 0);
  seen = kb.Seen(KEY_ESC);
  Check(seen.empty(), "swallow after the grab: ESC press and release swallowed (seen '" + seen + "')");

  // A grab that takes a swallowed press's release leaves no stale state:
  // the key's next press and release, with no move running, both pass.
  SetCodes(fd, {28});
  Endless(fd);
  ExpectBrake(fd, kb, KEY_ENTER, 1, 28, "swallow: ENTER press before a grab");
  kb.Grab(true);
  kb.Key(KEY_ENTER, 0);
  kb.Grab(false);
  kb.Seen(KEY_ENTER);  // the grab's release without a press: x4step never saw it
  kb.Key(KEY_ENTER, 1);
  kb.Key(KEY_ENTER, 0);
  seen = kb.Seen(KEY_ENTER);
  Check(seen == "+-",
        "swallow: after a grab took a release, the next press and release pass (seen '" + seen + "')");
  Check(SetSwallow(fd, false), "keys no longer swallowed");

  // Without swallowing, a brake key reaches the application entirely.
  SetCodes(fd, {28});
  Endless(fd);
  ExpectBrake(fd, kb, KEY_ENTER, 1, 28, "no swallow: ENTER press");
  kb.Key(KEY_ENTER, 0);
  seen = kb.Seen(KEY_ENTER);
  Check(seen == "+-", "no swallow: press and release seen (seen '" + seen + "')");

  std::sort(latencies.begin(), latencies.end());
  if (!latencies.empty())
    std::printf(
        "brake-key latency (uinput write -> engine braking): median %llu ns, max %llu ns over %zu keys\n",
        (unsigned long long)latencies[latencies.size() / 2], (unsigned long long)latencies.back(),
        latencies.size());
  close(fd);
  return guest::Finish("keys_test");
}
