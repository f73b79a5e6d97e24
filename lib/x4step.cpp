// SPDX-License-Identifier: LGPL-2.1-or-later
// libx4step C++ API over the x4step kernel module's ioctl interface.
#include "x4step.hpp"

#include <fcntl.h>
#include <linux/x4step.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <fstream>
#include <ostream>
#include <thread>
#include <utility>

#include "detail.hpp"

extern "C" {
#include "x4_check.h"  // the kernel's own argument checks
}
#include "x4step_access.hpp"

namespace x4step {

static_assert(axes == X4STEP_AXES);
static_assert(freq_min_hz == X4_FREQ_MIN_HZ && freq_max_hz == X4_FREQ_MAX_HZ &&
              ramp_max.count() == X4_RAMP_MAX_MS);
static_assert(timing_max.count() == X4_TIMING_MAX_NS && pulse_min.count() == X4_PULSE_MIN_NS);
static_assert(vel_max == X4STEP_VEL_MAX && acc_max == X4STEP_ACC_MAX);
static_assert(vel_max == X4_VEL_MAX && acc_max == X4_ACC_MAX);
static_assert(axis_error::ref_travel == X4STEP_AXERR_REF_TRAVEL &&
              axis_error::limit_pos == X4STEP_AXERR_LIMIT_POS &&
              axis_error::limit_neg == X4STEP_AXERR_LIMIT_NEG &&
              axis_error::ambiguous == X4STEP_AXERR_AMBIGUOUS &&
              axis_error::ref_passed == X4STEP_AXERR_REF_PASSED);

namespace {

constexpr int inputs_count = 5;

class category_impl : public std::error_category {
 public:
  const char *name() const noexcept override { return "x4step"; }
  std::string message(int ev) const override {
    switch (static_cast<errc>(ev)) {
      case errc::ok:
        return "no error";
      case errc::no_steps:
        return "no steps: give at least one axis a non-zero path";
      case errc::freq_too_high:
        return "frequency too high: use at most " + std::to_string(freq_max_hz) + " Hz";
      case errc::freq_too_low:
        return "frequency too low: use at least " + std::to_string(freq_min_hz) + " Hz";
      case errc::ramp_too_high:
        return "ramp too long: use at most " + std::to_string(ramp_max.count()) + " ms";
      case errc::ramp_freq:
        return "ramp too long for the frequency: ramp (ms) must not exceed frequency (Hz)";
      case errc::lpt_not_found:
        return "port not found: is x4step loaded, the port present and not in use?";
      case errc::not_active:
        return "no move is running";
      case errc::param_fail:
        return "parameter out of range";
      case errc::init_not_done:
        return "no port opened: call X4Init first";
      case errc::is_active:
        return "a move is running: wait for it to end or brake it";
      case errc::not_loaded:
        return "nothing loaded: load a move first";
      case errc::is_loaded:
        return "a move is loaded already: start it first";
      case errc::steps_too_high:
        return "path too long: at most 16777216 steps per axis";
    }
    return "unknown x4step error " + std::to_string(ev);
  }
};

}  // namespace

namespace detail {

void fail(errc e) { throw error(make_error_code(e)); }

void fail_errno(int err, const std::string &what) {
  throw error(std::error_code(err, std::system_category()), what);
}

// The module's errnos for the X4Step state errors (see linux/x4step.h).
void fail_ioctl(int err, const char *what, int result) {
  switch (err) {
    case EINVAL:
      if (result > 0 && result <= static_cast<int>(errc::steps_too_high)) fail(static_cast<errc>(result));
      fail(errc::param_fail);
    case EBUSY:
      fail(errc::is_active);
    case EEXIST:
      fail(errc::is_loaded);
    case ENODATA:
      fail(errc::not_loaded);
    case ESRCH:
      fail(errc::not_active);
    case ERANGE:  // each move alone is fine: together they are too fast
      throw error(make_error_code(errc::freq_too_high),
                  std::string(what) +
                      ": the moves of the port together would need more port writes per second than its "
                      "budget (module parameter write_budget): wait for a move to end, or run slower");
    case ENODEV:
    case ENXIO:
      fail(errc::lpt_not_found);
    default:
      fail_errno(err, what);
  }
}

}  // namespace detail

namespace {

using detail::deadline;
using detail::fail;
using detail::fail_errno;
using detail::fail_ioctl;
using detail::narrow_steps;

void need_axes(axis_set s) {
  if (s.empty()) fail(errc::param_fail);
}

// The axes of a mask from the kernel (bits beyond axis 4 name none).
axis_set axes_of(uint32_t mask) { return axis_set(mask & axis_set::all().mask()); }

// One open port; the common part of controller and monitor.
struct device {
  std::unique_ptr<detail::port_io> io;
  std::string path;

