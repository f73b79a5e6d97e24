// SPDX-License-Identifier: GPL-2.0
// x4ctl gcode: a G-code part program on a machine (lib/machine), checked
// whole, then streamed to the module's path queue. The check from where
// the machine stands and the run are shared with the panel's cycle start.
#ifndef X4CTL_GCODE_CMD_HPP
#define X4CTL_GCODE_CMD_HPP

#include <array>
#include <cstdint>
#include <functional>
#include <string>

#include "cli.hpp"
#include "machine_io.hpp"
#include "path_stream.hpp"
#include "planner.hpp"

namespace x4ctl {

class toolpath_plot;
class progress_meter;

/// x4ctl gcode: check (and with --check stop there), then run.
int cmd_gcode(const config &c);
/// x4ctl mdi: the blocks as a one-line program (c.blocks, then M2), as cmd_gcode.
int cmd_mdi(const config &c);

/// A program: a file's text or mdi's blocks, in memory: read once, so what
/// was checked is what runs even if the file changes meanwhile (a few MB
/// for a large CAM file).
struct program {
  std::string name;  // what errors give: the file, or "mdi"
  std::string text;
  bool is_file = true;
  std::string by;  // the command that runs it if not gcode or mdi ("panel")
  std::string command() const { return !by.empty() ? by : is_file ? "gcode" : "mdi"; }
  // Before an error: a file's names the command; mdi's names itself ("mdi:2:7: ...");
  // the panel's message line names none (FILE:LINE:COLUMN: ...).
  std::string prefix() const { return is_file && by.empty() ? "gcode: " : ""; }
  /// Throws failure if the file cannot be read.
  static program from_file(const std::string &file);
};

/// A program found good from where the machine stands.
struct program_check {
  m::plan_summary total;
  long pauses = 0;             // M0, M1, M6: an operator at a terminal
  g::pose start{};             // where the machine stood, machine units
  g::coordinate_state coords;  // the parameter file's offsets it was planned with
};

/// Checks p whole from where the machine on ctl stands, with the parameter
/// file's offsets and the homed-first rule (an axis with a home switch the
/// program moves must be homed). Throws usage_error (FILE:LINE:COLUMN: ...)
/// or failure ("...; nothing moved").
program_check check_at_machine(const config &c, const m::machine &mc, x4step::controller &ctl,
                               const program &p);

/// "N lines, about M:SS; extents (mm, work): X 0..10 Y ...": a check on one line.
std::string check_line(const m::machine &mc, const program_check &k);

/// How a run went.
struct run_result {
  bool aborted = false;
  bool interrupted = false;              // by Ctrl-C or SIGINT
  std::array<long, x4step::axes> end{};  // motor positions, steps
  std::string end_line;                  // "gcode: done in 2:18, estimated 2:11, at X1 Y2 (mm)"
  std::string end_json;                  // the result record
};

/// Where a run shows itself: nullptr view: standard output (x4ctl gcode),
/// else the view's (x4ctl panel), with the meter for its progress line.
struct run_view {
  std_console *keys = nullptr;
  std::function<void(const x4step::path_status &, std::uint64_t done, progress_meter &)> show;
  std::function<void(const std::string &)> say;
};

/// Runs a checked program on ctl (the port prepared): the path streamed
/// with space hold/resume, ESC abort, +/- override; outputs off at the
/// end; a program that ran to its end leaves its offsets in the parameter
/// file. command begins its lines ("gcode", "mdi"; "": nothing does).
run_result run_checked(const config &c, const m::machine &mc, x4step::controller &ctl, const program &p,
                       const program_check &k, const std::string &command, bool keyboard, toolpath_plot *plot,
                       const run_view *view);

}  // namespace x4ctl

#endif  // X4CTL_GCODE_CMD_HPP
