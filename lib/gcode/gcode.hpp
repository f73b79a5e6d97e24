// SPDX-License-Identifier: LGPL-2.1-or-later
/**
 * @file gcode.hpp
 * @brief The G-code interpreter: RS274/NGC text in, canonical machining
 *        commands out (issue 20, first slice).
 *
 * The subset CAM post-processors for GRBL and LinuxCNC emit, with the modal
 * rules of the NIST RS274/NGC interpreter (version 3) as LinuxCNC applies
 * them: G0 G1 G2 G3 (IJK and R, full circles, helices, P turns), G4, G10 L2
 * and L20, G17 G18 G19, G20 G21, G28 G28.1 G30 G30.1, G38.2 G38.3 G38.4
 * G38.5 (probing, below), G40, G43 H, G43.1, G49, G53, G54..G59.3, G61
 * G61.1 G64 (P, Q), G90 G91, G90.1 G91.1, G92 G92.1, G93 G94; the drilling
 * cycles G73 G81 G82 G83 G85 G89 (XY plane, G90 or G91, L repeats) with
 * G98 G99 and G80, expanded into traverses, feeds and dwells as LinuxCNC
 * expands them; M0 M1 M2 M30 M3 M4 M5 M6 M7 M8 M9; F S T N; comments ( )
 * and ;, (MSG,...), (DEBUG,...), block delete /, %. Anything else is
 * refused with an error naming file:line:column (and what to do instead
 * where there is a way), never skipped.
 *
 * Streaming: a program is read one line at a time; nothing is kept of a
 * line once it is executed. The interpreter knows nothing of motors or
 * the kernel: it calls a sink (below), in the order of the program.
 *
 * Probing (G38.2..G38.5, modal group 1 like G1): accepted and refused as
 * LinuxCNC's rs274 does: an axis word needed, a feed rate needed, G38.2
 * and G38.4 refused when the move has length zero; refused in inverse
 * time (G93, where LinuxCNC would probe at a feed left from before). The
 * sink runs the move (sink::straight_probe) and the program goes on from
 * where the machine stopped. G38.2 and G38.4 are errors when the input
 * did not change ("G38.2 move finished without making contact", as
 * LinuxCNC says it) or was already in the awaited state at the start (a
 * trip equal to the move's start: no step made); G38.3 and G38.5 are not. LinuxCNC also stores the trip in
 * #5061..#5070: this interpreter has no # parameters; a caller takes the
 * trip from the sink's call (a GRBL bridge's [PRB:...]).
 *
 * Coordinates: every position given to the sink is in machine coordinates
 * (program position + G5x offset + G92 offset + tool length offset) in the
 * machine's length unit (options::machine_units); rotary axes A B C are
 * in degrees. The offsets, the active coordinate system and the G28/G30
 * positions start as options::coordinates gives them (zero by default)
 * and live in memory for the interpreter's life; coordinates() gives them
 * back for the caller to keep (lib/machine's parameter file); the
 * position starts at options::start.
 *
 * Not installed (yet): built as a static library inside the tree, linked
 * by the tests, the bench and, through the planner (lib/machine), x4ctl.
 */
#ifndef X4STEP_GCODE_HPP
#define X4STEP_GCODE_HPP

#include <array>
#include <iosfwd>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>

namespace x4step::gcode {

/// Axes, in LinuxCNC's order: X Y Z (length) A B C (degrees).
enum axis_index { X = 0, Y, Z, A, B, C, n_axes };
using pose = std::array<double, n_axes>;

enum class units { mm, inch };
/// G17 (XY), G18 (ZX), G19 (YZ).
enum class plane { xy, zx, yz };
/// G61 exact path, G61.1 exact stop, G64 blending (with tolerances).
enum class path_mode { exact_path, exact_stop, blend };
/// G93 inverse time (1/min), G94 units per minute.
enum class feed_mode { inverse_time, units_per_minute };
enum class spindle_dir { off, cw, ccw };

/// A refused program: what() is "file:line:column: message".
class error : public std::runtime_error {
 public:
  error(std::string file, int line, int column, const std::string &message);
  const std::string &file() const noexcept { return file_; }
  int line() const noexcept { return line_; }
  int column() const noexcept { return column_; }
  /// The message alone, without the location.
  const std::string &message() const noexcept { return message_; }

