// SPDX-License-Identifier: GPL-2.0
// The guest tests' keyboard: a uinput device that types key events into the
// real input core, where x4step's brake key handler listens to every
// keyboard (keys_test, events_test, path_test). Optionally its own evdev
// node, read as an application would (the swallow checks of keys_test).
#pragma once

#include <dirent.h>
#include <fcntl.h>
#include <linux/uinput.h>
#include <sys/ioctl.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>

namespace guest {

class Keyboard {
 public:
  // Keys 1..127 (ESC and every set-1 make code), named `name`.
  explicit Keyboard(const char *name = "x4step test keyboard")
      : fd_(open("/dev/uinput", O_WRONLY | O_NONBLOCK | O_CLOEXEC)), name_(name) {
    ioctl(fd_, UI_SET_EVBIT, EV_KEY);
    for (int k = 1; k < 128; k++) ioctl(fd_, UI_SET_KEYBIT, k);
    uinput_setup setup{};
    setup.id.bustype = BUS_VIRTUAL;
    std::snprintf(setup.name, sizeof setup.name, "%s", name);
    ioctl(fd_, UI_DEV_SETUP, &setup);
    ioctl(fd_, UI_DEV_CREATE);
    usleep(200000);  // let the handlers connect
  }
  ~Keyboard() {
    if (evdev_ >= 0) close(evdev_);
    ioctl(fd_, UI_DEV_DESTROY);
    close(fd_);
  }
  Keyboard(const Keyboard &) = delete;
  Keyboard &operator=(const Keyboard &) = delete;

  bool ok() const { return fd_ >= 0; }

  // value: 1 press, 0 release, 2 auto-repeat. Returns the CLOCK_MONOTONIC
  // time (ns) just before the write.
  uint64_t Key(int code, int value) {
    input_event ev[2] = {};
    ev[0].type = EV_KEY;
    ev[0].code = static_cast<uint16_t>(code);
    ev[0].value = value;
    ev[1].type = EV_SYN;
    ev[1].code = SYN_REPORT;
    timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    const uint64_t t = uint64_t(ts.tv_sec) * 1000000000u + uint64_t(ts.tv_nsec);
    if (write(fd_, ev, sizeof ev) != sizeof ev) std::perror("uinput write");
    return t;
  }
  // A press and its release.
  void Tap(int code) {
    Key(code, 1);
    Key(code, 0);
  }

  // The keyboard's own /dev/input/eventN, read as an application would.
  // Returns its descriptor, -1 if not found.
  int OpenEvdev() {
    DIR *d = opendir("/dev/input");
    for (dirent *e; d && (e = readdir(d));) {
      if (std::strncmp(e->d_name, "event", 5)) continue;
      const std::string path = std::string("/dev/input/") + e->d_name;
      const int fd = open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
      char name[UINPUT_MAX_NAME_SIZE] = {};
      if (fd >= 0 && ioctl(fd, EVIOCGNAME(sizeof name - 1), name) >= 0 && name_ == name) {
        evdev_ = fd;
        break;
      }
      if (fd >= 0) close(fd);
    }
    if (d) closedir(d);
    return evdev_;
  }
  // What the evdev reader got since the last call: "+" press, "-" release,
  // "r" repeat of `key`, in order (the other keys are ignored).
  std::string Seen(int key) {
    std::string seen;
    input_event ev[64];
    ssize_t n;
    while ((n = read(evdev_, ev, sizeof ev)) > 0)
      for (ssize_t i = 0; i < n / ssize_t(sizeof ev[0]); i++)
        if (ev[i].type == EV_KEY && ev[i].code == key) seen += "-+r"[std::min(ev[i].value, 2)];
    return seen;
  }
  // EVIOCGRAB of the evdev reader.
  bool Grab(bool on) { return ioctl(evdev_, EVIOCGRAB, on ? 1 : 0) == 0; }

 private:
  int fd_;
  std::string name_;
  int evdev_ = -1;
};

}  // namespace guest
