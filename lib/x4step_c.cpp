// SPDX-License-Identifier: LGPL-2.1-or-later
// The X4Step C API: a thin layer over the C++ API. Nothing is thrown
// across it: every exception becomes the documented error code.
#include <linux/x4step.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <new>
#include <optional>
#include <vector>

extern "C" {
#include "x4_check.h"  // the kernel's own timing check
}
#include "detail.hpp"
#include "sim/options.hpp"
#include "x4step.h"
#include "x4step.hpp"
#include "x4step_ext.h"
#include "x4step_path.hpp"

static_assert(X4HOME_PHASE1 == X4STEP_HOME_PHASE1 && X4HOME_PHASE2 == X4STEP_HOME_PHASE2 &&
              X4HOME_BRAKE == X4STEP_HOME_BRAKE && X4AXERR_REF_PASSED == X4STEP_AXERR_REF_PASSED);
static_assert(X4AX_RUN == X4STEP_AX_RUN && X4AX_SYNC == X4STEP_AX_SYNC && X4AX_ERROR == X4STEP_AX_ERROR &&
              X4AX_REF1 == X4STEP_AX_REF1 && X4AX_REF2 == X4STEP_AX_REF2 && X4AX_ACCEL == X4STEP_AX_ACCEL &&
              X4AX_CRUISE == X4STEP_AX_CRUISE && X4AX_DECEL == X4STEP_AX_DECEL);
static_assert(X4AXERR_REF_TRAVEL == X4STEP_AXERR_REF_TRAVEL && X4AXERR_LIMIT_POS == X4STEP_AXERR_LIMIT_POS &&
              X4AXERR_LIMIT_NEG == X4STEP_AXERR_LIMIT_NEG && X4AXERR_AMBIGUOUS == X4STEP_AXERR_AMBIGUOUS);

