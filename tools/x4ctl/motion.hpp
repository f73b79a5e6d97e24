// SPDX-License-Identifier: GPL-2.0
// x4ctl: start a move and follow it to its end, with live steps, ESC,
// signals and time limits. Shared by the interpreter and the subcommands.
#ifndef X4CTL_MOTION_HPP
#define X4CTL_MOTION_HPP

#include <array>
#include <chrono>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "io.hpp"
#include "show.hpp"

namespace x4ctl {

using steady = std::chrono::steady_clock;
using deadline = std::optional<steady::time_point>;

/// How often a running move is looked at (keys, signals, display).
constexpr milliseconds tick{50};

/// How a move ended.
struct outcome {
  x4step::status end;      ///< status once the motors stand
  bool completed = false;  ///< a move reached its target (never for endless moves)
  std::string halted_by;   ///< why it ended early ("ESC", "time up", ...); empty if completed
  /// Completed, but a brake or stop was asked for that found the move at its
  /// end (its halted_by): a sequence of moves ends here all the same.
  std::string late_halt;
};

/// p.load(m), and p.move_endless(...), with the refusals that depend on the
/// port's settings explained: a move of axis 4 in a phase mode, a frequency
/// the step timing cannot fit. Those throw failure; other errors pass.
void load_move(port &p, const x4step::move &m);
void start_endless(port &p, x4step::axis a, x4step::direction dir, int freq_hz, milliseconds ramp);
/// p.move_to(...), the same way.
void start_goto(port &p, x4step::axis_set axes, const std::array<long, x4step::axes> &targets, bool relative);
/// p.home(...), the same way; an axis without a reference switch is refused
/// with a failure that says how to name one.
void start_home(port &p, x4step::axis a, const x4step::homing &h);

/// Loads and starts m and follows it until it ends. ESC, Ctrl-C, a brake
/// request or the deadline brake it; a stop request stops it.
outcome run_move(port &p, console &con, const x4step::move &m, deadline until = std::nullopt);

/// A sequence of moves, as in the X4Step manual's first example (X4Load,
/// X4Start, X4Load while the move runs, X4Start once X4GetState is 0):
/// each move is loaded while the one before it runs, and started the moment
/// that one ends, with no pause for planning. start_moves loads and starts
/// moves[0] and preloads moves[1]; before anything moves, it refuses (with
/// failure) a move the port's settings do not allow.
void start_moves(port &p, const std::vector<x4step::move> &moves);

/// Called when moves[index] has ended, after the next move (if this one
/// completed) has been started and the one after it preloaded.
using move_ended = std::function<void(std::size_t index, const outcome &o)>;

/// Follows the moves that start_moves started to their end: the outcome of
/// each move that ran. A move that does not complete (or has a late_halt)
/// ends the sequence, and the moves after it are not started. A refused
/// preload brakes the running move and throws.
std::vector<outcome> follow_moves(port &p, console &con, const std::vector<x4step::move> &moves,
                                  const move_ended &ended = {});

/// Starts an endless move and follows it until it is braked.
outcome run_endless(port &p, console &con, x4step::axis a, x4step::direction dir, int freq_hz,
                    milliseconds ramp, deadline until = std::nullopt);

/// Follows whatever runs on p, as run_move does after starting; target
/// (the loaded steps) decides completed, and the progress bar.
outcome follow(port &p, console &con, const std::optional<step_counts> &target, deadline until);

/// How the axes' own moves (goto, home) ended.
struct axes_outcome {
  x4step::axes_status end;  ///< once the axes stand
  std::string halted_by;    ///< who halted some of them ("ESC", "brake request", ...); empty if nobody
};

/// Follows the axes until none of them runs. ESC, Ctrl-C or the
/// deadline brake them; brake and stop requests halt those of them they name.
axes_outcome follow_axes(port &p, console &con, x4step::axis_set axes, deadline until = std::nullopt);

/// "done: 1000 800 600 400" or "halted (ESC) at 412 of 1000 steps: 412 330 247 165".
std::string describe(const outcome &o, const std::optional<step_counts> &target);

/// brake() and stop() that accept finding the move ended already.
void brake_quietly(port &p);
void stop_quietly(port &p);

/// Waits up to d on the port's clock for a key or signal (key::none if
/// none came). A simulated port in virtual time: d passes there at once,
/// or, paced (a wait that only Ctrl-C ends), as on the wall clock.
key pause(port &p, console &con, milliseconds d, bool paced = false);

/// The deadline t from now on the port's clock; none without t.
deadline deadline_in(const port &p, const std::optional<milliseconds> &t);

/// An endless move (jog, M+, M-, T) that nothing would end, what (the
/// command) names it: a simulated port in virtual time without a time,
/// a terminal, a brake key script or (toward: the axis and direction of a
/// jog) a limit switch input ahead. Throws usage_error naming the ways.
void check_endless_ends(
    const port &p, const console &con, bool timed, const std::string &what,
    const std::optional<std::pair<x4step::axis, x4step::direction>> &toward = std::nullopt);

/// Redraws the live line of a terminal.
void draw_live(console &con, const std::string &line);

/// The steps of a move as the status reports them.
step_counts steps_of(const x4step::move &m);

/// The index of the axis with the longest path (0..3; the first of equals).
int leader_index(const step_counts &steps);

}  // namespace x4ctl

#endif  // X4CTL_MOTION_HPP
