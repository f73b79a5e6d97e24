// SPDX-License-Identifier: LGPL-2.1-or-later
// libx4step: continuous paths (x4step_path.hpp) over the module's write()
// of segment records and its X4STEP_PATH_* ioctls.
#include <linux/x4step.h>
#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <ostream>

#include "detail.hpp"
#include "x4step_path.hpp"

extern "C" {
#include "x4_check.h"  // the kernel's own argument checks
}

namespace x4step {

using detail::deadline;
using detail::fail;
using detail::fail_errno;
using detail::fail_ioctl;

static_assert(static_cast<int>(path_state::held) == X4STEP_PATH_HELD);

namespace {

constexpr std::uint32_t value_max = 0x7fffffff;

std::uint8_t to_engine(probe_mode m) {
  switch (m) {
    case probe_mode::none:
      return X4_PROBE_NONE;
    case probe_mode::toward:
      return X4_PROBE_TOWARD;
    case probe_mode::away:
      return X4_PROBE_AWAY;
  }
  return 0xff;  // not a mode: param_fail
}

x4step_segment to_kernel(const segment &s) {
  x4step_segment k{};
  for (axis a : axis_set::all()) k.steps[a.index()] = static_cast<__s32>(s.steps(a));
  k.length = s.length();
  k.v_max = s.top_speed();
  k.v_entry = s.entry_speed();
  k.accel = s.accel();
  k.tag = s.tag();
  if (s.probe() == probe_mode::toward) k.flags = X4STEP_SEG_PROBE_TOWARD;
  if (s.probe() == probe_mode::away) k.flags = X4STEP_SEG_PROBE_AWAY;
  return k;
}

// The controller's port; init_not_done once it is closed.
detail::port_io &need_io(const controller &c) { return detail::access::io(c); }

[[noreturn]] void fail_write(int err) {
  if (err == ECANCELED)
    throw error(make_error_code(errc::not_active),
                "the path was flushed (a stop, an emergency stop, a limit switch, an abort or a brake key): "
                "path::clear() before a new path");
  fail_ioctl(err, "write of path segments");
}

// Write what fits now (the descriptor is O_NONBLOCK): whole records, up to
// the first bad one (which fails this call if it is the first).
std::size_t write_some(detail::port_io &io, const segment *s, std::size_t n) {
  constexpr std::size_t chunk = 64;
  std::size_t done = 0;
  while (done < n) {
    x4step_segment k[chunk];
    std::size_t m = 0;
    for (; m < std::min(chunk, n - done); m++) {
      const errc e = check(s[done + m]);
      if (e != errc::ok && done + m == 0) fail(e);
      if (e != errc::ok) break;
      k[m] = to_kernel(s[done + m]);
    }
    if (!m) return done;  // the bad one fails the next call
    const ssize_t got = io.write(k, m * sizeof k[0]);
    if (got < 0 && errno == EAGAIN) return done;
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) {
      if (done) return done;
      fail_write(errno);
    }
    done += static_cast<std::size_t>(got) / sizeof k[0];
    if (static_cast<std::size_t>(got) < m * sizeof k[0]) return done;
  }
  return done;
}

void ctl(const controller &c, unsigned cmd, unsigned value, const char *what) {
  x4step_path_ctl k{};
  k.cmd = cmd;
  k.value = value;
  if (need_io(c).ioctl(X4STEP_PATH_CTL, &k)) fail_ioctl(errno, what);
}

}  // namespace

// The kernel's own check of a record (kmod/engine/x4_check.c).
errc check(const segment &s) noexcept {
  x4_segment k{};
  for (axis a : axis_set::all()) k.steps[a.index()] = detail::narrow_steps(s.steps(a));
  k.length = s.length();
  k.v_max = s.top_speed();
  k.v_entry = s.entry_speed();
  k.accel = s.accel();
  k.probe = to_engine(s.probe());
  const int ret = x4_segment_check(&k, 0);
  return ret == X4_ERR_RATE_BUDGET ? errc::freq_too_high : static_cast<errc>(ret);
}

std::uint32_t junction_speed(const std::array<double, axes> &in, const std::array<double, axes> &out,
                             double accel, double deviation) noexcept {
  double dot = 0, n_in = 0, n_out = 0;
  for (int i = 0; i < axes; i++) {
    dot += in[i] * out[i];
    n_in += in[i] * in[i];
    n_out += out[i] * out[i];
  }
  if (n_in <= 0 || n_out <= 0) return 0;
  const double cos_theta = -dot / std::sqrt(n_in * n_out);  // theta: the angle between them
  if (cos_theta > 0.999999) return 0;                       // a reversal
  if (cos_theta < -0.999999) return UINT32_MAX;             // straight on
  const double sin_half = std::sqrt(0.5 * (1 - cos_theta));
  const double v = std::sqrt(accel * deviation * sin_half / (1 - sin_half));
  return v >= double(value_max) ? value_max : static_cast<std::uint32_t>(v);
}

std::ostream &operator<<(std::ostream &os, path_state s) {
  switch (s) {
    case path_state::idle:
      return os << "idle";
    case path_state::running:
      return os << "running";
    case path_state::holding:
      return os << "holding";
    case path_state::held:
      return os << "held";
  }
  return os << "state " << static_cast<int>(s);
}

