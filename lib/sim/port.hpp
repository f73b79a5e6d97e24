// SPDX-License-Identifier: LGPL-2.1-or-later
// The simulated port: the module's engine (kmod/engine, the very objects
// the host tests run) behind the module's request interface, with a clock
// of its own instead of the hrtimer and a record of the pins instead of
// the port registers. What the module's glue does around the engine
// (kmod/x4step_main.c, x4step_ioctl.c, x4step_move.c, x4step_motion.c,
// x4step_port.c, x4step_events.c, x4step_path.c) is
// done here in the same order with the same engine calls; its decisions
// (kmod/engine/x4_req.c, x4_track.c) are the very code the module runs:
// the checks, errnos, events and pin writes are the module's. Internal to
// libx4step.
#ifndef X4STEP_SIM_PORT_HPP
#define X4STEP_SIM_PORT_HPP

#include <sys/types.h>

#include <array>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

#include "options.hpp"

extern "C" {
#include "x4_engine.h"
#include "x4_req.h"
#include "x4_track.h"
}

namespace x4step::sim {

class vcd_writer;
class terminal;

/// One port write: the data register and the control outputs (pin
/// levels, X4_CTL_*) after it, at engine time t_ns.
struct pin_write {
  std::uint64_t t_ns;
  std::uint8_t data;
  std::uint8_t ctl;
};

/// An open descriptor of a port (the module's struct x4_file).
struct file {
  bool controller = false;
  std::uint64_t ev_next = 0;  ///< seq of the next event it reads
  int efd = -1;               ///< eventfd, readable while poll would report
  bool efd_set = false;
};

class port {
 public:
  using time_point = std::chrono::steady_clock::time_point;

  port(int number, options o);
  port(const port &) = delete;
  port &operator=(const port &) = delete;
  ~port();

  /// The port sim:number, shared by every descriptor of this process that
  /// has it open; a fresh one if none has.
  static std::shared_ptr<port> get(int number, const options &o);
  /// The port if any descriptor of this process has it open.
  static std::shared_ptr<port> find(int number);

  /// The module's open() and release() of a descriptor.
  void open(file &f, bool controller);
  void close(file &f);

  int ioctl(file &f, unsigned long cmd, void *arg);
  ssize_t read(file &f, void *buf, size_t n);
  ssize_t write(file &f, const void *buf, size_t n);
  int poll(file &f, short events, int timeout_ms, short *revents);
  time_point now() const;

  // The machine side, for tests and scripts.

  /// Input pin levels (X4GetIn bits) of the inputs no switch of the
  /// machine drives; they read LOW until set.
  void set_inputs(unsigned levels);
  /// The machine's axes, in steps, as its pins moved them.
  std::array<std::int64_t, 4> machine_positions() const;
  /// A key event (set-1 code) as the module's input handler sees it:
  /// true if it braked a move. Scripted keys (X4STEP_SIM_KEYS) come at
  /// their times, typed ones (terminal.hpp) when typed.
  bool key(unsigned code);
  /// Keep every pin write from now on (off: none kept).
  void record(bool on);
  std::vector<pin_write> writes() const;
  /// Virtual time only: run the engine's events up to engine time t_ns.
  void run_until(std::uint64_t t_ns);
  std::uint64_t engine_now() const;
  /// Virtual time: what passes while a program polls the state (a status
  /// read, X4GetTimer), so that a loop such as the manual's
  /// `while (X4GetState()) ;` ends. Real time: nothing.
  static constexpr std::uint64_t poll_quantum_ns = 100000;
  void let_time_pass();
  const options &settings() const noexcept { return opt_; }

 private:
  using lock = std::unique_lock<std::mutex>;
  using starter = int (*)(x4_engine *e, const void *arg, std::uint64_t now);

  std::uint64_t now_locked() const;
  std::uint64_t steady_ns_locked() const;
  unsigned inputs_locked();
  void write_locked(std::uint64_t t);
  void write_rest_locked();
  void fire_locked(std::uint64_t t);
  void drain_locked(std::uint64_t until);
  void tick_done_locked();
  void note_ends_locked();
  void changed_locked();
  short revents_locked(const file &f) const;
  bool step_virtual_locked(std::uint64_t limit);
  bool key_locked(unsigned code);
  std::uint64_t next_key_ns_locked() const;
  void keys_due_locked(std::uint64_t t_ns);
  void advance_locked(std::uint64_t t_ns);
  void timer_thread();
  // state.cpp: X4STEP_SIM_STATE, what a module would keep between programs.
  void load_state_locked();
  void save_state_locked();
  // An axis as X4STEP_SIM_STATE keeps it (state.cpp).
  struct kept_axis {
    long long coordinate = 0, machine = 0;
    int synced = 0;
    bool operator==(const kept_axis &o) const {
      return coordinate == o.coordinate && machine == o.machine && synced == o.synced;
    }
  };
  // This port's axes as read from the file: only what changed since is
  // written back, so that a reader's close keeps another program's moves.
  std::array<kept_axis, 4> kept_{};