  device(const std::string &p, int flags) : io(detail::open_port(p, flags)), path(p) {}

  void call(unsigned long cmd, void *arg, const char *what) const {
    if (io->ioctl(cmd, arg)) fail_ioctl(errno, what);
  }

  status get_status() const {
    x4step_status st{};
    call(X4STEP_GET_STATUS, &st, "X4STEP_GET_STATUS");
    status s;
    s.active = st.flags & X4STEP_ST_ACTIVE;
    s.loaded = st.flags & X4STEP_ST_LOADED;
    s.controlled = st.flags & X4STEP_ST_CONTROLLED;
    std::copy(std::begin(st.steps), std::end(st.steps), s.steps.begin());
    s.inputs = st.inputs;
    s.inputs_stale = st.flags & X4STEP_ST_INPUTS_STALE;
    s.inputs_time =
        std::chrono::steady_clock::time_point(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
            std::chrono::nanoseconds(st.inputs_time_ns)));
    s.outputs = st.outputs;
    s.data = st.data;
    s.last_brake_code = static_cast<int>(st.last_brake_code);
    s.moves_ended = st.moves_ended;
    return s;
  }

  // One poll() for POLLIN (no move runs) of up to ms (-1: for ever);
  // false on timeout or signal.
  bool poll_in(int ms) const {
    short revents = 0;
    const int n = io->poll(POLLIN, ms, &revents);
    if (n < 0 && errno == EINTR) return false;
    if (n < 0) fail_errno(errno, "poll " + path);
    if (n > 0 && (revents & (POLLERR | POLLHUP))) fail(errc::lpt_not_found);
    return n > 0;
  }

  bool wait(std::chrono::milliseconds timeout) const {
    const deadline d(timeout, *io);
    for (;;) {
      if (poll_in(d.poll_ms())) return true;
      if (d.expired()) return false;
    }
  }

  axes_status get_axes() const {
    x4step_axes ka{};
    call(X4STEP_GET_AXES, &ka, "X4STEP_GET_AXES");
    axes_status s;
    for (int i = 0; i < axes; i++) {
      const x4step_axis &k = ka.axis[i];
      axis_status &a = s.axis[i];
      a.position = k.position;
      a.velocity = k.velocity;
      a.error = k.error;
      a.running = k.state & X4STEP_AX_RUN;
      a.synced = k.state & X4STEP_AX_SYNC;
      a.ref1 = k.state & X4STEP_AX_REF1;
      a.ref2 = k.state & X4STEP_AX_REF2;
      a.accelerating = k.state & X4STEP_AX_ACCEL;
      a.cruising = k.state & X4STEP_AX_CRUISE;
      a.decelerating = k.state & X4STEP_AX_DECEL;
    }
    s.inputs = ka.inputs;
    s.switches_active = ka.switches;
    s.inputs_stale = ka.flags & X4STEP_ST_INPUTS_STALE;
    return s;
  }

  // Events are POLLPRI (POLLIN means idle): poll, then read one.
  std::optional<event> read_event(std::chrono::milliseconds timeout) const {
    const deadline d(timeout, *io);
    for (;;) {
      short revents = 0;
      const int n = io->poll(POLLPRI, d.poll_ms(), &revents);
      if (n < 0 && errno == EINTR) return std::nullopt;
      if (n < 0) fail_errno(errno, "poll " + path);
      if (n > 0 && (revents & POLLPRI)) {
        x4step_event k{};
        const ssize_t got = io->read(&k, sizeof k);
        if (got == static_cast<ssize_t>(sizeof k)) return to_event(k);
        if (got < 0 && errno == ENODEV) fail(errc::lpt_not_found);
        if (got < 0 && errno != EAGAIN && errno != EINTR) fail_errno(errno, "read " + path);
        continue;  // a dup of the descriptor read it
      }
      if (n > 0 && (revents & (POLLERR | POLLHUP))) fail(errc::lpt_not_found);
      if (d.expired()) return std::nullopt;
    }
  }