void path::configure(const path_config &c) {
  x4step_path_config k{};
  k.depth = c.depth();
  k.flags = c.keys_abort() ? X4STEP_PATH_KEYS_ABORT : 0;
  if (c.probe_active_low()) k.flags |= X4STEP_PATH_PROBE_NC;
  if (c.probe_input() > 5) fail(errc::param_fail);
  k.probe = c.probe_input();
  if (need_io(*c_).ioctl(X4STEP_SET_PATH_CONFIG, &k)) fail_ioctl(errno, "X4STEP_SET_PATH_CONFIG");
}

path_config path::config() const {
  x4step_path_config k{};
  if (need_io(*c_).ioctl(X4STEP_GET_PATH_CONFIG, &k)) fail_ioctl(errno, "X4STEP_GET_PATH_CONFIG");
  return path_config()
      .depth(k.depth)
      .keys_abort(k.flags & X4STEP_PATH_KEYS_ABORT)
      .probe_input(k.probe, k.flags & X4STEP_PATH_PROBE_NC);
}

probe_latch path::probe() const {
  x4step_probe k{};
  if (need_io(*c_).ioctl(X4STEP_GET_PROBE, &k)) fail_ioctl(errno, "X4STEP_GET_PROBE");
  probe_latch l;
  l.tripped = k.flags & X4STEP_PROBE_TRIPPED;
  for (int i = 0; i < axes; i++) l.steps[static_cast<std::size_t>(i)] = k.position[i];
  l.tag = k.tag;
  return l;
}

std::size_t path::try_append(const segment *s, std::size_t n) { return write_some(need_io(*c_), s, n); }

void path::append(const std::vector<segment> &s) {
  std::size_t done = 0;
  while (done < s.size()) {
    done += try_append(s.data() + done, s.size() - done);
    if (done == s.size()) break;
    // Full: wait for room (POLLOUT), or until no move runs (POLLIN). A
    // path that stands then is held, and no room comes until a resume():
    // say so rather than wait for ever (or for 5 ms: it starts now).
    short revents = 0;
    if (need_io(*c_).poll(POLLOUT | POLLIN, -1, &revents) < 0 && errno != EINTR)
      fail_errno(errno, "poll " + c_->path());
    if (revents & (POLLERR | POLLHUP)) fail(errc::lpt_not_found);
    if (revents & POLLOUT || !(revents & POLLIN)) continue;
    const path_state now = status().state;
    if (now == path_state::held)
      throw error(make_error_code(errc::not_active),
                  "the path is held and its queue is full: resume() it (or abort()) before appending more; " +
                      std::to_string(done) + " of " + std::to_string(s.size()) + " segments were queued");
    if (now == path_state::idle && need_io(*c_).poll(POLLOUT, 5, &revents) < 0 && errno != EINTR)
      fail_errno(errno, "poll " + c_->path());
  }
}

void path::append(const segment &s) { append(std::vector<segment>{s}); }

void path::clear() { ctl(*c_, X4STEP_PATH_CLEAR, 0, "X4STEP_PATH_CTL clear"); }
void path::hold() { ctl(*c_, X4STEP_PATH_HOLD, 0, "X4STEP_PATH_CTL hold"); }
void path::resume() { ctl(*c_, X4STEP_PATH_RESUME, 0, "X4STEP_PATH_CTL resume"); }
void path::abort() { ctl(*c_, X4STEP_PATH_ABORT, 0, "X4STEP_PATH_CTL abort"); }

void path::set_override(unsigned percent) {
  if (percent < 1 || percent > 200) fail(errc::param_fail);
  ctl(*c_, X4STEP_PATH_OVERRIDE, percent, "X4STEP_PATH_CTL override");
}

path_status path::status() const {
  x4step_path_status k{};
  if (need_io(*c_).ioctl(X4STEP_GET_PATH, &k)) fail_ioctl(errno, "X4STEP_GET_PATH");
  path_status s;
  s.state = static_cast<path_state>(k.state);
  s.queued = k.queued;
  s.depth = k.depth;
  s.override_percent = k.override;
  s.speed = k.speed;
  s.keys_abort = k.flags & X4STEP_PATH_KEYS_ABORT;
  s.tag = k.tag;
  s.done = k.done;
  s.starved = k.starved;
  return s;
}

bool path::wait(std::chrono::milliseconds timeout) const {
  const deadline d(timeout, need_io(*c_));
  for (;;) {
    const path_status s = status();
    if (s.state == path_state::held || (s.state == path_state::idle && !s.queued)) return true;
    if (d.expired()) return false;
    // POLLIN: no move runs (the end of a move wakes the pollers). A path
    // idle with segments queued starts in a moment: look again in 5 ms.
    short revents = 0;
    const int ms = s.state == path_state::idle ? d.poll_ms(5) : d.poll_ms();
    if (need_io(*c_).poll(POLLIN, ms, &revents) < 0 && errno != EINTR)
      fail_errno(errno, "poll " + c_->path());
    if (revents & (POLLERR | POLLHUP)) fail(errc::lpt_not_found);
  }
}

}  // namespace x4step
