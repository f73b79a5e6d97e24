// SPDX-License-Identifier: GPL-2.0
// x4ctl: the command line: one config struct for all commands, and the
// parser that fills it from the commands' records (command.hpp).
#ifndef X4CTL_CLI_HPP
#define X4CTL_CLI_HPP

#include <array>
#include <chrono>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "x4step.hpp"

namespace x4ctl {

/// A mistake in the command line or in a script: exit status 2.
class usage_error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The port or the machine did not do what was asked: exit status 1.
class failure : public std::runtime_error {
 public:
  explicit failure(const std::string &what, int err = 0) : std::runtime_error(what), err_(err) {}
  int err() const { return err_; }  ///< the errno behind it; 0: none known

 private:
  int err_;
};

struct subcommand;
/// x4ctl without a command: the test program (command.hpp).
const subcommand &main_command();

/// x4ctl path: what a line of the path does not say.
struct path_defaults {
  unsigned speed = 1000;   ///< steps/s along the path
  unsigned accel = 10000;  ///< steps/s^2
  double deviation = 0.5;  ///< junction deviation, steps
};

/// Everything the command line says.
struct config {
  const subcommand *cmd = &main_command();  ///< the command given
  int lpt = 1;
  std::string device;  ///< -d PATH; empty: the device of lpt
  bool sim = false;    ///< --sim: the simulated port sim:lpt-1
  bool help = false;   ///< --help: show the help of cmd
  bool version = false;
  const subcommand *topic = &main_command();  ///< help COMMAND

  x4step::move move;  ///< move, sweep (the distance on axis): steps, freq, ramp
  /// move --then: the moves after move, each with its freq and ramp; started
  /// one after the other, each preloaded while the one before it runs.
  std::vector<x4step::move> then;
  x4step::axis axis = x4step::axis::x;  ///< jog, sweep
  x4step::direction dir = x4step::direction::positive;
  std::optional<std::chrono::milliseconds> time;  ///< jog: brake after; out: hold for
  bool wait = false;
  int sweep_from = 0, sweep_to = 0, sweep_step = 0;

  bool json = false;       ///< --json of the reading subcommands (json.hpp)
  bool watch = false;      ///< in
  bool read_only = false;  ///< in: never take the port
  x4step::signal signal = x4step::signal::one;
  bool level = false;         ///< out
  std::vector<int> codes;     ///< keys
  std::optional<long> moves;  ///< monitor: end after this many moves
  std::optional<long> count;  ///< watch: end after this many events
  std::string file = "-";     ///< run; "-" is stdin
  bool check = false;         ///< run: check the script, move nothing
  bool echo = false;          ///< run: print each command

  /// timing: the times to change (read, modify, write); none given: only show.
  std::optional<std::chrono::nanoseconds> pulse, space, dir_setup, dir_hold;
  std::optional<x4step::output_mode> mode;  ///< mode: the one to set; none: only show

  // Positioning. c.axis is the axis of profile and home.
  x4step::axis_set axes;                     ///< goto, zero, halt, limits: the axes named
  std::array<long, x4step::axes> targets{};  ///< goto: coordinates (or distances) of the axes named
  bool relative = false;                     ///< goto: targets are distances
  bool no_wait = false;                      ///< goto: leave the moves to a background x4ctl
  /// profile: the values to change; none given: only show.
  std::optional<unsigned> v0, ve, vm, a0, ae;
  x4step::homing homing;                ///< home
  long at = 0;                          ///< zero: the coordinate to set
  std::optional<int> ref, plus, minus;  ///< limits AXIS: the inputs to name (0: none)
  std::optional<unsigned> nc;           ///< limits: normally closed inputs (bit k: input k+1)
  bool halt_stop = false;               ///< halt: stop at once rather than brake

  path_defaults path;               ///< path (c.file: the path, "-" stdin; c.check: only check)
  unsigned override_percent = 100;  ///< path, gcode: feed override
  std::string machine;              ///< --machine (machine_path(): else $X4STEP_MACHINE, /etc/...)
  bool no_pause = false;            ///< gcode, mdi: M0/M1/M6 do not wait for the operator
  std::vector<std::string> blocks;  ///< mdi: the blocks, one line each
  std::string svg;                  ///< gcode --svg: the plot's file; empty: none

  // Machine units (home, jog and panel with a machine file; c.machine).
  std::string letters;             ///< home: the axes' letters (empty: all); jog: the axis' (c.dir its way)
  std::optional<double> feed;      ///< jog, panel --feed: units/min
  std::optional<double> distance;  ///< jog --distance: units, > 0; none: to the soft limit
  std::vector<std::pair<char, double>> work;  ///< touch-off: LETTER=VALUE, work coordinates
  int work_system = -1;                       ///< touch-off --system: 0 G54 .. 8 G59.3; -1 the active one
  /// home and jog in machine units: --machine or axis letters given.
  bool machine_units() const { return !machine.empty() || !letters.empty(); }

  // machine check FILE... / machine import INI [HAL] [-o FILE]
  std::string machine_action;      ///< check or import
  std::vector<std::string> files;  ///< check: the machine files; import: INI [HAL]
  std::string output;              ///< import -o: the machine file to write; empty: standard output
};

/// Parses and checks the whole command line (values too, without a device).
/// Throws usage_error.
config parse_args(const std::vector<std::string> &args);

/// The help of a command (main_command(): the program's, with every command).
std::string help_text(const subcommand &c);
/// The command's name; "x4ctl" for main_command().
std::string name_of(const subcommand &c);
std::string version_text();

/// /dev/x4stepN of -p, or -d.
std::string device_of(const config &c);

/// A whole decimal number, optionally signed; throws usage_error naming what.
long parse_number(const std::string &text, const std::string &what);

/// The library's sentence for an X4Step error code.
std::string message(x4step::errc e);

/// Ramp when none is given: 50 ms, but never more than the frequency allows.
int default_ramp_ms(int freq_hz);

constexpr int default_freq_hz = 1000;

/// Whether the command line, or X4STEP_SIM, asks for a simulated port.
bool sim_wanted(const config &c);

}  // namespace x4ctl

#endif  // X4CTL_CLI_HPP