  static event to_event(const x4step_event &k) {
    event e;
    e.seq = k.seq;
    e.time =
        std::chrono::steady_clock::time_point(std::chrono::duration_cast<std::chrono::steady_clock::duration>(
            std::chrono::nanoseconds(k.timestamp_ns)));
    e.type = static_cast<event_type>(k.type);
    e.axes = axes_of(k.axes);
    e.how = k.how;
    e.value = k.value;
    e.ambiguous = k.flags & X4STEP_EVF_AMBIGUOUS;
    std::copy(std::begin(k.position), std::end(k.position), e.position.begin());
    return e;
  }

  // poll() reports POLLIN only while no move at all runs; the end of any
  // move wakes the pollers, but the kernel puts them back to sleep while
  // another move still runs. So this looks at the axes themselves and
  // polls in slices of at most 5 ms: it returns at once when everything
  // ends, and within 5 ms when only the axes waited for end.
  bool wait_axes(axis_set which, std::chrono::milliseconds timeout) const {
    need_axes(which);
    const deadline d(timeout, *io);
    for (;;) {
      const axes_status s = get_axes();
      bool runs = false;
      for (axis a : which) runs |= s[a].running;
      if (!runs) return true;
      if (d.expired()) return false;
      poll_in(d.poll_ms(5));
    }
  }
};

// A coordinate or distance: signed 32 bits.
int32_t narrow_s32(long v) {
  if (v < INT32_MIN || v > INT32_MAX) fail(errc::param_fail);
  return static_cast<int32_t>(v);
}

// The targets of a move of one axis only.
std::array<long, axes> one_axis(axis a, long value) {
  std::array<long, axes> t{};
  t[a.index()] = value;
  return t;
}

uint8_t narrow_input(int in) {
  if (in < 0 || in > inputs_count) fail(errc::param_fail);
  return static_cast<uint8_t>(in);
}

}  // namespace

const std::error_category &category() noexcept {
  static const category_impl instance;
  return instance;
}

std::error_code make_error_code(errc e) noexcept { return {static_cast<int>(e), category()}; }

errc check(const move &m) noexcept {
  x4_move km{};
  for (int i = 0; i < axes; i++) km.steps[i] = narrow_steps(m.steps[i]);
  km.freq_hz = m.freq_hz;
  km.ramp_ms = static_cast<int32_t>(std::clamp<long long>(m.ramp.count(), -1, ramp_max.count() + 1));
  return static_cast<errc>(x4_move_check(&km));
}

errc check_endless(int freq_hz, std::chrono::milliseconds ramp) noexcept {
  return static_cast<errc>(x4_ramp_check(
      freq_hz, static_cast<int32_t>(std::clamp<long long>(ramp.count(), -1, ramp_max.count() + 1))));
}

const char *version() noexcept { return X4STEP_LIB_VERSION; }

std::string device_path(int lpt) {
  if (lpt < 1 || lpt > 4) fail(errc::param_fail);
  return "/dev/x4step" + std::to_string(lpt - 1);
}

errc check(const profile &p) noexcept {
  const x4_profile kp{p.start_speed(), p.end_speed(), p.top_speed(), p.accel(), p.decel()};
  return static_cast<errc>(x4_profile_check(&kp));
}

errc check(const homing &h) noexcept {
  const uint8_t phases =
      (h.phase1() ? X4_HOME_PHASE1 : 0) | (h.phase2() ? X4_HOME_PHASE2 : 0) | (h.brake() ? X4_HOME_BRAKE : 0);
  // Above 32 bits sref is refused as 2^31 is.
  const uint32_t sref = h.max_travel() > INT32_MAX ? 0x80000000u : static_cast<uint32_t>(h.max_travel());
  return static_cast<errc>(x4_home_check(phases, h.phase1_speed(), h.phase2_speed(), sref));
}

