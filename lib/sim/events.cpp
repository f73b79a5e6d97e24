// SPDX-License-Identifier: LGPL-2.1-or-later
// libx4step: the simulated port's event stream. A line-by-line port of
// the module's kmod/x4step_events.c (x4_ev_push_locked() ...
// x4_events_fired_locked(), and its read()): why a move ended is told
// from what the glue asked for and what the engine shows after each of
// its calls. Glue duplicated from the module: keep the two in step (or
// move both into kmod/engine, see the report of issue 19).
#include <linux/x4step.h>

#include <cerrno>
#include <cstring>

#include "port.hpp"

namespace x4step::sim {

void port::ev_push_locked(unsigned type, unsigned axes, unsigned how, unsigned value, unsigned flags) {
  x4step_event &ev = events_[ev_seq_ & (events_.size() - 1)];
  std::uint64_t now = steady_ns_locked();
  std::memset(&ev, 0, sizeof ev);
  ev.seq = ev_seq_++;
  if (now < ev_time_ns_) now = ev_time_ns_;
  ev_time_ns_ = now;
  ev.timestamp_ns = now;
  ev.type = type;
  ev.axes = axes;
  ev.how = how;
  ev.value = value;
  ev.flags = flags;
  for (int i = 0; i < X4_AXES; i++)
    ev.position[i] = static_cast<std::int32_t>(eng_.pos_base[i] + static_cast<std::uint32_t>(eng_.steps[i]));
}

std::uint8_t port::ev_chans_locked(std::uint8_t axes) const {
  std::uint8_t chans = 0;
  for (int i = 0; i < X4_AXES; i++)
    if (eng_.busy & (1u << i) && x4_engine_chan_axes(&eng_, i) & axes) chans |= 1u << i;
  return chans;
}

std::uint8_t port::ev_chan_axes_locked(std::uint8_t chans) const {
  std::uint8_t axes = 0;
  for (int i = 0; i < X4_AXES; i++)
    if (chans & (1u << i)) axes |= eng_.ch[i].run.axes;
  return axes;
}

void port::ev_brake_locked(std::uint8_t chans, unsigned source, unsigned code) {
  if (!chans) return;
  ev_braked_ |= chans;
  ev_push_locked(X4STEP_EV_BRAKE, ev_chan_axes_locked(chans), source, code, 0);
}

int port::ev_chan_of_axis_locked(int i) const {
  for (int c = 0; c < X4_AXES; c++)
    if (ev_busy_ & (1u << c) && eng_.ch[c].run.axes & (1u << i)) return c;
  return -1;
}

void port::ev_errors_locked() {
  for (int i = 0; i < X4_AXES; i++) {
    const std::uint8_t fresh = eng_.err[i] & ~ev_err_[i];
    ev_err_[i] = eng_.err[i];
    if (!fresh) continue;
    const int c = ev_chan_of_axis_locked(i);
    const unsigned amb = eng_.err[i] & X4_AXERR_AMBIGUOUS ? X4STEP_EVF_AMBIGUOUS : 0;
    if (fresh & X4_AXERR_LIMIT_POS)
      ev_push_locked(X4STEP_EV_SWITCH, 1u << i, X4STEP_SW_LIMIT_POS, eng_.sw.plus[i], amb);
    if (fresh & X4_AXERR_LIMIT_NEG)
      ev_push_locked(X4STEP_EV_SWITCH, 1u << i, X4STEP_SW_LIMIT_NEG, eng_.sw.minus[i], amb);
    if (c < 0) continue;
    if (fresh & (X4_AXERR_LIMIT_POS | X4_AXERR_LIMIT_NEG))
      ev_how_[c] = X4STEP_END_LIMIT;
    else if (fresh & X4_AXERR_REF_TRAVEL)
      ev_how_[c] = X4STEP_END_REF_TRAVEL;
    else if (fresh & X4_AXERR_REF_PASSED)
      ev_how_[c] = X4STEP_END_REF_PASSED;
  }
}

void port::ev_ref_locked(int c) {
  const int axis = eng_.ch[c].run.leader;
  ev_push_locked(X4STEP_EV_SWITCH, 1u << axis, X4STEP_SW_REF, eng_.sw.ref[axis], 0);
}

void port::ev_home_locked(int c, std::uint8_t was) {
  const x4_chan &ch = eng_.ch[c];
  if (ev_how_[c]) return;
  if (was == X4_HOME_PHASE1 && !ch.ref_found) return;
  if (was == X4_HOME_PHASE2) ev_ref_locked(c);
  if (!ch.home) ev_how_[c] = was == X4_HOME_PHASE2 ? X4STEP_END_HOMED : X4STEP_END_REF_FOUND;
}

void port::ev_update_locked(int c, unsigned kind) {
  if (std::memcmp(eng_.err, ev_err_, sizeof ev_err_)) ev_errors_locked();
  for (int i = 0; i < X4_AXES; i++) {
    const std::uint8_t was = ev_home_[i];
    if (eng_.ch[i].ref_found && !ev_ref_found_[i] && eng_.ch[i].home) ev_ref_locked(i);
    ev_ref_found_[i] = eng_.ch[i].ref_found;
    ev_home_[i] = eng_.ch[i].home;
    if (i == c && was && was != eng_.ch[i].home) ev_home_locked(i, was);
  }
  const std::uint8_t ended = ev_busy_ & ~eng_.busy;
  const std::uint8_t started = eng_.busy & ~ev_busy_;
  for (int i = 0; i < X4_AXES; i++) {
    const std::uint8_t bit = 1u << i;
    if (!(ended & bit)) continue;
    unsigned how = ev_how_[i];
    // A path's end (held, aborted): paths are not simulated yet.
    if (!how)
      how = ev_stopped_ & bit  ? X4STEP_END_STOPPED
            : ev_braked_ & bit ? X4STEP_END_BRAKED
                               : X4STEP_END_COMPLETED;
    ev_push_locked(X4STEP_EV_MOVE_ENDED, eng_.ch[i].run.axes, how, 0, 0);
    ev_how_[i] = 0;
  }
  ev_braked_ &= ~ended;
  ev_stopped_ &= ~ended;
  ev_busy_ = eng_.busy;
  if (started & 1) ev_path_ = kind == X4STEP_KIND_PATH;
  for (int i = 0; i < X4_AXES; i++)
    if (started & (1u << i)) ev_push_locked(X4STEP_EV_MOVE_STARTED, eng_.ch[i].run.axes, kind, 0, 0);
}

void port::ev_fired_locked(int c) {
  if (eng_.busy != ev_busy_ || eng_.ch[c].home != ev_home_[c] || eng_.ch[c].ref_found != ev_ref_found_[c] ||
      std::memcmp(eng_.err, ev_err_, sizeof ev_err_))
    ev_update_locked(c, 0);
}

// x4_events_read() on an O_NONBLOCK descriptor: whole events, as many as
// fit and are there; EAGAIN if none.
ssize_t port::read(file &f, void *buf, size_t n) {
  const lock l(m_);
  if (n < sizeof(x4step_event)) {
    errno = EINVAL;
    return -1;
  }
  const std::uint64_t oldest = ev_seq_ > events_.size() ? ev_seq_ - events_.size() : 1;
  if (f.ev_next < oldest) f.ev_next = oldest;
  size_t done = 0;
  while (n - done >= sizeof(x4step_event) && f.ev_next < ev_seq_) {
    std::memcpy(static_cast<char *>(buf) + done, &events_[f.ev_next & (events_.size() - 1)],
                sizeof(x4step_event));
    f.ev_next++;
    done += sizeof(x4step_event);
  }
  if (!done) {
    errno = EAGAIN;
    return -1;
  }
  changed_locked();
  return static_cast<ssize_t>(done);
}

// Path segments: not simulated yet.
ssize_t port::write(file &f, const void *, size_t) {
  const lock l(m_);
  errno = controller_ == &f ? EOPNOTSUPP : EBADF;
  return -1;
}

}  // namespace x4step::sim