 private:
  std::string file_;
  int line_, column_;
  std::string message_;
};

/// A straight move (G0 traverse, G1 feed, G28/G30 traverses, G53).
struct straight {
  pose end;
  /// Feed rate for feeds: machine units per minute, or 1/min in inverse
  /// time (then the move lasts 1/feed minutes). 0 for traverses.
  double feed;
  feed_mode mode;
};

/// A circular or helical arc (G2/G3) in the active plane. The end is the
/// full pose (the helix's travel is along the plane's normal axis, other
/// axes move linearly); the centre is in machine coordinates, on the
/// plane's first and second axes (G17: X Y, G18: Z X, G19: Y Z).
struct arc {
  pose end;
  double centre_first, centre_second;
  plane in;
  /// LinuxCNC's rotation: > 0 counter-clockwise, < 0 clockwise seen from
  /// the plane's positive normal; |turns| - 1 full circles beyond the arc
  /// to the end (end == start in the plane: |turns| full circles).
  int turns;
  double feed;
  feed_mode mode;
};

/// G38.2 (toward the workpiece, an error without contact), G38.3 (the
/// same, no error), G38.4 (away from it: stop when contact breaks, an
/// error if it does not), G38.5 (the same, no error).
enum class probe_kind { toward_or_error, toward, away_or_error, away };

/// Where a probe move stopped (machine coordinates, machine units).
struct probe_outcome {
  /// Where the machine stands after it: the interpreter goes on from here.
  pose stop;
  /// Whether the probe input changed (contact made, or broken for G38.4/5).
  bool tripped = true;
  /// Where it changed; where the move ended when it did not (LinuxCNC's
  /// #5061..#5069 in machine coordinates).
  pose trip{};
};

/// Where the canonical commands go. Every function has an empty default:
/// a sink overrides what it needs. Calls come in the program's order.
class sink {
 public:
  virtual ~sink() = default;
  virtual void straight_traverse(const straight &) {}
  virtual void straight_feed(const straight &) {}
  /// G38.2..G38.5: a feed (units per minute) to s.end that stops where
  /// the probe input changes. Runs it to its end (it starts and ends at
  /// rest) and returns where the machine stopped; the interpreter goes on
  /// from there. This default (a sink that does not move: a check, a
  /// preview) answers contact at the programmed end.
  virtual probe_outcome straight_probe(const straight &s, probe_kind) { return {s.end, true, s.end}; }
  virtual void arc_feed(const arc &) {}
  virtual void dwell(double /*seconds*/) {}
  /// The program's length unit changed (G20/G21); positions stay in machine units.
  virtual void program_units(units) {}
  virtual void select_plane(plane) {}
  /// G64 P (blend tolerance, machine units, 0 = none) Q (naive CAM tolerance).
  virtual void set_path_mode(path_mode, double /*p_tolerance*/, double /*q_tolerance*/) {}
  virtual void spindle(spindle_dir, double /*rpm*/) {}
  virtual void coolant(bool /*mist*/, bool /*flood*/) {}
  /// T: the tool to have ready; M6: change to it (a pause for the operator).
  virtual void select_tool(int) {}
  virtual void change_tool(int) {}
  /// The tool length offset now in force (machine units per axis).
  virtual void tool_length_offset(const pose &) {}
  /// M0 (optional false) and M1 (optional true): wait for the operator.
  virtual void pause(bool /*optional*/) {}
  /// (MSG, text): to show the operator when the line runs.
  virtual void message(std::string_view) {}
  /// (DEBUG, text): LinuxCNC shows it as a message too (this default).
  virtual void debug(std::string_view text) { message(text); }
  /// Something accepted that the operator should know of (G43 H without
  /// a tool table): what() is "file:line:column: warning: ...". It comes
  /// with the line's other commands, before them.
  virtual void warning(const error & /*what*/) {}
  /// M2 or M30 (or the closing %): nothing is read after it.
  virtual void program_end(bool /*m30*/) {}
  /// The line whose commands follow (before the first of them): a sink
  /// that refuses a command later (a planner's soft limit) names it.
  virtual void source_line(const std::string & /*file*/, int /*line*/) {}
};

/// What LinuxCNC keeps in its parameter file (.var) between programs: the
/// work offsets, the active system, the G28/G30 positions and the G92
/// offset; machine coordinates, machine units (degrees for A B C).
struct coordinate_state {
  std::array<pose, 9> g5x{};  ///< G54, G55 ... G59, G59.1, G59.2, G59.3
  int system = 0;             ///< the active one: 0 G54 .. 8 G59.3
  pose g28{}, g30{};          ///< G28.1 and G30.1 store these
  pose g92{};                 ///< G92's offset (G92.1 zeroes it)
  bool operator==(const coordinate_state &o) const {
    return g5x == o.g5x && system == o.system && g28 == o.g28 && g30 == o.g30 && g92 == o.g92;
  }
  bool operator!=(const coordinate_state &o) const { return !(*this == o); }
  /// From work (program) to machine coordinates: the active system's
  /// offset plus G92's (no tool length offset).
  pose work_offset() const {
    pose p{};
    for (size_t a = 0; a < p.size(); a++) p[a] = g5x.at(size_t(system))[a] + g92[a];
    return p;
  }
};

struct options {
  /// The unit of every length given to the sink.
  units machine_units = units::mm;
  /// The program's unit until a G20/G21 (LinuxCNC without an INI: mm).
  units initial_units = units::mm;
  /// Honour block delete: skip lines that start with '/'.
  bool block_delete = false;
  /// Where the machine stands at the start, machine coordinates and units.
  pose start{};
  /// The offsets and stored positions to start with (machine units).
  coordinate_state coordinates{};
};

/// One tool: length offsets (G43 H) in machine units.
struct tool {
  pose offset{};
  double diameter = 0;
};

/// A LinuxCNC tool table file ("T1 P1 Z0.5 D0.125 ;comment" per line),
/// its values in `in` units, converted to the machine's.
std::map<int, tool> read_tool_table(const std::string &path, units in, units machine);

class interpreter {
 public:
  explicit interpreter(sink &out, options o = {});
  ~interpreter();
  interpreter(const interpreter &) = delete;
  interpreter &operator=(const interpreter &) = delete;