namespace {

// The one port of the C API, as in the DOS library.
std::optional<x4step::controller> port;
std::chrono::steady_clock::time_point timer_start = std::chrono::steady_clock::now();

// A failure the manual has no code for: errno says what it was (x4step.h).
int unforeseen(int err) noexcept {
  errno = err;
  switch (err) {
    case EACCES:
    case EPERM:
    case EIO:
    case ENODEV:
    case ENXIO:
    case EBADF:
    case ENOTTY:
      return X4ErrLPTNotFound;  // the port cannot be used
    default:
      return X4ErrParamFail;
  }
}

template <typename F>
int guarded(F &&f) noexcept {
  try {
    f();
    return X4NoErr;
  } catch (const x4step::error &e) {
    if (e.code().category() == x4step::category()) return e.code().value();
    return unforeseen(e.code().value());
  } catch (const std::bad_alloc &) {
    return unforeseen(ENOMEM);
  } catch (...) {
    return unforeseen(EINVAL);
  }
}

[[noreturn]] void fail(x4step::errc e) { throw x4step::error(x4step::make_error_code(e)); }

// The manual's functions run one move at a time (X4ErrIsActive, manual
// 4.1); concurrent moves are the positioning extension's.
void refuse_while_active(const x4step::status &s) {
  if (s.active) fail(x4step::errc::is_active);
}

// The default step timing of the module (its parameters), else X4Step's
// where they fail the engine's check: the module ignored them then too. A
// simulated port has the module's built-in defaults: a loaded module's
// parameters are none of its business.
x4step::step_timing module_step_timing(bool simulated) {
  x4_timing k{0, 0, X4_DIR_SETUP_NS, 0};
  if (simulated) return {};
  const auto param = [](const char *name, uint32_t &out) {
    std::ifstream f(std::string("/sys/module/x4step/parameters/") + name);
    uint32_t ns;
    if (f >> ns) out = ns;
  };
  param("pulse_ns", k.pulse_ns);
  param("space_ns", k.space_ns);
  param("dir_setup_ns", k.dir_setup_ns);
  param("dir_hold_ns", k.dir_hold_ns);
  if (x4_timing_check(&k, X4_MODE_CLOCK_DIR)) return {};
  using std::chrono::nanoseconds;
  return x4step::step_timing()
      .pulse(nanoseconds(k.pulse_ns))
      .space(nanoseconds(k.space_ns))
      .dir_setup(nanoseconds(k.dir_setup_ns))
      .dir_hold(nanoseconds(k.dir_hold_ns));
}

// X4Init starts from the DOS library's state, whatever an earlier
// controller (x4ctl, a C++ program) left configured: clock and direction
// outputs without inversions, the module's default step timing, only ESC
// brakes, no switches, the default profiles.
void dos_state(x4step::controller &c) {
  c.set_config({});
  c.set_step_timing(module_step_timing(x4step::sim::is_sim_name(c.path())));
  c.set_brake_codes({});
  c.set_switches({});
  for (x4step::axis a : x4step::axis_set::all()) c.set_profile(a, {});
}

// X4Init found no port: the manual's program learns only X4ErrLPTNotFound,
// so what to fix (load the module, join group lp, the simulator's setting
// it refused) goes to stderr, once, without the code's general "is x4step
// loaded" where the error says more.
void tell_init_failure(int lpt, const x4step::error &e) noexcept {
  // Once per program: one that tries LPT1..4 in turn, or again and
  // again, gets the reason once, not a line per call.
  static std::atomic<bool> told{false};
  if (e.code() != x4step::errc::lpt_not_found || told.exchange(true)) return;
  try {
    std::string text = e.what();
    const std::string general = ": " + e.code().message();
    if (text.size() > general.size() &&
        text.compare(text.size() - general.size(), general.size(), general) == 0)
      text.resize(text.size() - general.size());
    const std::string node = x4step::device_path(lpt);
    const bool general_only = text == node || text == e.code().message();
    if (general_only && ::access(node.c_str(), F_OK) != 0)
      text = node +
             ": no such device: load the x4step module (sudo modprobe x4step), or set X4STEP_SIM=1 "
             "for the simulated port";
    std::fprintf(stderr, "libx4step: X4Init(LPT%d): %s\n", lpt, text.c_str());
  } catch (...) {
    std::fprintf(stderr, "libx4step: X4Init(LPT%d): %s\n", lpt, e.what());
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

// A value for an unsigned field; out of its range: param_fail.
unsigned to_unsigned(long v) {
  if (v < 0 || static_cast<unsigned long>(v) > UINT_MAX)
    throw x4step::error(x4step::make_error_code(x4step::errc::param_fail));
  return static_cast<unsigned>(v);
}

// A speed for an int field; beyond int, a value the library also refuses.
int to_speed(long v) { return static_cast<int>(std::clamp<long>(v, INT_MIN, INT_MAX)); }

int state_bits(const x4step::axis_status &a) {
  return (a.running ? X4AX_RUN : 0) | (a.synced ? X4AX_SYNC : 0) | (a.error ? X4AX_ERROR : 0) |
         (a.ref1 ? X4AX_REF1 : 0) | (a.ref2 ? X4AX_REF2 : 0) | (a.accelerating ? X4AX_ACCEL : 0) |
         (a.cruising ? X4AX_CRUISE : 0) | (a.decelerating ? X4AX_DECEL : 0);
}

// The axis' own status, or param_fail for a bad axis.
int axis_state(int axis, x4step::axis_status &out) noexcept {
  if (!port) return X4ErrInitNotDone;
  return guarded([&] { out = port->get_axis(x4step::axis(axis)); });
}

int halt_axis(int axis, x4step::halt_mode how) noexcept {
  if (!port) return X4ErrInitNotDone;
  return guarded([&] { port->halt(x4step::axis(axis), how); });
}

int move_endless(int axis, int freq, int ramp, x4step::direction dir) noexcept {
  if (!port) return X4ErrInitNotDone;
  if (!x4step::axis::valid(axis)) return X4ErrParamFail;
  const std::chrono::milliseconds r(ramp);
  if (const x4step::errc e = x4step::check_endless(freq, r); e != x4step::errc::ok)
    return static_cast<int>(e);
  return guarded([&] {
    const x4step::status s = port->get_status();
    if (s.loaded) fail(x4step::errc::is_loaded);
    refuse_while_active(s);
    port->move_endless(x4step::axis(axis), dir, freq, r);
  });
}

}  // namespace

extern "C" {

int X4Init(int lpt) {
  if (lpt < LPT1 || lpt > LPT4) return X4ErrParamFail;
  port.reset();
  X4ClearTimer();
  const int ret = guarded([lpt] {
    try {
      port.emplace(lpt);
    } catch (const x4step::error &e) {
      tell_init_failure(lpt, e);
      throw;
    }
    dos_state(*port);
  });
  if (ret != X4NoErr) port.reset();
  return ret;
}

int X4ReInit(void) {
  if (!port) return X4ErrInitNotDone;
  port.reset();  // brakes running motors, waits until they stand (no limit), releases the port
  return X4NoErr;
}

int X4Load(long w1, long w2, long w3, long w4, int freq, int ramp) {
  if (!port) return X4ErrInitNotDone;
  return guarded([&] { port->load({{w1, w2, w3, w4}, freq, std::chrono::milliseconds(ramp)}); });
}

int X4Start(void) {
  return with_port([](x4step::controller &c) {
    const x4step::status s = c.get_status();
    if (!s.loaded) fail(x4step::errc::not_loaded);
    refuse_while_active(s);
    c.start();
  });
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

// The timer runs on the port's clock: a simulated port's in virtual time.
static std::chrono::steady_clock::time_point timer_now() noexcept {
  if (!port) return std::chrono::steady_clock::now();
  x4step::detail::port_io &io = x4step::detail::access::io(*port);
  io.let_time_pass();
  return io.now();
}

void X4ClearTimer(void) { timer_start = timer_now(); }

long X4GetTimer(void) {
  return static_cast<long>(
      std::chrono::duration_cast<std::chrono::milliseconds>(timer_now() - timer_start).count());
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
    port->set_step_timing(x4step::step_timing()
                              .pulse(nanoseconds(pulse_ns))
                              .space(nanoseconds(space_ns))
                              .dir_setup(nanoseconds(dir_setup_ns))
                              .dir_hold(nanoseconds(dir_hold_ns)));
  });
}

int X4SetOutputMode(int mode) {
  if (!port) return X4ErrInitNotDone;
  if (mode < X4MODE_CLOCK_DIR || mode > X4MODE_SMC_PHASE_HOLD) return X4ErrParamFail;
  return guarded([&] { port->set_config(port->get_config().mode(static_cast<x4step::output_mode>(mode))); });
}

int X4SetProfile(int axis, long v0, long ve, long vm, long a0, long ae) {
  if (!port) return X4ErrInitNotDone;
  return guarded([&] {
    port->set_profile(x4step::axis(axis), x4step::profile()
                                              .start_speed(to_unsigned(v0))
                                              .end_speed(to_unsigned(ve))
                                              .top_speed(to_unsigned(vm))
                                              .accel(to_unsigned(a0))
                                              .decel(to_unsigned(ae)));
  });
}

int X4MoveTo(int axis, long target) {
  if (!port) return X4ErrInitNotDone;
  return guarded([&] { port->move_to(x4step::axis(axis), target); });
}

int X4MoveBy(int axis, long distance) {
  if (!port) return X4ErrInitNotDone;
  return guarded([&] { port->move_by(x4step::axis(axis), distance); });
}

int X4Home(int axis, long vref1, long vref2, long sref, int phases) {
  if (!port) return X4ErrInitNotDone;
  if (phases & ~(X4HOME_AUTO | X4HOME_BRAKE)) return X4ErrParamFail;
  const auto h = x4step::homing()  // the library checks the rest
                     .phase1_speed(to_speed(vref1))
                     .phase2_speed(to_speed(vref2))
                     .max_travel(static_cast<unsigned long>(std::max(0L, sref)))
                     .phase1(phases & X4HOME_PHASE1)
                     .phase2(phases & X4HOME_PHASE2)
                     .brake(phases & X4HOME_BRAKE);
  return guarded([&] { port->home(x4step::axis(axis), h); });
}

int X4SetPosition(int axis, long position) {
  if (!port) return X4ErrInitNotDone;
  return guarded([&] { port->set_position(x4step::axis(axis), position); });
}

int X4GetPosition(int axis, long *position) {
  x4step::axis_status a;
  if (const int e = axis_state(axis, a); e != X4NoErr) return e;
  if (!position) return X4ErrParamFail;
  *position = a.position;
  return X4NoErr;
}

int X4GetAxisState(int axis, int *state, int *error) {
  x4step::axis_status a;
  if (const int e = axis_state(axis, a); e != X4NoErr) return e;
  if (state) *state = state_bits(a);
  if (error) *error = static_cast<int>(a.error);
  return X4NoErr;
}

int X4SetSwitches(int axis, int ref_input, int plus_input, int minus_input) {
  if (!port) return X4ErrInitNotDone;
  if (!x4step::axis::valid(axis)) return X4ErrParamFail;
  return guarded([&] {
    x4step::switches s = port->get_switches();
    s.ref[axis - 1] = ref_input;
    s.plus[axis - 1] = plus_input;
    s.minus[axis - 1] = minus_input;
    port->set_switches(s);
  });
}

int X4SetSwitchPolarity(int nc_mask) {
  if (!port) return X4ErrInitNotDone;
  return guarded([&] {
    x4step::switches s = port->get_switches();
    s.nc = static_cast<unsigned>(nc_mask);  // a negative one is out of range too
    port->set_switches(s);
  });
}

int X4BrakeAxis(int axis) { return halt_axis(axis, x4step::halt_mode::brake); }

int X4StopAxis(int axis) { return halt_axis(axis, x4step::halt_mode::stop); }

// An X4Segment as the library's segment (param_fail: a value above 32 bits).
static x4step::segment to_segment(const X4Segment &s) {
  if (s.length > UINT32_MAX || s.top_speed > UINT32_MAX || s.entry_speed > UINT32_MAX || s.accel > UINT32_MAX)
    fail(x4step::errc::param_fail);
  x4step::segment g;
  for (x4step::axis a : x4step::axis_set::all()) g.steps(a, s.steps[a.index()]);
  return g.length(static_cast<std::uint32_t>(s.length))
      .top_speed(static_cast<std::uint32_t>(s.top_speed))
      .entry_speed(static_cast<std::uint32_t>(s.entry_speed))
      .accel(static_cast<std::uint32_t>(s.accel))
      .tag(s.tag);
}

int X4PathAppend(const X4Segment *segments, int count) {
  if (!port) return X4ErrInitNotDone;
  if (count < 0 || (count && !segments)) return X4ErrParamFail;
  return guarded([&] {
    std::vector<x4step::segment> v;
    for (const X4Segment &s : std::vector<X4Segment>(segments, segments + count)) v.push_back(to_segment(s));
    x4step::path(*port).append(v);
  });
}

int X4PathProbeInput(int input, int active_low) {
  if (!port) return X4ErrInitNotDone;
  if (input < 0 || input > 5) return X4ErrParamFail;
  return guarded([&] {
    x4step::path p(*port);
    p.configure(p.config().depth(0).probe_input(static_cast<unsigned>(input), active_low != 0));
  });
}

int X4PathAppendProbe(const X4Segment *segment, int mode) {
  if (!port) return X4ErrInitNotDone;
  if (!segment || (mode != X4PROBE_TOWARD && mode != X4PROBE_AWAY)) return X4ErrParamFail;
  return guarded([&] {
    x4step::path(*port).append(to_segment(*segment).probe(mode == X4PROBE_TOWARD ? x4step::probe_mode::toward
                                                                                 : x4step::probe_mode::away));
  });
}

int X4PathProbe(int *tripped, long *position, unsigned long long *tag) {
  if (!port) return X4ErrInitNotDone;
  return guarded([&] {
    const x4step::probe_latch l = x4step::path(*port).probe();
    if (tripped) *tripped = l.tripped;
    if (position)
      for (std::size_t i = 0; i < l.steps.size(); i++) position[i] = l.steps[i];
    if (tag) *tag = l.tag;
  });
}

int X4PathHold(void) {
  return with_port([](x4step::controller &c) { x4step::path(c).hold(); });
}

int X4PathResume(void) {
  return with_port([](x4step::controller &c) { x4step::path(c).resume(); });
}

int X4PathAbort(void) {
  return with_port([](x4step::controller &c) { x4step::path(c).abort(); });
}

int X4PathClear(void) {
  return with_port([](x4step::controller &c) { x4step::path(c).clear(); });
}

int X4PathOverride(int percent) {
  if (!port) return X4ErrInitNotDone;
  if (percent < 1 || percent > 200) return X4ErrParamFail;
  return guarded([&] { x4step::path(*port).set_override(static_cast<unsigned>(percent)); });
}

int X4PathState(int *state, long *queued, unsigned long long *tag) {
  if (!port) return X4ErrInitNotDone;
  return guarded([&] {
    const x4step::path_status s = x4step::path(*port).status();
    if (state) *state = static_cast<int>(s.state);
    if (queued) *queued = static_cast<long>(s.queued);
    if (tag) *tag = s.tag;
  });
}

}  // extern "C"