std::ostream &operator<<(std::ostream &os, const axes_status &s) {
  for (int i = 0; i < axes; i++) {
    const axis_status &a = s.axis[i];
    os << (i ? " | " : "") << i + 1 << ": " << a.position << (a.synced ? " synced" : "");
    if (a.running) os << " running " << a.velocity << "/s";
    if (a.ref1) os << " ref1";
    if (a.ref2) os << " ref2";
    if (a.accelerating) os << " accel";
    if (a.cruising) os << " cruise";
    if (a.decelerating) os << " decel";
    if (a.error) os << " error 0x" << std::hex << a.error << std::dec;
  }
  return os << " | inputs 0x" << std::hex << s.inputs << " switches 0x" << s.switches_active << std::dec
            << (s.inputs_stale ? " (stale)" : "");
}

namespace {

const char *event_how(const event &e) {
  static const char *const kinds[] = {"X4Step move", "endless move", "goto", "reference run"};
  static const char *const ends[] = {"completed",
                                     "braked",
                                     "stopped",
                                     "at a limit",
                                     "homed",
                                     "REF found",
                                     "reference travel exceeded",
                                     "braked off the reference switch"};
  static const char *const sources[] = {"by request", "by key", "by the controller's close",
                                        "by an emergency halt"};
  static const char *const switches[] = {"E+", "E-", "REF", "probe"};
  static const char *const changes[] = {"opened", "closed", "released the port"};
  const unsigned h = e.how - 1;
  switch (e.type) {
    case event_type::move_started:
      return h < 4 ? kinds[h] : "";
    case event_type::move_ended:
      return h < 8 ? ends[h] : "";
    case event_type::brake:
      return h < 4 ? sources[h] : "";
    case event_type::switch_hit:
      return h < 4 ? switches[h] : "";
    case event_type::controller:
      return h < 3 ? changes[h] : "";
    default:
      return "";
  }
}

}  // namespace

std::ostream &operator<<(std::ostream &os, const event &e) {
  static const char *const names[] = {"move started", "move ended", "brake",
                                      "switch",       "controller", "port gone"};
  const unsigned t = static_cast<unsigned>(e.type) - 1;
  os << '#' << e.seq << ' ';
  if (t < 6)
    os << names[t];
  else
    os << "event type " << static_cast<unsigned>(e.type);
  if (!e.axes.empty()) {
    os << ": axes";
    for (axis a : e.axes) os << ' ' << a.number();
  }
  const char *how = event_how(e);
  if (*how) os << (e.axes.empty() ? ": " : ", ") << how;
  if (e.type == event_type::brake && e.how == static_cast<unsigned>(brake_source::key)) os << ' ' << e.value;
  if (e.type == event_type::switch_hit) os << " on input " << e.value << (e.ambiguous ? " (ambiguous)" : "");
  os << ", at";
  for (long p : e.position) os << ' ' << p;
  return os;
}

std::ostream &operator<<(std::ostream &os, const status &s) {
  os << (s.active ? "active" : "idle") << (s.loaded ? " loaded" : "") << " steps";
  for (long long v : s.steps) os << ' ' << v;
  return os << " inputs 0x" << std::hex << s.inputs << (s.inputs_stale ? " (stale)" : "") << " outputs 0x"
            << s.outputs << std::dec << " brake-code " << s.last_brake_code;
}

// ---- controller -------------------------------------------------------------

struct controller::impl : device {
  using device::device;
};

controller::controller(int lpt) : controller(detail::port_name(lpt)) {}
controller::controller(const std::filesystem::path &path)
    : impl_(std::make_unique<impl>(path.string(), O_RDWR)) {}
controller::controller(controller &&other) noexcept = default;
controller &controller::operator=(controller &&other) noexcept {
  if (this != &other) {
    close();
    impl_ = std::move(other.impl_);
  }
  return *this;
}
controller::~controller() { close(); }

controller::operator bool() const noexcept { return impl_ != nullptr; }

const std::string &controller::path() const noexcept {
  static const std::string none;
  return impl_ ? impl_->path : none;
}

int controller::fd() const noexcept { return impl_ ? impl_->io->fd() : -1; }

const controller::impl &controller::need() const {
  if (!impl_) fail(errc::init_not_done);
  return *impl_;
}

void controller::load(const move &m) {
  const auto &d = need();
  if (const errc e = check(m); e != errc::ok) fail(e);
  x4step_move km{};
  for (int i = 0; i < axes; i++) km.steps[i] = narrow_steps(m.steps[i]);
  km.freq_hz = m.freq_hz;
  km.ramp_ms = static_cast<int32_t>(m.ramp.count());
  if (d.io->ioctl(X4STEP_LOAD, &km)) fail_ioctl(errno, "X4STEP_LOAD", km.result);
}

