// SPDX-License-Identifier: LGPL-2.1-or-later
// The X4Step C API: a thin layer over the C++ API. Nothing is thrown
// across it: every exception becomes the documented error code.
#include <chrono>
#include <cstring>
#include <optional>
#include <vector>

#include "x4step.h"
#include "x4step.hpp"
#include "x4step_ext.h"

namespace {

// The one port of the C API, as in the DOS library.
std::optional<x4step::controller> port;
std::chrono::steady_clock::time_point timer_start = std::chrono::steady_clock::now();

template <typename F>
int guarded(F &&f) noexcept {
  try {
    f();
    return X4NoErr;
  } catch (const x4step::error &e) {
    if (e.code().category() == x4step::category()) return e.code().value();
    return X4ErrParamFail;  // the kernel refused in a way we did not foresee
  } catch (...) {
    return X4ErrParamFail;
  }
}

int with_port(void (*op)(x4step::controller &)) noexcept {
  if (!port) return X4ErrInitNotDone;
  return guarded([op] { op(*port); });
}

x4step::status status_or_idle() noexcept {
  if (port) {
    try {
      return port->get_status();
    } catch (...) {
    }
  }
  return {};
}

int move_endless(int axis, int freq, int ramp, x4step::direction dir) noexcept {
  if (!port) return X4ErrInitNotDone;
  return guarded([&] { port->move_endless(axis, dir, freq, std::chrono::milliseconds(ramp)); });
}

}  // namespace

extern "C" {

int X4Init(int lpt) {
  if (lpt < LPT1 || lpt > LPT4) return X4ErrParamFail;
  port.reset();
  X4ClearTimer();
  return guarded([lpt] { port.emplace(lpt); });
}

int X4ReInit(void) {
  if (!port) return X4ErrInitNotDone;
  port.reset();  // brakes running motors, waits, releases the port
  return X4NoErr;
}

int X4Load(long w1, long w2, long w3, long w4, int freq, int ramp) {
  if (!port) return X4ErrInitNotDone;
  return guarded([&] { port->load({{w1, w2, w3, w4}, freq, std::chrono::milliseconds(ramp)}); });
}

int X4Start(void) {
  return with_port([](x4step::controller &c) { c.start(); });
}

int X4Brake(void) {
  return with_port([](x4step::controller &c) { c.brake(); });
}

int X4Stop(void) {
  return with_port([](x4step::controller &c) { c.stop(); });
}

int X4GetState(void) { return status_or_idle().active ? 1 : 0; }

long X4GetSteps(int axis) {
  if (axis < 1 || axis > 4) return 0;
  return static_cast<long>(status_or_idle().steps[axis - 1]);
}

int X4MovePos(int axis, int freq, int ramp) {
  return move_endless(axis, freq, ramp, x4step::direction::positive);
}

int X4MoveNeg(int axis, int freq, int ramp) {
  return move_endless(axis, freq, ramp, x4step::direction::negative);
}

int X4BrakeCodes(char *codes) {
  if (!port) return X4ErrInitNotDone;
  if (!codes) return X4ErrParamFail;
  std::vector<int> list;
  for (const char *c = codes; *c; c++) list.push_back(static_cast<unsigned char>(*c));
  return guarded([&] { port->set_brake_codes(list); });
}

int X4LastBrakeCode(void) { return status_or_idle().last_brake_code; }

void X4ClearTimer(void) { timer_start = std::chrono::steady_clock::now(); }

long X4GetTimer(void) {
  return static_cast<long>(
      std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - timer_start)
          .count());
}

int X4GetIn(void) { return static_cast<int>(status_or_idle().inputs); }

int X4SetOut(int sig) {
  if (!port) return X4ErrInitNotDone;
  if (sig < SIGNAL1ON || sig > SIGNAL2OFF) return X4ErrParamFail;
  const auto which = sig <= SIGNAL1OFF ? x4step::signal::one : x4step::signal::two;
  const bool high = sig == SIGNAL1ON || sig == SIGNAL2ON;
  return guarded([&] { port->set_output(which, high); });
}

int X4SetStepTiming(long pulse_ns, long space_ns, long dir_setup_ns, long dir_hold_ns) {
  if (!port) return X4ErrInitNotDone;
  using std::chrono::nanoseconds;
  return guarded([&] {
    port->set_step_timing(
        {nanoseconds(pulse_ns), nanoseconds(space_ns), nanoseconds(dir_setup_ns), nanoseconds(dir_hold_ns)});
  });
}

int X4SetOutputMode(int mode) {
  if (!port) return X4ErrInitNotDone;
  if (mode < X4MODE_CLOCK_DIR || mode > X4MODE_SMC_PHASE_HOLD) return X4ErrParamFail;
  return guarded([&] {
    x4step::config c = port->get_config();
    c.mode = static_cast<x4step::output_mode>(mode);
    port->set_config(c);
  });
}

}  // extern "C"
