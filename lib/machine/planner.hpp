// SPDX-License-Identifier: LGPL-2.1-or-later
/**
 * @file planner.hpp
 * @brief The planner (issue 20): the interpreter's motions, in machine
 *        units, become path segments in steps (x4step_path.hpp).
 *
 * - Exact: every segment's end is the absolute programmed point (a move's
 *   end, or a point on an arc) rounded to steps once, so nothing
 *   accumulates: after any program each motor stands at
 *   round(programmed end x SCALE), however many segments it took.
 * - Rapids at the axes' MAX_VELOCITY; feeds at F, clamped so that no axis
 *   exceeds its MAX_VELOCITY; the acceleration along each segment the
 *   most that keeps every axis within its MAX_ACCELERATION. [TRAJ]
 *   MAX_LINEAR_VELOCITY caps both.
 * - Arcs and helices: equal chords, as few as keep every chord within
 *   ARC_TOLERANCE of the arc.
 * - Corners: the entry speed of each segment is GRBL's junction speed
 *   (planner.c: the acceleration along the corner's bisector limited by
 *   every axis, and the junction deviation), at most the slower of the
 *   two segments' speeds; the kernel's look-ahead does the rest. G64 P
 *   sets the deviation; G61.1 (exact stop), dwells, pauses, tool changes
 *   and output changes stop the path.
 * - Soft limits: every segment's end (rapids, feeds, every chord point of
 *   an arc) is checked before it is given on: a point beyond a limit is a
 *   gcode::error naming the program's file and line. A program is
 *   therefore planned whole once (plan_program into an output that only
 *   counts) before the first step, then again into the path queue.
 * - Probing (G38.2..G38.5): one segment to the programmed end (its soft
 *   limits checked), from rest to rest, handed to planner_output::probe();
 *   the runner runs it to its end and says where the motors stopped; the
 *   plan goes on from there (gcode::probe_outcome back to the interpreter).
 * - Messages: (MSG,...) and (DEBUG,...) come with the number of segments
 *   before them, so that a runner shows each when its line runs, not
 *   when it is planned (up to a queue's length earlier): message_queue.
 *
 * Lengths, speeds and accelerations given to the kernel are in path units
 * of 1/10000 mm (an inch is 254000 of them; a degree 10000 on a mm
 * machine, 254000 on an inch machine).
 */
#ifndef X4STEP_PLANNER_HPP
#define X4STEP_PLANNER_HPP

#include <array>
#include <cstdint>
#include <deque>
#include <functional>
#include <iosfwd>
#include <string>
#include <string_view>
#include <utility>

#include "gcode.hpp"
#include "machine.hpp"
#include "x4step_path.hpp"

namespace x4step::machine {

/// Path units per machine unit (length unit; degrees count the same).
double path_units_per_unit(gcode::units u) noexcept;

/// What the planner knows of a segment beyond the segment itself.
struct segment_info {
  int line = 0;        ///< the program's line (also the segment's tag)
  bool rapid = false;  ///< G0 (or G28/G30/G53's traverse)
  double length = 0;   ///< along the path, machine units (degrees for rotary-only moves)
  double speed = 0;    ///< its top speed, units/s
  double feed = 0;     ///< the feed asked for, units/s (rapids: the same as speed)
  gcode::pose end{};   ///< where it ends, machine units, as programmed
};

/// Where a (MSG,...) or (DEBUG,...) belongs in the path.
struct message_info {
  int line = 0;        ///< the program's line
  bool debug = false;  ///< (DEBUG,...) rather than (MSG,...)
  /// The segments planned before it: its line starts running once that
  /// many are done (path_status::done counted from the path's start).
  std::uint64_t after = 0;
};

/// What a probing segment did (planner_output::probe). Steps are the
/// motors' absolute positions as the planner counts them
/// (plan_summary::steps: round(machine position x SCALE)), motor 1..4 at
/// 0..3.
struct probe_result {
  /// false: the segment did not run (a check, a plan that does not move):
  /// the planner takes contact at the programmed end.
  bool ran = false;
  /// The probe input changed (contact made, or broken for G38.4/G38.5).
  bool tripped = false;
  /// Where it changed (the engine's latch); where the motors stopped.
  std::array<long, x4step::axes> trip{}, stop{};
};

/// Where planned segments and the program's other commands go, in order.
class planner_output {
 public:
  virtual ~planner_output() = default;
  virtual void segment(const x4step::segment &, const segment_info &) = 0;
  /// A probing segment (G38.2..G38.5): it starts from rest and the path
  /// stands still after it. A runner sets segment.probe() itself (toward
  /// for G38.2/G38.3, away for G38.4/G38.5), runs the path to the end of
  /// this segment and returns the latch. This default does not run it.
  virtual probe_result probe(const x4step::segment &, const segment_info &, gcode::probe_kind) { return {}; }
  /// The commands below come after the path stood still (the next
  /// segment starts from rest).
  virtual void dwell(double /*seconds*/) {}
  /// M0 / M1 (optional), M6 (tool >= 0): wait for the operator.
  virtual void pause(bool /*optional*/, int /*tool*/) {}
  virtual void spindle(bool /*on*/) {}
  virtual void coolant(bool /*mist*/, bool /*flood*/) {}
  virtual void message(std::string_view) {}
  /// (MSG,...) and (DEBUG,...) with their place. A runner that queues
  /// segments ahead of the motion holds them (message_queue) and shows
  /// each when its line runs; this default shows it now, by message().
  virtual void message_at(std::string_view text, const message_info &) { message(text); }
  /// The interpreter's warnings (G43 H without a tool table):
  /// "file:line:column: warning: ...", when the line is planned.
  virtual void warning(const gcode::error &) {}
};

/// Messages held until the motion reaches them (planner_output::message_at):
/// a runner adds each as it is planned and asks, as the path advances,
/// for those now due.
class message_queue {
 public:
  using show_fn = std::function<void(const std::string &, const message_info &)>;
  void add(std::string_view text, const message_info &i) { q_.emplace_back(std::string(text), i); }
  /// Shows, in program order, every message due once `done` segments are
  /// done; how many.
  std::size_t due(std::uint64_t done, const show_fn &show) {
    std::size_t n = 0;
    for (; !q_.empty() && q_.front().second.after <= done; ++n) {
      const auto m = std::move(q_.front());
      q_.pop_front();
      show(m.first, m.second);
    }
    return n;
  }
  bool empty() const noexcept { return q_.empty(); }
  /// Drops the rest (an aborted run).
  void clear() noexcept { q_.clear(); }