void controller::start() { need().call(X4STEP_START, nullptr, "X4STEP_START"); }
void controller::brake() { need().call(X4STEP_BRAKE, nullptr, "X4STEP_BRAKE"); }
void controller::stop() { need().call(X4STEP_STOP, nullptr, "X4STEP_STOP"); }

void controller::move_endless(axis a, direction dir, int freq_hz, std::chrono::milliseconds ramp) {
  const auto &d = need();
  if (const errc e = check_endless(freq_hz, ramp); e != errc::ok) fail(e);
  x4step_endless ke{};
  ke.axis = a.number();
  ke.direction = dir == direction::negative ? -1 : 1;
  ke.freq_hz = freq_hz;
  ke.ramp_ms = static_cast<int32_t>(ramp.count());
  if (d.io->ioctl(X4STEP_MOVE_ENDLESS, &ke)) fail_ioctl(errno, "X4STEP_MOVE_ENDLESS", ke.result);
}

status controller::get_status() const { return need().get_status(); }
bool controller::active() const { return get_status().active; }

long long controller::steps(axis a) const { return get_status().steps[a.index()]; }

unsigned controller::inputs() const { return get_status().inputs; }

bool controller::wait(std::chrono::milliseconds timeout) const { return need().wait(timeout); }

void controller::set_output(signal s, bool high) {
  x4step_outputs out{};
  out.mask = s == signal::one ? X4STEP_OUT_SIGNAL1 : X4STEP_OUT_SIGNAL2;
  out.levels = high ? out.mask : 0;
  need().call(X4STEP_SET_OUTPUTS, &out, "X4STEP_SET_OUTPUTS");
}

void controller::set_brake_codes(const std::vector<int> &codes) {
  const auto &d = need();
  if (codes.size() > X4STEP_MAX_BRAKE_CODES) fail(errc::param_fail);
  x4step_brake_codes bc{};
  for (int c : codes) {
    if (c < 1 || c > 255) fail(errc::param_fail);
    bc.codes[bc.count++] = static_cast<uint16_t>(c);
  }
  d.call(X4STEP_SET_BRAKE_CODES, &bc, "X4STEP_SET_BRAKE_CODES");
}

void controller::set_config(const config &c) {
  x4step_config kc{};
  kc.clock_invert = c.clock_invert().mask();
  kc.dir_invert = c.dir_invert().mask();
  kc.flags = c.keys_swallow() ? X4STEP_CFG_KEYS_SWALLOW : 0;
  kc.output_mode = static_cast<uint32_t>(c.mode());
  need().call(X4STEP_SET_CONFIG, &kc, "X4STEP_SET_CONFIG");
}

config controller::get_config() const {
  x4step_config kc{};
  need().call(X4STEP_GET_CONFIG, &kc, "X4STEP_GET_CONFIG");
  return config()
      .clock_invert(axes_of(kc.clock_invert))
      .dir_invert(axes_of(kc.dir_invert))
      .keys_swallow((kc.flags & X4STEP_CFG_KEYS_SWALLOW) != 0)
      .mode(static_cast<output_mode>(kc.output_mode));
}

void controller::set_step_timing(const step_timing &t) {
  const auto ns = [](std::chrono::nanoseconds v) {
    if (v.count() < 0 || v.count() > X4_TIMING_MAX_NS) fail(errc::param_fail);
    return static_cast<uint32_t>(v.count());
  };
  x4step_step_timing kt{};
  kt.pulse_ns = ns(t.pulse());
  kt.space_ns = ns(t.space());
  kt.dir_setup_ns = ns(t.dir_setup());
  kt.dir_hold_ns = ns(t.dir_hold());
  need().call(X4STEP_SET_STEP_TIMING, &kt, "X4STEP_SET_STEP_TIMING");
}

step_timing controller::get_step_timing() const {
  x4step_step_timing kt{};
  need().call(X4STEP_GET_STEP_TIMING, &kt, "X4STEP_GET_STEP_TIMING");
  using std::chrono::nanoseconds;
  return step_timing()
      .pulse(nanoseconds(kt.pulse_ns))
      .space(nanoseconds(kt.space_ns))
      .dir_setup(nanoseconds(kt.dir_setup_ns))
      .dir_hold(nanoseconds(kt.dir_hold_ns));
}

