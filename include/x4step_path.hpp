// SPDX-License-Identifier: LGPL-2.1-or-later
/**
 * @file x4step_path.hpp
 * @brief Continuous paths (module interface 5): straight segments that run
 *        back to back, planned ahead in the kernel so that the motors
 *        always stop on the path, whatever the program does.
 *
 * A path belongs to a x4step::controller (the port's owner) and owns every
 * axis while it is active. Each segment moves the axes by whole steps,
 * interpolated as X4Step moves are, along a length in a unit the program
 * chooses (mm / 1000, say, or steps / 1000); speeds and accelerations are
 * in that unit along the path. The kernel plans over its whole queue:
 * each segment is entered as fast as its corner (entry_speed) and the
 * stop of everything queued after it allow. When the program is late to
 * refill, the motors slow down and stop on the path; when it dies, they
 * hold along the path and the queue is flushed.
 *
 * @code
 *   x4step::controller c(1);
 *   x4step::path p(c);
 *   p.append(x4step::segment{}.steps(x4step::axis::x, 4000).length(4000).top_speed(2000).accel(20000));
 *   p.append(x4step::segment{}.steps(x4step::axis::y, 4000).length(4000).top_speed(2000).accel(20000)
 *                .entry_speed(x4step::junction_speed({1, 0}, {0, 1}, 20000, 1)));
 *   p.wait();  // until the queue ran empty, or a hold stood
 * @endcode
 *
 * Probing (G38.2..G38.5, module interface 6): a segment with probe(mode)
 * watches the path's probe input (path_config::probe_input) on every step
 * tick. Where the input first is in the awaited state, path::probe()
 * latches every axis' position (the step at which the input changed, at
 * any feed), and the path brakes along the path and is flushed, as by
 * abort(): append() throws not_active until clear().
 *
 * @code
 *   p.configure(x4step::path_config{}.probe_input(3, false));  // pin 12, NO
 *   p.append(x4step::segment{}.steps(x4step::axis::z, -4000).length(4000).top_speed(500).accel(5000)
 *                .probe(x4step::probe_mode::toward));
 *   p.wait();
 *   const x4step::probe_latch l = p.probe();  // l.tripped, l.steps[2]
 *   p.clear();
 * @endcode
 *
 * Threads: as a controller (x4step.hpp): one thread at a time per object.
 */
#ifndef X4STEP_PATH_HPP
#define X4STEP_PATH_HPP

#include <array>
#include <chrono>
#include <cstdint>
#include <iosfwd>
#include <vector>

#include "x4step.hpp"

#pragma GCC visibility push(default)
namespace x4step {

/// What a probing segment waits for on the path's probe input.
enum class probe_mode {
  none,    ///< not a probing segment
  toward,  ///< stop when the input becomes active: G38.2/G38.3
  away     ///< stop when it becomes inactive: G38.4/G38.5
};

/// One straight segment of a path, built by name:
/// segment{}.steps(axis::x, 100).steps(axis::y, -40).length(1077).top_speed(5000).accel(50000)
/// Rules (the kernel's): some steps (|steps| <= 16777216 per axis); length,
/// speeds and accel 1..2^31 - 1 (entry_speed may be 0); top_speed / accel at
/// most 1800 s; the leader axis' rate at top_speed within what the port can
/// do (else freq_too_high), its acceleration 1..1000000 steps/s^2.
class segment {
 public:
  segment &steps(axis a, long n) noexcept {
    steps_[a.index()] = n;
    return *this;
  }
  /// The path's length of the segment, in the program's unit.
  segment &length(std::uint32_t units) noexcept { return set(length_, units); }
  /// Its top speed, units/s (the feed, before the override).
  segment &top_speed(std::uint32_t v) noexcept { return set(v_max_, v); }
  /// The most the corner before it allows, units/s (junction_speed()); default 0: stop there.
  segment &entry_speed(std::uint32_t v) noexcept { return set(v_entry_, v); }
  /// Acceleration and braking along it, units/s^2.
  segment &accel(std::uint32_t a) noexcept { return set(accel_, a); }
  /// Yours: path::status() reports the running segment's (e.g. a program line).
  segment &tag(std::uint64_t t) noexcept {
    tag_ = t;
    return *this;
  }
  /// A probing segment: it ends where the probe input reaches the state
  /// `m` waits for (path::probe() has where), braking along the path and
  /// flushing the queue; if it never does, the path goes on after it. The
  /// path needs a probe input (path_config::probe_input), else param_fail.
  /// The input is sampled at each step tick: a feed of v steps/s sees a
  /// change within 1/v s, and brakes from there with accel().
  segment &probe(probe_mode m) noexcept {
    probe_ = m;
    return *this;
  }

  long steps(axis a) const noexcept { return steps_[a.index()]; }
  std::uint32_t length() const noexcept { return length_; }
  std::uint32_t top_speed() const noexcept { return v_max_; }
  std::uint32_t entry_speed() const noexcept { return v_entry_; }
  std::uint32_t accel() const noexcept { return accel_; }
  std::uint64_t tag() const noexcept { return tag_; }
  probe_mode probe() const noexcept { return probe_; }

