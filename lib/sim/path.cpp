// SPDX-License-Identifier: LGPL-2.1-or-later
// libx4step: continuous paths on the simulated port, as the module's
// kmod/x4step_path.c takes them: segments written in chunks, checked,
// queued and planned by kmod/engine/x4_path.c, and kicked; the
// X4STEP_PATH_* requests with the module's checks (kmod/engine/x4_req.c).
// Descriptors of the library are O_NONBLOCK: a full queue is EAGAIN, and
// the library polls for POLLOUT (which runs the clock in virtual time).
#include <linux/x4step.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "port.hpp"

namespace x4step::sim {
namespace {

constexpr std::uint32_t path_chunk = 8;  // the module's X4_PATH_CHUNK

// x4step_kick(): only a path that begins is a start (the timer, the last
// brake code); a running one follows its plan without a new event.
int kick(x4_engine *e, const void *, std::uint64_t now) {
  return x4_path_kick(e, now) ? X4_OK : X4_ERR_IS_ACTIVE;
}

int resume(x4_engine *e, const void *, std::uint64_t now) { return x4_path_resume(e, now); }

}  // namespace

// x4step_path_resize(): a new queue of `depth` slots, the old one freed.
int port::path_resize_locked(std::uint32_t depth) {
  if (eng_.path.depth == depth) return 0;
  std::vector<x4_path_slot> slots(depth);
  const int ret = x4_path_set_queue(&eng_, slots.data(), depth);
  if (ret) return x4_req_errno(ret);
  path_slots_.swap(slots);
  return 0;
}

// x4step_path_go(): start the path, unless it was flushed meanwhile; then
// what this write() queued after the flush goes too, and it ends.
int port::path_go_locked() {
  if (path_flushed_locked()) {
    x4_path_hold(&eng_, true);
    return -ECANCELED;
  }
  run_locked(kick, nullptr, X4STEP_KIND_PATH);
  return 0;
}

// x4step_motion_path_aborts_locked(): whether a brake by `source` aborts the path.
bool port::path_brake_aborts_locked(unsigned source) const {
  return x4_req_brake_aborts_path(source, path_cfg_flags_) && x4_path_active(&eng_);
}

// x4step_motion_path_brake_locked(): hold a path, and flush it too for `source`;
// true: it aborted the path.
bool port::path_brake_locked(unsigned source) {
  return path_brake_aborts_locked(source) && !x4_track_path_abort(&track_, &eng_);
}

// x4step_path_write() on an O_NONBLOCK descriptor: one write() at a time, the
// port's lock let go between chunks.
ssize_t port::write(file &f, const void *buf, size_t n) {
  const std::lock_guard<std::mutex> one(write_m_);
  lock l(m_);
  const auto fail = [](int err) {
    errno = err;
    return -1;
  };
  if (controller_ != &f) return fail(EBADF);
  if (n % sizeof(x4step_segment)) return fail(EINVAL);
  if (!buf) return fail(EFAULT);
  int ret = path_slots_.empty() ? path_resize_locked(X4STEP_PATH_DEPTH_MIN) : 0;
  size_t done = 0;
  while (!ret && done < n) {
    if (done) {  // between chunks: the timer, the ioctls
      l.unlock();
      l.lock();
      if (controller_ != &f) break;
    }
    if (path_flushed_locked()) {
      ret = -ECANCELED;
      break;
    }
    const size_t m = std::min<size_t>({(n - done) / sizeof(x4step_segment), path_chunk, x4_path_room(&eng_)});
    if (!m) {
      if (!done) ret = -EAGAIN;
      break;
    }
    for (size_t i = 0; i < m && !ret; i++) {
      x4step_segment r;
      std::memcpy(&r, static_cast<const char *>(buf) + done, sizeof r);
      x4_segment seg;
      ret = x4_req_segment(&r, &seg);
      if (!ret) ret = x4_path_check(&eng_, &seg);
      ret = x4_req_errno(ret);
      if (ret) break;
      x4_path_push(&eng_, &seg);
      done += sizeof r;
    }
    if (path_go_locked()) {  // what it queued is flushed too
      ret = -ECANCELED;
      done = 0;
    }
  }
  // x4step_path_plan_work(): the module goes on with the pass the pushes'
  // budget left, a bounded part a jiffy; here it comes through at once.
  if (x4_path_plan(&eng_, 0)) {
    x4_path_plan(&eng_, UINT32_MAX);
    if (eng_.path.state != X4_PATH_IDLE) x4_path_kick(&eng_, now_locked());
  }
  changed_locked();
  if (done) return static_cast<ssize_t>(done);
  return fail(-ret);
}

// x4step_path_ctl_cmd().
int port::path_ctl_locked(const x4step_path_ctl &c) {
  if (x4_req_bad_path_ctl(&c)) return -EINVAL;
  switch (c.cmd) {
    case X4STEP_PATH_HOLD:
    case X4STEP_PATH_ABORT: {
      const int ret =
          c.cmd == X4STEP_PATH_ABORT ? x4_track_path_abort(&track_, &eng_) : x4_path_hold(&eng_, false);
      changed_locked();
      return x4_req_errno(ret);
    }
    case X4STEP_PATH_CLEAR:
      path_flushes_seen_ = eng_.path.flushes;
      return 0;
    case X4STEP_PATH_RESUME:
      return x4_req_errno(run_locked(resume, nullptr, X4STEP_KIND_PATH));
    case X4STEP_PATH_OVERRIDE: {
      const int ret = x4_path_set_override(&eng_, c.value);
      if (ret) return x4_req_errno(ret);
      x4_path_replan(&eng_);
      run_locked(kick, nullptr, X4STEP_KIND_PATH);
      return 0;
    }
    default:
      return -EINVAL;
  }
}

// x4step_path_set_config().
int port::path_config_locked(const x4step_path_config &c) {
  if (x4_req_bad_path_config(&c)) return -EINVAL;
  int ret = x4_req_errno(x4_req_set_probe(&eng_, &c));
  if (!ret && c.depth) ret = path_resize_locked(c.depth);
  if (!ret) path_cfg_flags_ = c.flags;
  return ret;
}

// x4step_path_ioctl_read(): GET_PATH_CONFIG, GET_PATH and GET_PROBE, on any descriptor.
int port::path_read_locked(unsigned long cmd, void *arg) {
  if (cmd == X4STEP_GET_PROBE) {
    x4step_probe pr;
    x4_req_probe(&eng_, &pr);
    std::memcpy(arg, &pr, sizeof pr);
    return 0;
  }
  if (cmd == X4STEP_GET_PATH_CONFIG) {
    x4step_path_config cfg;
    x4_req_path_config(&eng_, path_cfg_flags_, &cfg);
    std::memcpy(arg, &cfg, sizeof cfg);
    return 0;
  }
  x4_path_status s;
  x4_path_get_status(&eng_, &s);
  x4step_path_status st;
  x4_req_path_status(&s, path_cfg_flags_, &st);
  std::memcpy(arg, &st, sizeof st);
  return 0;
}

}  // namespace x4step::sim