void controller::set_profile(axis a, const profile &p) {
  const auto &d = need();
  if (check(p) != errc::ok) fail(errc::param_fail);
  x4step_profile kp{};
  kp.axis = static_cast<uint32_t>(a.number());
  kp.v0 = p.start_speed();
  kp.ve = p.end_speed();
  kp.vm = p.top_speed();
  kp.a0 = p.accel();
  kp.ae = p.decel();
  d.call(X4STEP_SET_PROFILE, &kp, "X4STEP_SET_PROFILE");
}

profile controller::get_profile(axis a) const {
  const auto &d = need();
  x4step_profile kp{};
  kp.axis = static_cast<uint32_t>(a.number());
  d.call(X4STEP_GET_PROFILE, &kp, "X4STEP_GET_PROFILE");
  return profile().start_speed(kp.v0).end_speed(kp.ve).top_speed(kp.vm).accel(kp.a0).decel(kp.ae);
}

void controller::move_to(axis a, long target) { move_to(a, one_axis(a, target), false); }

void controller::move_by(axis a, long distance) { move_to(a, one_axis(a, distance), true); }

void controller::move_to(axis_set s, const std::array<long, axes> &targets, bool relative) {
  const auto &d = need();
  need_axes(s);
  x4step_goto g{};
  g.axes = s.mask();
  g.flags = relative ? X4STEP_GOTO_RELATIVE : 0;
  for (axis a : s) g.target[a.index()] = narrow_s32(targets[a.index()]);
  if (d.io->ioctl(X4STEP_GOTO, &g)) fail_ioctl(errno, "X4STEP_GOTO", g.result);
}

void controller::home(axis a, const homing &h) {
  const auto &d = need();
  if (check(h) != errc::ok) fail(errc::param_fail);
  x4step_home kh{};
  kh.axis = static_cast<uint32_t>(a.number());
  kh.phases = (h.phase1() ? X4STEP_HOME_PHASE1 : 0) | (h.phase2() ? X4STEP_HOME_PHASE2 : 0) |
              (h.brake() ? X4STEP_HOME_BRAKE : 0);
  kh.vref1 = h.phase1_speed();
  kh.vref2 = h.phase2_speed();
  kh.sref = static_cast<uint32_t>(h.max_travel());
  if (d.io->ioctl(X4STEP_HOME, &kh)) fail_ioctl(errno, "X4STEP_HOME", kh.result);
}

void controller::halt(axis_set s, halt_mode how) {
  const auto &d = need();
  need_axes(s);
  x4step_halt kh{};
  kh.axes = s.mask();
  kh.how = how == halt_mode::stop ? X4STEP_HALT_STOP : X4STEP_HALT_BRAKE;
  d.call(X4STEP_HALT, &kh, "X4STEP_HALT");
}

void controller::set_position(axis a, long position) {
  const auto &d = need();
  x4step_position kp{};
  kp.axes = a.bit();
  kp.position[a.index()] = narrow_s32(position);
  d.call(X4STEP_SET_POSITION, &kp, "X4STEP_SET_POSITION");
}

void controller::set_switches(const switches &s) {
  const auto &d = need();
  if (s.nc >= 1u << inputs_count) fail(errc::param_fail);
  x4step_switches ks{};
  for (int i = 0; i < axes; i++) {
    ks.ref[i] = narrow_input(s.ref[i]);
    ks.plus[i] = narrow_input(s.plus[i]);
    ks.minus[i] = narrow_input(s.minus[i]);
  }
  ks.nc = static_cast<uint8_t>(s.nc);
  d.call(X4STEP_SET_SWITCHES, &ks, "X4STEP_SET_SWITCHES");
}

switches controller::get_switches() const {
  x4step_switches ks{};
  need().call(X4STEP_GET_SWITCHES, &ks, "X4STEP_GET_SWITCHES");
  switches s;
  for (int i = 0; i < axes; i++) {
    s.ref[i] = ks.ref[i];
    s.plus[i] = ks.plus[i];
    s.minus[i] = ks.minus[i];
  }
  s.nc = ks.nc;
  return s;
}