 private:
  std::deque<std::pair<std::string, message_info>> q_;
};

/// Totals of everything planned so far.
struct plan_summary {
  int lines = 0;  ///< the last line that did something (M2, %)
  long segments = 0;
  double length = 0;         ///< along the path, machine units
  double seconds = 0;        ///< at the segments' top speeds, plus dwells (no ramps)
  gcode::pose min{}, max{};  ///< extents of the planned points and the start, machine units
  /// The same in work coordinates: each point less the work offset
  /// (G5x + G92, no tool length) in force when it was planned.
  gcode::pose work_min{}, work_max{};
  bool moved = false;  ///< min/max hold something
  /// Each motor's step position after it (motor 1..4 at 0..3).
  std::array<long, x4step::axes> steps{};
};

class planner : public gcode::sink {
 public:
  /// The machine must outlive the planner. start: where it stands now.
  planner(const machine &m, planner_output &out, const gcode::pose &start = {});

  void straight_traverse(const gcode::straight &s) override;
  void straight_feed(const gcode::straight &s) override;
  gcode::probe_outcome straight_probe(const gcode::straight &s, gcode::probe_kind k) override;
  void arc_feed(const gcode::arc &a) override;
  void dwell(double seconds) override;
  void set_path_mode(gcode::path_mode m, double p_tolerance, double q_tolerance) override;
  void spindle(gcode::spindle_dir d, double rpm) override;
  void coolant(bool mist, bool flood) override;
  void change_tool(int tool) override;
  void pause(bool optional) override;
  void message(std::string_view text) override;
  void debug(std::string_view text) override;
  void warning(const gcode::error &w) override;
  void source_line(const std::string &file, int line) override;

  const plan_summary &summary() const noexcept { return sum_; }
  /// The machine stands at `p` (machine units), elsewhere than the last
  /// segment ended (a hold, an abort, a jog): the next segment starts
  /// there, from rest.
  void set_position(const gcode::pose &p);
  /// Where the work offset in force comes from (the interpreter's
  /// work_offset()); without it work extents are machine extents.
  void work_offset_from(std::function<gcode::pose()> f) { work_offset_ = std::move(f); }

 private:
  struct speed {
    bool rapid;
    double feed_per_s;  // units/s; 0: see seconds
    double seconds;     // inverse time: the segment lasts this long
  };
  /// checked: end is known within the soft limits (an arc's chords are
  /// checked before the first). probe: a probing segment, given to
  /// out_.probe() (its answer in *result). False: less than a step, nothing planned.
  bool line_to(const gcode::pose &end, const speed &sp, bool checked = false,
               const gcode::probe_kind *probe = nullptr, probe_result *result = nullptr);
  void check_limits(const gcode::pose &p) const;
  [[noreturn]] void fail(const std::string &what) const;

  const machine &m_;
  planner_output &out_;
  double ppu_;  // path units per machine unit
  gcode::pose pos_;
  std::array<double, x4step::axes> prev_dir_{};  // the last segment's move per motor, machine units
  std::uint32_t prev_top_ = 0;                   // its top speed, path units/s
  bool stop_next_ = true;                        // the next segment starts from rest
  bool exact_stop_ = false;                      // G61.1
  double deviation_;
  std::string file_;
  int line_ = 0;
  plan_summary sum_;
  std::function<gcode::pose()> work_offset_;
};

/// Reads a whole program and plans it into out: the machine's units and
/// tool table, the program starting where the machine stands (start) with
/// the offsets and stored positions `coords` (a parameter file's, params.hpp).
/// Throws gcode::error on the first line refused, by the interpreter or
/// by the planner (a soft limit, a move the kernel cannot take). If
/// `coords_after` is given, it receives them as the program left them.
plan_summary plan_program(const machine &m, std::istream &in, const std::string &name, planner_output &out,
                          const gcode::pose &start = {}, const gcode::coordinate_state &coords = {},
                          gcode::coordinate_state *coords_after = nullptr);

/// The interpreter alone, in the machine's units: every error but the
/// planner's (which need the start position), without planning.
void check_program(const machine &m, std::istream &in, const std::string &name);

}  // namespace x4step::machine

#endif
