// SPDX-License-Identifier: GPL-2.0
// x4grbl: a GRBL 1.1 controller on an x4step machine (issue 31). The
// bridge is the protocol and the machine state behind it, without any
// transport: bytes in (receive), bytes out (take_output), time (tick).
// main.cpp carries it over a pseudo-terminal or TCP.
//
// Lines are taken in order. A G-code line goes through the same
// interpreter and planner as `x4ctl gcode` (lib/gcode, lib/machine) into
// a backlog of segments and commands, and from there into the module's
// path queue as it has room; the line is acknowledged (ok) once it is
// planned, and the next line is taken only while the backlog is short,
// so a sender that counts characters is held back by the acks, as GRBL's
// planner holds it. Real-time bytes act at once, between any two bytes.
#ifndef X4GRBL_BRIDGE_HPP
#define X4GRBL_BRIDGE_HPP

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include "cli.hpp"
#include "gcode.hpp"
#include "io.hpp"
#include "machine.hpp"
#include "planner.hpp"
#include "settings.hpp"
#include "x4step_path.hpp"

namespace x4grbl {

namespace m = x4step::machine;
namespace g = x4step::gcode;

/// GRBL's receive buffer, which senders that count characters fill.
constexpr std::size_t rx_buffer_size = 128;
/// The longest line taken (GRBL: 80 after removing blanks; a PC affords
/// more): a longer one is refused whole with error:11.
constexpr std::size_t max_line = 256;

class bridge {
 public:
  /// c: the machine file (c.machine) and the port (c.sim, c.device);
  /// keep_port: hold the port between clients (a simulated one, which
  /// lives in this process), else it is opened for each client and
  /// released when it leaves, so that x4ctl can use the machine between.
  bridge(const x4ctl::config &c, bool keep_port);
  ~bridge();
  bridge(const bridge &) = delete;
  bridge &operator=(const bridge &) = delete;

  /// A client connected: the port is opened, the welcome line sent.
  void connect();
  /// The client went away: any motion holds along the path and the
  /// queue is flushed; outputs off; the port released (unless kept).
  void disconnect();
  bool connected() const noexcept { return connected_; }
  /// Bytes from the client.
  void receive(std::string_view bytes);
  /// Moves the work on: lines into the planner, segments into the path
  /// queue, dwells, alarms, the end of a reset. Call it at least every
  /// few milliseconds while busy().
  void tick();
  /// Something runs or waits: tick() soon (else on input or every 100 ms).
  /// (The path queue holds at least 256 segments, a quarter of a second
  /// and more: a tick every few milliseconds keeps it full, and a
  /// simulated port has no descriptor that polls for room.)
  bool busy() const;
  /// What to send to the client (taken: the buffer is emptied).
  std::string take_output();
  /// While a blocking operation (homing) runs, the bridge calls this to
  /// read the client (receive) for up to `ms` milliseconds and send its
  /// output, so that `?` and a reset are served meanwhile.
  void on_serve(std::function<void(int ms)> f) { serve_ = std::move(f); }
  /// SIGTERM: holds along the path, flushes, outputs off, port released.
  void shutdown();
  /// A line for the log (stderr) of what the bridge did, or "".
  std::string take_log();

 private:
  enum class run_state { idle, cycle, hold, jog, homing, alarm, check, sleep };
  struct item;
  class output;
  struct line_in {
    std::string text;
    bool overflow = false;
  };

  // Lines.
  void realtime(unsigned char c);
  void pump();
  bool take_line(const line_in &l);
  void system_command(const std::string &line);
  void gcode_line(const std::string &line);
  void jog_line(const std::string &line);
  void reply(int error);
  void say(const std::string &line);
  void message(const std::string &text) { say("[MSG:" + text + "]"); }

  // Motion.
  void feed_path();
  void update_motion();
  void abort_motion();
  void release();
  bool motion_pending() const;
  bool path_idle() const;
  void resync();
  g::pose planned_end() const;
  void outputs_off();
  void set_output(m::pin p, bool on);
  void home(const std::string &letters);
  m::probe_result run_probe(const x4step::segment &s, g::probe_kind k);
  struct line_abandoned {};  // a reset during a line's probe: it gets no reply
  void raise_alarm(int code, bool critical);
  void run_startup();
  void soft_reset();
  void finish_reset();
  /// A fresh interpreter from where the machine stands, or from `at`.
  void new_program();
  void new_program(const g::pose &at);
  void reload_coordinates();
  void save_coordinates();

  // Reports.
  run_state state() const;
  std::string status_report();
  std::string parameters_report() const;
  std::string modes_report() const;
  std::string axes_text(const g::pose &p) const;
  g::pose machine_position() const;
  double report_scale() const;

  x4ctl::config c_;
  m::machine mc_;
  bool keep_port_;
  settings settings_;
  std::unique_ptr<x4ctl::controller_port> port_;
  std::unique_ptr<x4step::path> path_;
  bool connected_ = false;

  // Receiving.
  std::string partial_;
  bool partial_overflow_ = false;
  bool last_cr_ = false;
  std::deque<line_in> lines_;
  std::size_t pending_bytes_ = 0;

  // The program.
  std::unique_ptr<output> out_;
  std::unique_ptr<m::planner> planner_;
  std::unique_ptr<g::interpreter> interp_;
  g::coordinate_state saved_coords_;
  int line_no_ = 0;

  // The motion.
  std::deque<item> backlog_;
  std::size_t backlog_segments_ = 0;
  std::uint64_t queued_ = 0;  // segments given to the path since it was cleared
  std::uint64_t base_done_ = 0;
  bool jogging_ = false;
  std::unique_ptr<output> jog_out_;
  std::unique_ptr<m::planner> jog_planner_;
  g::pose jog_end_{};  // where the jogs queued end
  std::optional<std::chrono::steady_clock::time_point> dwell_until_;
  bool paused_ = false;  // M0, M1, M6: Hold until ~
  bool hold_asked_ = false;
  bool aborting_ = false;  // a reset or a jog cancel: the path brakes, then is cleared
  bool reset_pending_ = false;
  std::uint64_t starved_base_ = 0;  // the path's starved count at connect

  // The machine's state as GRBL tells it.
  int alarm_ = 0;
  bool alarm_critical_ = false;  // hard or soft limit: a reset first
  bool homing_ = false;
  bool check_mode_ = false;
  bool sleeping_ = false;
  bool locked_ = false;       // homed first: axes with home switches not homed (GRBL's homing lock)
  bool unlocked_ = false;     // $X: the homed-first rule waived
  bool locked_port_ = false;  // the port could not be opened: nothing moves
  unsigned feed_override_ = 100, rapid_override_ = 100, spindle_override_ = 100;
  bool flood_ = false, mist_ = false;
  int wco_counter_ = 0, ovr_counter_ = 0;
  g::pose last_wco_{};
  g::pose probe_{};  // the last probe's trip (machine coordinates), for $# and [PRB:]
  bool probe_ok_ = false;

  bool status_asked_ = false;  // '?' came: a report goes with the next output
  std::string out_text_;
  std::string log_;
  std::function<void(int)> serve_;
};

}  // namespace x4grbl

#endif  // X4GRBL_BRIDGE_HPP
