// SPDX-License-Identifier: LGPL-2.1-or-later
/**
 * @file params.hpp
 * @brief The parameter file (issue 30): the machine state that outlives a
 *        command — work offsets G54..G59.3, the active system, the G28 and
 *        G30 positions and the G92 offset — in LinuxCNC's .var format and
 *        numbering, so that a LinuxCNC user recognises it.
 *
 * The machine file names it (`[RS274NGC] PARAMETER_FILE`, relative to
 * the machine file's directory). One line per parameter, "NUMBER VALUE"
 * (LinuxCNC writes "5221\t0.000000"), values in the machine's units
 * (degrees for A B C):
 *
 *   5161..5166  G28 position X Y Z A B C      (G28.1 stores it)
 *   5181..5186  G30 position X Y Z A B C      (G30.1)
 *   5210        1 while a G92 offset applies
 *   5211..5216  G92 offset X Y Z A B C
 *   5220        the active system, 1 (G54) .. 9 (G59.3)
 *   5221..5226  G54 X Y Z A B C; 5241.. G55, 5261.. G56, ..., 5381.. G59.3
 *                (5201 + 20 x system)
 *
 * Other numbers in the file (LinuxCNC's U V W and R, user parameters)
 * are kept as they are when x4step writes it. A missing file is all
 * zeros (G54 active); a line that is no "NUMBER VALUE" is refused with
 * file:line.
 *
 * Writes are atomic and safe with several writers: an update takes an
 * exclusive flock() on "FILE.lock" (beside it, opened read-only so that
 * another user's lock file serves too), reads the file, changes it,
 * writes "FILE.XXXXXX" in the same directory with the old file's mode,
 * fsyncs it, renames it over FILE and fsyncs the directory. A reader (no
 * lock) sees the old file or the new one, never half of one; two updates
 * never lose each other's change. Numbers are read and written in the C
 * format whatever the program's locale; a line with anything after its
 * value, a number outside 1..5602 or one given twice is refused. Every
 * group is written with LinuxCNC's nine axes (U V W as found, else 0), as
 * LinuxCNC refuses a file that lacks one. On a kernel without file locks
 * (flock() ENOSYS) updates go unlocked; the rename still keeps them whole.
 */
#ifndef X4STEP_PARAMS_HPP
#define X4STEP_PARAMS_HPP

#include <functional>
#include <map>
#include <stdexcept>
#include <string>

#include "gcode.hpp"

namespace x4step::machine {

/// A parameter file that cannot be read or written: what() names the
/// file (and the line) and what to do.
class parameter_error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Every parameter of a file, by number (its text's values).
using parameters = std::map<int, double>;

/// The coordinate state within parameters (the numbers above), and back.
gcode::coordinate_state coordinates_of(const parameters &p);
void set_coordinates(parameters &p, const gcode::coordinate_state &c);

/// What a command changed (before -> after), each value on its own, put
/// into `into` (the file's state now: another command may have changed
/// other values meanwhile, which stay).
void apply_changes(gcode::coordinate_state &into, const gcode::coordinate_state &before,
                   const gcode::coordinate_state &after);

/// "5221\t0.000000\n" lines, by number: LinuxCNC's format.
std::string format_parameters(const parameters &p);
/// Reads that text (blank lines allowed); `name` for errors.
parameters parse_parameters(const std::string &text, const std::string &name);

class parameter_file {
 public:
  explicit parameter_file(std::string path) : path_(std::move(path)) {}
  const std::string &path() const noexcept { return path_; }

  /// Its parameters now (none if the file does not exist).
  parameters read_all() const;
  /// The coordinate state it holds (zeros, G54, if the file does not exist).
  gcode::coordinate_state read() const { return coordinates_of(read_all()); }

  /// Under the lock: reads it, lets `change` change the state, writes it
  /// back (only if it changed); returns the state written.
  gcode::coordinate_state update(const std::function<void(gcode::coordinate_state &)> &change) const;
  /// Under the lock: the state becomes c (other parameters kept).
  void write(const gcode::coordinate_state &c) const {
    update([&c](gcode::coordinate_state &s) { s = c; });
  }

 private:
  std::string path_;
};

}  // namespace x4step::machine

#endif  // X4STEP_PARAMS_HPP