axes_status controller::get_axes() const { return need().get_axes(); }

axis_status controller::get_axis(axis a) const { return need().get_axes()[a]; }

bool controller::wait_axes(axis_set s, std::chrono::milliseconds timeout) const {
  return need().wait_axes(s, timeout);
}

std::optional<event> controller::read_event(std::chrono::milliseconds timeout) const {
  return need().read_event(timeout);
}

void controller::close() noexcept {
  if (!impl_) return;
  // Brake and wait here: the kernel brakes on its own when the device
  // closes, but keeps the port until the motors stand, so a new controller
  // could not open yet. HALT of every axis covers the axes' own moves and
  // the interpolated move alike. No time limit: a profile's brake may take
  // minutes. This runs in the destructor and the noexcept move assignment,
  // so nothing is thrown: an error (the port went away: POLLERR) ends the
  // wait, and the device is closed anyway.
  x4step_halt all{axis_set::all().mask(), X4STEP_HALT_BRAKE, {}};
  impl_->io->ioctl(X4STEP_HALT, &all);  // ESRCH: nothing to brake
  try {
    impl_->wait(std::chrono::milliseconds(-1));
  } catch (...) {
  }
  impl_.reset();
}

std::chrono::steady_clock::time_point controller::now() const { return detail::access::io(*this).now(); }

bool controller::clock_runs() const { return !detail::access::io(*this).virtual_time(); }

void controller::sleep_for(std::chrono::nanoseconds d) {
  detail::port_io &io = detail::access::io(*this);
  if (io.virtual_time())
    io.pass(d);
  else if (d.count() > 0)
    std::this_thread::sleep_for(d);
}

namespace detail {

port_io &access::io(const controller &c) {
  if (!c.impl_) fail(errc::init_not_done);
  return *c.impl_->io;
}

}  // namespace detail

// ---- monitor ------------------------------------------------------------------

struct monitor::impl : device {
  using device::device;
};

monitor::monitor(int lpt) : monitor(detail::port_name(lpt)) {}
monitor::monitor(const std::filesystem::path &path)
    : impl_(std::make_unique<impl>(path.string(), O_RDONLY)) {}
monitor::monitor(monitor &&other) noexcept = default;
monitor &monitor::operator=(monitor &&other) noexcept = default;
monitor::~monitor() = default;

monitor::operator bool() const noexcept { return impl_ != nullptr; }

const std::string &monitor::path() const noexcept {
  static const std::string none;
  return impl_ ? impl_->path : none;
}

int monitor::fd() const noexcept { return impl_ ? impl_->io->fd() : -1; }

void monitor::close() noexcept { impl_.reset(); }

status monitor::get_status() const {
  if (!impl_) fail(errc::init_not_done);
  return impl_->get_status();
}

bool monitor::wait(std::chrono::milliseconds timeout) const {
  if (!impl_) fail(errc::init_not_done);
  return impl_->wait(timeout);
}

axes_status monitor::get_axes() const {
  if (!impl_) fail(errc::init_not_done);
  return impl_->get_axes();
}

bool monitor::wait_axes(axis_set s, std::chrono::milliseconds timeout) const {
  if (!impl_) fail(errc::init_not_done);
  return impl_->wait_axes(s, timeout);
}

std::optional<event> monitor::read_event(std::chrono::milliseconds timeout) const {
  if (!impl_) fail(errc::init_not_done);
  return impl_->read_event(timeout);
}

unsigned monitor::abi_version() const {
  if (!impl_) fail(errc::init_not_done);
  x4step_info info{};
  impl_->call(X4STEP_GET_INFO, &info, "X4STEP_GET_INFO");
  return info.abi_version;
}

void monitor::emergency_halt(halt_mode how) const {
  if (!impl_) fail(errc::init_not_done);
  x4step_estop k{};
  k.how = how == halt_mode::stop ? X4STEP_HALT_STOP : X4STEP_HALT_BRAKE;
  if (impl_->io->ioctl(X4STEP_ESTOP, &k) == 0) return;
  if (errno == ENOTTY)
    throw error(std::make_error_code(std::errc::not_supported),
                impl_->path +
                    ": the x4step module is too old for an emergency halt from a monitor: update x4step.ko");
  fail_ioctl(errno, "X4STEP_ESTOP");
}

}  // namespace x4step