  /// The tools G43 H takes lengths from. Without a table (never set), G43
  /// H applies length 0 with a warning to the sink; with one, a tool
  /// missing from it is an error.
  void set_tool_table(std::map<int, tool> table);

  /// Runs a program to its end (M2, M30, closing % or end of file), line by
  /// line; `name` is the file name errors give. A UTF-8 byte-order mark
  /// at its start is skipped. Throws gcode::error on the
  /// first line that is refused: nothing of that line reaches the sink.
  /// A program must end with M2/M30 or %: else an error at its end.
  void run(std::istream &in, const std::string &name);
  /// The same, opening a file (error "cannot open" at line 0).
  void run_file(const std::string &path);
  /// Runs a whole program into a sink that drops everything: the check to
  /// make before any motion (the interpreter's state is left untouched).
  void check(std::istream &in, const std::string &name) const;

  /// One line (MDI, a streaming protocol): executed at once. Returns false
  /// once the program ended (M2/M30).
  bool execute_line(std::string_view line, const std::string &name, int line_no);

  /// The current position, machine coordinates, machine units.
  pose position() const;
  /// The machine stands elsewhere than programmed (after a hold, an
  /// abort or a probe): the next move starts from `machine` (machine
  /// coordinates and units). Offsets and modes stay.
  void set_position(const pose &machine);
  /// The offsets, the active system and the stored positions now
  /// (machine units): what a parameter file keeps.
  coordinate_state coordinates() const;
  /// From work to machine coordinates now (coordinates().work_offset()),
  /// cheaply: a sink may ask it for every point.
  pose work_offset() const;
  units program_units() const noexcept;

  /// Another program changed the offsets (a parameter file written by
  /// another tool between lines): they become `c`; the modes stay.
  void set_coordinates(const coordinate_state &c);

  /// The modes in force, as GRBL's $G reports them.
  struct modes {
    int motion = 800;  ///< G code x 10: 0 G0, 10 G1, 20, 30, 382 G38.2 ..., 800 G80
    int system = 0;    ///< 0 G54 .. 8 G59.3
    plane in = plane::xy;
    units program = units::mm;
    bool incremental = false;
    feed_mode feed_in = feed_mode::units_per_minute;
    spindle_dir spindle = spindle_dir::off;
    bool mist = false, flood = false;
    int tool = 0;
    double feed = 0, speed = 0;  ///< as programmed (program units / min)
  };
  modes modal() const;

 private:
  struct impl;
  std::unique_ptr<impl> p_;
};

}  // namespace x4step::gcode

#endif
