// SPDX-License-Identifier: LGPL-2.1-or-later
// libx4step: the simulated port's event stream, as the module's
// kmod/x4step_events.c keeps it: a ring of 256 events that each
// descriptor reads from its own position. Why moves end is told by the
// engine's tracker (kmod/engine/x4_track.c), which the module runs too.
#include <linux/x4step.h>

#include <cerrno>
#include <cstring>

#include "port.hpp"

namespace x4step::sim {

// x4step_ev_push_locked().
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

void port::track_push(x4_track *t, u32 type, u32 axes, u32 how, u32 value, u32 flags) {
  static_cast<tracker *>(t)->self->ev_push_locked(type, axes, how, value, flags);
}

// x4step_events_read() on an O_NONBLOCK descriptor: whole events, as many as
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

}  // namespace x4step::sim