 private:
  segment &set(std::uint32_t &field, std::uint32_t value) noexcept {
    field = value;
    return *this;
  }
  std::array<long, axes> steps_{};
  std::uint32_t length_ = 0, v_max_ = 0, v_entry_ = 0, accel_ = 0;
  std::uint64_t tag_ = 0;
  probe_mode probe_ = probe_mode::none;
};

/// Why a segment is invalid (steps_too_high, no_steps, param_fail, or
/// freq_too_high: its leader faster than any port steps), or errc::ok: the
/// kernel's own check of a record, as far as it does not depend on the port.
errc check(const segment &s) noexcept;

/// The highest speed at the corner between two straight pieces, by GRBL's
/// junction deviation: the speed at which a circle `deviation` away from
/// the corner, touching both pieces, is taken with acceleration `accel`.
/// `in` and `out` are the pieces' directions (any length, in the path's
/// unit); a straight line gives no limit (UINT32_MAX), a reversal 0.
std::uint32_t junction_speed(const std::array<double, axes> &in, const std::array<double, axes> &out,
                             double accel, double deviation) noexcept;

enum class path_state { idle, running, holding, held };
std::ostream &operator<<(std::ostream &os, path_state s);

struct path_status {
  path_state state = path_state::idle;
  unsigned queued = 0;  ///< segments queued, the running one included
  unsigned depth = 0;   ///< the queue's size
  unsigned override_percent = 100;
  unsigned speed = 0;         ///< path units/s now
  bool keys_abort = false;    ///< brake keys abort (else they hold)
  std::uint64_t tag = 0;      ///< of the running (or next) segment; 0: none
  std::uint64_t done = 0;     ///< segments completed since the module was loaded
  std::uint64_t starved = 0;  ///< refills that came after the path began to stop
};

/// The queue's size (256..4096, a power of 2; 0 keeps it: it can change
/// only while no path is active), what brake keys do, and the probe input
/// (like the depth, it can change only while no path is active).
class path_config {
 public:
  path_config &depth(unsigned n) noexcept {
    depth_ = n;
    return *this;
  }
  path_config &keys_abort(bool on) noexcept {
    keys_abort_ = on;
    return *this;
  }
  /// The probe input of probing segments: 1..5 (X4GetIn bit 0..4, as
  /// switches number them), 0: none; active_low for a normally closed
  /// probe. Its own polarity: switches::nc does not apply to it. An input
  /// above 5 fails configure() with param_fail.
  path_config &probe_input(unsigned input, bool active_low) noexcept {
    probe_input_ = input;
    probe_active_low_ = active_low;
    return *this;
  }
  unsigned depth() const noexcept { return depth_; }
  bool keys_abort() const noexcept { return keys_abort_; }
  unsigned probe_input() const noexcept { return probe_input_; }
  bool probe_active_low() const noexcept { return probe_active_low_; }

 private:
  unsigned depth_ = 0;  // 0: keep the depth (256 at first)
  bool keys_abort_ = false;
  unsigned probe_input_ = 0;
  bool probe_active_low_ = false;
};

/// Where the last probing segment that ran stopped waiting (path::probe()).
struct probe_latch {
  bool tripped = false;            ///< its input reached the awaited state
  std::array<long, axes> steps{};  ///< every axis' position (steps) at that step tick; 0 without a trip
  std::uint64_t tag = 0;           ///< the probing segment's tag
};

/// The path of a controller's port. Holds a reference: the controller
/// must outlive it. Destroying it changes nothing (the controller's close
/// holds and flushes a running path).
class path {
 public:
  explicit path(controller &c) noexcept : c_(&c) {}

  /// Only while no path is active (else is_active), unless the depth is
  /// 0 and the probe input stays as it is (keys_abort changes any time).
  void configure(const path_config &c);
  path_config config() const;

  /// Queue segments in order, waiting while the queue is full (poll(), no
  /// spinning). A bad segment throws; the ones before it are queued. Once
  /// the path was flushed (a stop, an emergency stop, a limit switch, an
  /// abort, a brake key that aborts), it throws not_active until clear():
  /// a program learns that its path was stopped, rather than running the
  /// rest from where it stood. A held path (hold(), a brake key) frees no
  /// room: with the queue full, it throws not_active, rather than wait
  /// for a resume() that the waiting thread itself would have to give (a
  /// program that resumes from another thread appends the rest then:
  /// status().done + queued grew by the segments this call queued).
  void append(const segment &s);
  void append(const std::vector<segment> &s);
  /// Queue what fits now, without waiting; how many were queued.
  std::size_t try_append(const segment *s, std::size_t n);

  void hold();    ///< brake along the path to rest (not_active: no path)
  void resume();  ///< go on from a hold
  void abort();   ///< hold, then flush the queue
  void clear();   ///< accept segments again after a flush (a new path)
  /// Feed override, 1..200 percent of every top speed, within 2 ms.
  void set_override(unsigned percent);

  path_status status() const;
  /// The latch of the last probing segment that ran (cleared when one
  /// starts): tripped, and every axis' position where its input changed.
  probe_latch probe() const;
  /// Block until the path stands: its queue ran empty (done, or flushed by
  /// an abort, a stop or a limit), or a hold reached rest (poll(), no
  /// spinning); status() tells which. False on timeout; -1: for ever.
  bool wait(std::chrono::milliseconds timeout = std::chrono::milliseconds(-1)) const;
  /// The controller's descriptor: POLLOUT while the queue has room.
  int fd() const noexcept { return c_->fd(); }

 private:
  controller *c_;
};

}  // namespace x4step
#pragma GCC visibility pop

#endif  // X4STEP_PATH_HPP
