// SPDX-License-Identifier: LGPL-2.1-or-later
/**
 * @file machine.hpp
 * @brief The machine file (issue 20): what a machine is, in real units —
 *        which motor drives which axis, steps per unit, speeds, soft limits,
 *        homing, output pins, the port. Every key: machines/README.md.
 *
 * INI text, LinuxCNC's section and key names where LinuxCNC has one ([TRAJ]
 * LINEAR_UNITS, [AXIS_X] MAX_VELOCITY, [JOINT_0] SCALE, HOME_SEARCH_VEL,
 * ...), so a LinuxCNC user carries the numbers over; x4step's own settings
 * in [X4STEP]. A file is read whole and checked whole: every bad value,
 * unknown section or key (with "did you mean KEY?" for a near miss),
 * missing key or contradiction is reported in one pass, each as
 * "file:line:col: [SECTION] KEY: what to fix", and no machine is made.
 * LinuxCNC's own sections and keys that x4step does not use are accepted
 * and listed in machine::warnings.
 */
#ifndef X4STEP_MACHINE_HPP
#define X4STEP_MACHINE_HPP

#include <algorithm>
#include <array>
#include <cmath>
#include <iosfwd>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "gcode.hpp"

namespace x4step::machine {

/// A refused machine file: every mistake found in it, in file order.
/// what() is one line per mistake, "file:line:col: [SECTION] KEY: message"
/// ("file:line:" without a column, "file:" without a line).
class error : public std::runtime_error {
 public:
  struct problem {
    int line = 0, col = 0;  ///< 0: none
    std::string key;        ///< "[SECTION] KEY", "[SECTION]" or ""
    std::string message;
  };
  /// One mistake.
  error(const std::string &file, int line, const std::string &key, const std::string &message);
  /// Several (at least one), sorted by line and column here.
  error(const std::string &file, std::vector<problem> problems);
  /// The first mistake's line, column and key.
  int line() const noexcept { return problems_.front().line; }
  int col() const noexcept { return problems_.front().col; }
  const std::string &key() const noexcept { return problems_.front().key; }
  const std::vector<problem> &problems() const noexcept { return problems_; }
  /// Each mistake as its line of what().
  std::vector<std::string> lines() const;

 private:
  std::string file_;
  std::vector<problem> problems_;
};

/// Homing of one axis (LinuxCNC's HOME_* keys; off when HOME_SEARCH_VEL is 0).
struct homing {
  bool enabled = false;
  int input = 0;          ///< the REF switch: input 1..5 (X4GetIn bit 0..4)
  double search_vel = 0;  ///< units/s, its sign the direction toward the switch
  double latch_vel = 0;   ///< units/s, signed, opposite to search_vel: backs off the switch
  double offset = 0;      ///< the switch's position, machine units
  double home = 0;        ///< where the axis goes after homing, machine units
  int sequence = 0;       ///< order: lower first, equal together
};

/// One axis letter of the machine.
struct axis {
  int motor = 0;                        ///< 0..3: motor 1..4 (the port's clock/direction pair)
  double scale = 0;                     ///< steps per unit (mm, inch or degree); negative reverses
  double min_limit = 0, max_limit = 0;  ///< soft limits, machine units
  double max_velocity = 0;              ///< units/s
  double max_acceleration = 0;          ///< units/s^2
  homing home;
};

/// An output pin the machine uses (signal 1 on pin 1, signal 2 on pin 14).
enum class pin { none = 0, pin1 = 1, pin14 = 14 };

/// The port's output mode ([X4STEP] OUTPUT_MODE, as `x4ctl mode`): clock-dir
/// (also written step-dir), smc-phase or smc-hold.
enum class output_mode { clock_dir, smc_phase, smc_hold };

struct machine {
  std::string name;           ///< [EMC] MACHINE
  std::string port = "LPT1";  ///< LPT1..LPT4
  output_mode mode = output_mode::clock_dir;
  gcode::units units = gcode::units::mm;
  /// By axis letter, gcode::X .. gcode::C; empty: the machine has no such axis.
  std::array<std::optional<axis>, gcode::n_axes> axes;
  double max_linear_velocity = 0;  ///< units/s along the path; 0: only the axes' limits
  double arc_tolerance = 0;        ///< most a chord may leave the arc, machine units
  double junction_deviation = 0;   ///< GRBL's, machine units
  pin spindle = pin::none, flood = pin::none, mist = pin::none;
  std::string tool_table;  ///< [EMCIO] TOOL_TABLE, relative to the file's directory made absolute
  /// What the file gives that x4step accepts but does not use (LinuxCNC's
  /// own sections and keys), each listed once: "file: ignored ...".
  std::vector<std::string> warnings;
  /// [RS274NGC] PARAMETER_FILE, made absolute as tool_table; empty: none
  /// (offsets last one command): params.hpp.
  std::string parameter_file;
  /// [TRAJ] NO_FORCE_HOMING = 1: programs may move axes not homed.
  bool no_force_homing = false;
  /// [X4STEP] PROBE_INPUT: the touch probe's input 1..5 for G38.x (0: none);
  /// PROBE_NC = 1: normally closed (active while low).
  int probe_input = 0;
  bool probe_nc = false;
};

/// Whether `units` lies within the axis' soft limits (a billionth of the
/// limit's size beyond counts as within). The planner asks it for every
/// point it plans, so it makes no words: beyond_soft_limit says why not.
inline bool within_soft_limits(const axis &ax, double units) noexcept {
  auto slack = [](double limit) { return 1e-9 * std::max(1.0, std::fabs(limit)); };
  return units >= ax.min_limit - slack(ax.min_limit) && units <= ax.max_limit + slack(ax.max_limit);
}

/// Why `units` lies beyond the soft limits of axis a (gcode::X ..), e.g.
/// "X 30 is beyond the soft limit [AXIS_X] MAX_LIMIT 24"; empty if within.
std::string beyond_soft_limit(const machine &m, size_t a, double units);

/// The closest of `names` to `word` within a small edit distance (a
/// misspelling: letters swapped, missing, extra or wrong), else "".
std::string nearest(const std::string &word, const std::vector<std::string> &names);

/// Reads and checks a machine file; `name` is the file name errors give.
machine read(std::istream &in, const std::string &name);
/// The same, opening the file (error at line 0 if it cannot be read).
machine read_file(const std::string &path);

}  // namespace x4step::machine

#endif
