// SPDX-License-Identifier: GPL-2.0
// x4ctl gcode and mdi: what a run shows while it runs and at its end: the
// progress line fitted to the terminal, the JSON progress records, the end
// line with the machine time and the estimate.
#ifndef X4CTL_RUN_DISPLAY_HPP
#define X4CTL_RUN_DISPLAY_HPP

#include <chrono>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "json.hpp"
#include "machine_io.hpp"
#include "planner.hpp"
#include "x4step_path.hpp"

namespace x4ctl {

/// "0:05", "12:05", "1:02:05": minutes and seconds, hours when needed.
std::string clock_text(double seconds);

/// A line of fields that fits width characters: fields[i] lists field i's
/// forms from the longest to the shortest ("" leaves it out). While the
/// line is wider than width, the field named next in shrink takes its next
/// form; what is still too wide is cut at width. Fields are joined by sep.
/// ASCII only (a character is a column).
std::string fit_line(const std::vector<std::vector<std::string>> &fields, const std::vector<size_t> &shrink,
                     size_t width, const std::string &sep = " | ");

/// The progress of a run, from the segments the kernel completed and,
/// within the running one, from where the motors stand. Times are on the
/// port's clock (a simulated port's virtual time), in seconds.
class progress_meter {
 public:
  /// keys: the keys work (a terminal on stdin): the line says which.
  /// command begins the lines ("gcode: running ..."); "": nothing does.
  progress_meter(const m::machine &mc, x4step::controller &ctl, const m::plan_summary &total,
                 std::string command, bool keys, unsigned override_percent, const g::pose &start);

  /// A segment went into the queue (in the program's order).
  void queued(const m::segment_info &i);
  /// A dwell of the program ended (the estimate counts it).
  void dwelled(double seconds);

  /// One record: a line of at most width characters, or a JSON object.
  std::string record(const x4step::path_status &s, std::uint64_t done, bool json, size_t width);

  /// The run ended: what was done at its end, for the end line.
  void ended(const x4step::path_status &s, std::uint64_t done) { measure(s, done); }
  /// Machine time since the meter began (the run's start).
  double elapsed() const;
  /// The estimate of the whole run at the override it began with.
  double estimated() const;
  /// "gcode: done in 2:18, estimated 2:11, at X1 Y2 Z3 (mm)"; aborted:
  /// "gcode: aborted at 41.2% after 0:57, estimated 2:11, at ...".
  std::string end_line(bool aborted, const std::string &where) const;
  /// The result record: result, elapsed, estimated, units, position.
  std::string end_json(bool aborted, const json_object &position) const;

 private:
  struct mark {
    double length = 0, seconds = 0;  // at the end of a segment, from the start
    double seg_length = 0, seg_seconds = 0;
    g::pose from{}, to{};
  };
  // What is done of the run: length and time at the top speeds.
  void measure(const x4step::path_status &s, std::uint64_t done);

  const m::machine &mc_;
  x4step::controller &ctl_;
  std::string command_;
  std::string units_;
  double ppu_;
  m::plan_summary total_;
  bool keys_;
  unsigned start_override_;
  std::deque<mark> pending_;  // queued, not yet done: at most the queue's depth
  mark done_;
  g::pose last_end_{};
  double queued_len_ = 0, queued_secs_ = 0, dwelled_ = 0;
  double now_len_ = 0, now_secs_ = 0;  // done, the running segment's part included
  std::uint64_t taken_ = 0;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace x4ctl

#endif  // X4CTL_RUN_DISPLAY_HPP
