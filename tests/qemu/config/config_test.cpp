// SPDX-License-Identifier: GPL-2.0
// In-guest half of the SET_CONFIG test on QEMU's parport (/dev/x4step0):
// wiring changes while idle (clock and direction inversion, output mode)
// between small moves that leave the pins in various states. Each change is
// framed in QEMU's port trace by markers written to the status register
// (which drives no pin): 0x58 0x43 CODE before it, CODE = clock_invert |
// mode << 4, and 0x58 0x4d before the next move. tests/qemu/config/check-config.sh
// then checks that no data write inside a frame makes an edge a driver
// wired for the NEW configuration counts as a step: no clock pin going to
// its active level (HIGH, or LOW when inverted); in the SMC phase modes no
// pattern that turns a motor (only "off", or the hold pattern of the
// motor's last position). A SET_CONFIG while a move runs must fail with
// EBUSY and change nothing. Prints PASS/FAIL lines and `CONFIGS n`.
#include <fcntl.h>
#include <linux/x4step.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

#include "check.hpp"

namespace {

using guest::Check;

int port_fd = -1;  // /dev/port

void Mark(std::initializer_list<uint8_t> bytes) {
  for (uint8_t b : bytes)
    if (pwrite(port_fd, &b, 1, 0x379) != 1) std::perror("/dev/port");
}

int Ioctl(int fd, unsigned long cmd, void *arg = nullptr) { return ioctl(fd, cmd, arg) ? errno : 0; }

void WaitIdle(int fd) {
  pollfd p{fd, POLLIN, 0};
  for (int i = 0; i < 100 && !(poll(&p, 1, 100) == 1 && (p.revents & POLLIN)); i++) {
  }
}

// A small move of every axis the mode drives, `sign` choosing directions.
bool Move(int fd, int sign, bool phase) {
  Mark({0x58, 0x4d});
  x4step_move m{{7 * sign, -5 * sign, 6 * sign, phase ? 0 : -4 * sign}, 2000, 0, 0, -1};
  const bool ok = Ioctl(fd, X4STEP_LOAD, &m) == 0 && Ioctl(fd, X4STEP_START) == 0;
  WaitIdle(fd);
  return ok;
}

std::string Str(const x4step_config &c) {
  char b[96];
  std::snprintf(b, sizeof b, "clock_invert 0x%x dir_invert 0x%x flags 0x%x mode %u", c.clock_invert,
                c.dir_invert, c.flags, c.output_mode);
  return b;
}

}  // namespace

int main() {
  setvbuf(stdout, nullptr, _IOLBF, 0);
  port_fd = open("/dev/port", O_WRONLY | O_CLOEXEC);
  const int fd = open("/dev/x4step0", O_RDWR | O_CLOEXEC);
  Check(port_fd >= 0 && fd >= 0, "open /dev/port and /dev/x4step0");
  if (port_fd < 0 || fd < 0) return 1;

  struct {
    uint32_t clock, dir, flags, mode;
  } const steps[] = {
      {0x5, 0x0, 0, X4STEP_MODE_CLOCK_DIR},
      {0xf, 0x3, 0, X4STEP_MODE_CLOCK_DIR},
      {0xa, 0x0, 0, X4STEP_MODE_CLOCK_DIR},
      {0xa, 0x0, X4STEP_CFG_KEYS_SWALLOW, X4STEP_MODE_CLOCK_DIR},  // the pins stay
      {0xa, 0x5, 0, X4STEP_MODE_CLOCK_DIR},                        // only directions
      {0xa, 0x0, 0, X4STEP_MODE_SMC_PHASE},
      {0x0, 0x0, 0, X4STEP_MODE_SMC_PHASE_HOLD},
      {0xf, 0x0, 0, X4STEP_MODE_CLOCK_DIR},  // from phase patterns to inverted clocks
      {0x3, 0x0, 0, X4STEP_MODE_SMC_PHASE_HOLD},
      {0x3, 0x0, 0, X4STEP_MODE_SMC_PHASE},
      {0x6, 0x0, 0, X4STEP_MODE_CLOCK_DIR},
      {0x0, 0x0, 0, X4STEP_MODE_CLOCK_DIR},
  };
  int n = 0, sign = 1;
  bool phase = false;
  Check(Move(fd, sign, phase), "a first move, default wiring");
  for (const auto &s : steps) {
    x4step_config c{};
    c.clock_invert = s.clock;
    c.dir_invert = s.dir;
    c.flags = s.flags;
    c.output_mode = s.mode;
    Mark({0x58, 0x43, static_cast<uint8_t>(s.clock | s.mode << 4)});
    const int err = Ioctl(fd, X4STEP_SET_CONFIG, &c);
    x4step_config got{};
    Ioctl(fd, X4STEP_GET_CONFIG, &got);
    Check(!err && !std::memcmp(&got, &c, sizeof c), "idle SET_CONFIG " + Str(c) + ": reads back");
    n++;
    phase = s.mode != X4STEP_MODE_CLOCK_DIR;
    sign = -sign;
    Check(Move(fd, sign, phase), "a move under " + Str(c));
    Check(Move(fd, -sign, phase), "and one back");
  }

  // While a move runs: EBUSY, nothing changed (the wiring is clock-dir, none inverted).
  x4step_endless e{2, 1, 1000, 20, 0, -1, {0, 0}};
  Mark({0x58, 0x4d});
  Ioctl(fd, X4STEP_MOVE_ENDLESS, &e);
  usleep(100000);
  for (uint32_t mode = 0; mode <= X4STEP_MODE_SMC_PHASE_HOLD; mode++) {
    x4step_config c{0xf, 0xf, 0, mode, {0, 0, 0, 0}};
    const int err = Ioctl(fd, X4STEP_SET_CONFIG, &c);
    x4step_config got{};
    Ioctl(fd, X4STEP_GET_CONFIG, &got);
    x4step_status st{};
    Ioctl(fd, X4STEP_GET_STATUS, &st);
    Check(
        err == EBUSY && got.clock_invert == 0 && got.dir_invert == 0 && got.output_mode == 0 &&
            (st.flags & X4STEP_ST_ACTIVE),
        "SET_CONFIG " + Str(c) + " while a move runs: EBUSY, unchanged, the move goes on (" + Str(got) + ")");
  }
  Ioctl(fd, X4STEP_BRAKE);
  WaitIdle(fd);
  std::printf("CONFIGS %d\n", n);
  close(fd);
  return guest::Finish("config_test");
}