  int run_locked(starter start, const void *arg, unsigned kind);
  int goto_locked(std::uint8_t axes, const std::int32_t *target, bool relative);
  void halted_locked();
  int brake_locked(std::uint8_t axes, unsigned source, unsigned code);
  int stop_locked(std::uint8_t axes);
  void claimed_locked();
  void quiesce_locked();
  void let_go_locked();
  void set_invert_locked(std::uint8_t clock_invert, std::uint8_t dir_invert);

  // ioctl.cpp: the module's x4step_ioctl() and its helpers.
  int ioctl_locked(file &f, unsigned long cmd, void *arg);
  int any_ioctl_locked(unsigned long cmd, void *arg);
  int status_locked(void *arg);
  int axes_locked(void *arg);

  // events.cpp: the module's x4step_events.c.
  void ev_push_locked(unsigned type, unsigned axes, unsigned how, unsigned value, unsigned flags);
  static void track_push(x4_track *t, u32 type, u32 axes, u32 how, u32 value, u32 flags);
  void update_locked(int c, unsigned kind) { x4_track_update(&track_, &eng_, c, kind); }

  // path.cpp: the module's x4step_path.c.
  int path_resize_locked(std::uint32_t depth);
  bool path_flushed_locked() const { return eng_.path.flushes != path_flushes_seen_; }
  int path_go_locked();
  bool path_brake_aborts_locked(unsigned source) const;
  bool path_brake_locked(unsigned source);
  int path_ctl_locked(const x4step_path_ctl &c);
  int path_config_locked(const x4step_path_config &c);
  int path_read_locked(unsigned long cmd, void *arg);

  const int number_;
  const options opt_;
  mutable std::mutex m_;
  std::mutex write_m_;             // one path write() at a time (the module's path_write_lock)
  std::condition_variable wake_;   // pollers and readers
  std::condition_variable timer_;  // the real-time thread
  time_point epoch_;               // engine time 0
  std::uint64_t vnow_ = 0;         // virtual time: the engine's now

  x4_engine eng_{};
  x4_engine plan_eng_{};
  x4_goto plan_goto_{};
  std::vector<file *> files_;
  const file *controller_ = nullptr;
  bool releasing_ = false;
  bool claimed_ = false;
  machine machine_;  // the axes, switches and scripted inputs
  unsigned inputs_read_ = 0;
  std::uint64_t inputs_ns_ = 0;
  bool written_valid_ = false;
  std::uint8_t data_written_ = 0, ctl_written_ = 0;
  std::uint8_t clock_invert_ = 0, dir_invert_ = 0, data_invert_ = 0;
  std::uint32_t cfg_flags_ = 0;
  std::uint16_t brake_codes_[20] = {};
  std::uint32_t n_brake_codes_ = 0;
  std::uint32_t last_brake_code_ = 0;
  std::uint64_t brake_time_ns_ = 0;
  std::uint64_t moves_ended_ = 0;

  bool recording_ = false;
  std::vector<pin_write> writes_;
  std::unique_ptr<vcd_writer> vcd_;

  // The event stream, as the module's x4_port ev_* fields.
  std::vector<x4step_event> events_;
  std::uint64_t ev_seq_ = 1;
  std::uint64_t ev_time_ns_ = 0;
  struct tracker : x4_track {
    port *self;
  };
  tracker track_{};

  // A path's queue (the module's path_* fields of x4_port).
  std::vector<x4_path_slot> path_slots_;
  std::uint32_t path_cfg_flags_ = 0;
  std::uint32_t path_flushes_seen_ = 0;

  std::size_t next_key_ = 0;  // the next of opt_.keys

  bool quit_ = false;
  std::thread thread_;  // real time only
  std::unique_ptr<terminal> tty_;
};

}  // namespace x4step::sim

#endif  // X4STEP_SIM_PORT_HPP
