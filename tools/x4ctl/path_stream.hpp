// SPDX-License-Identifier: GPL-2.0
// x4ctl: streaming segments into a port's path queue while serving the
// user (keys, signals) and redrawing the progress; shared by `x4ctl path`
// and `x4ctl gcode`.
#ifndef X4CTL_PATH_STREAM_HPP
#define X4CTL_PATH_STREAM_HPP

#include <chrono>
#include <functional>
#include <optional>
#include <string>

#include "term.hpp"
#include "x4step_path.hpp"

namespace x4ctl {

class path_stream {
 public:
  /// One progress record for the status (done: segments completed since
  /// the stream began): a line to redraw on a terminal, at most width
  /// characters (what is wider is cut there), or a JSON object.
  using progress_fn =
      std::function<std::string(const x4step::path_status &, std::uint64_t done, bool json, size_t width)>;

  /// keyboard: read keys from a terminal on stdin: space holds and
  /// resumes, ESC aborts (hold, then flush), + and - change the override
  /// by 10 %. Always: Ctrl-C, SIGTERM, `x4ctl brake` abort; `x4ctl stop` stops.
  path_stream(x4step::controller &ctl, unsigned override_percent, bool json, bool keyboard,
              progress_fn progress);
  /// A stream inside a full-screen program (x4ctl panel): keys from keys
  /// (the same keys as above), and instead of the live line, show is
  /// called at every status read and say with each line of text.
  struct view {
    std_console *keys = nullptr;
    std::function<void(const x4step::path_status &, std::uint64_t done)> show;
    std::function<void(const std::string &)> say;
  };
  path_stream(x4step::controller &ctl, unsigned override_percent, const view &v, progress_fn progress);
  ~path_stream();
  path_stream(const path_stream &) = delete;
  path_stream &operator=(const path_stream &) = delete;

  /// Queues s, waiting for room; false once the path was aborted (then
  /// nothing more is queued).
  bool push(const x4step::segment &s);
  /// Queues what fits of [s, s + n) now; how many.
  std::size_t push_some(const x4step::segment *s, std::size_t n);
  /// Waits until the path stands at its end (a hold is waited out); false:
  /// aborted, by the user or by the kernel (a flush: fewer done than queued).
  bool drain();
  /// Runs a probing segment (s.probe() set) from rest to its end: where
  /// the probe input tripped (the trip's flush of the path is no abort: the
  /// path goes on), or none once aborted, by the user or by the kernel.
  std::optional<x4step::probe_latch> probe(const x4step::segment &s);
  /// Waits for the time given on the port's clock (a simulated port's
  /// virtual time passes at once), serving keys; false: aborted.
  bool wait_for(std::chrono::milliseconds t);
  /// Waits for space (go on) or ESC (abort) with the path at rest; false: aborted.
  bool wait_for_operator();
  /// Shows the progress now.
  void show_now();
  /// Ends the progress: with JSON a last record; on a terminal the live
  /// line is cleared for the end line that follows.
  void finish();
  /// Prints a line of text between progress redraws (a message, a pause).
  void say(const std::string &text);

  /// Called at every status read while the path runs (a plot's samples).
  void on_poll(std::function<void()> f) { on_poll_ = std::move(f); }

  bool aborted() const noexcept { return aborted_; }
  /// Ctrl-C (a key or SIGINT) aborted it: the program it runs in ends too.
  bool interrupted() const noexcept { return interrupted_; }
  const x4step::path_status &status() const noexcept { return status_; }
  std::uint64_t done() const noexcept { return status_.done - base_; }
  unsigned override_percent() const noexcept { return override_; }

 private:
  void begin(std::chrono::steady_clock::time_point now);
  void serve(int poll_ms);
  void take(key k);
  void show(bool now);

  x4step::controller &ctl_;
  x4step::path path_;
  bool json_, live_;
  std_console own_;  // the keys of a stream without a view
  std_console &con_;
  view view_;
  progress_fn progress_;
  unsigned override_;
  bool aborted_ = false;
  bool interrupted_ = false;
  bool probing_ = false;      // a probing segment runs: its trip flushes the path
  bool drawn_ = false;        // a live line is on the screen
  std::uint64_t base_ = 0;    // the port's done count when the stream began
  std::uint64_t pushed_ = 0;  // segments queued by this stream
  x4step::path_status status_;
  std::chrono::steady_clock::time_point last_shown_;
  std::function<void()> on_poll_;
};

}  // namespace x4ctl

#endif  // X4CTL_PATH_STREAM_HPP
