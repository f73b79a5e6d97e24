// SPDX-License-Identifier: LGPL-2.1-or-later
// The simulated port's names and settings (README: "Try it without a
// parallel port"). Internal to libx4step.
#ifndef X4STEP_SIM_OPTIONS_HPP
#define X4STEP_SIM_OPTIONS_HPP

#include <cstdint>
#include <string>
#include <vector>

#include "machine.hpp"

namespace x4step::sim {

enum class time_mode {
  real,     ///< events at their times, by a thread, as the hrtimer
  virtual_  ///< as fast as possible: the library's waits advance the clock
};

/// A key event at a time: a set-1 code as the module's handler sees it
/// (make code 1..127 for a press, + 128 for its release).
struct scripted_key {
  std::uint64_t t_ns;  ///< engine time: since the port was opened
  unsigned code;
};

struct options {
  time_mode time = time_mode::real;
  std::string vcd;                 ///< a VCD file of every pin change, "" none
  std::vector<scripted_key> keys;  ///< X4STEP_SIM_KEYS, in time order
  bool terminal_keys = false;      ///< X4STEP_SIM_KEYS=tty: keys from stdin, a terminal
  machine model;                   ///< X4STEP_SIM_MACHINE and X4STEP_SIM_INPUTS
  std::string state;               ///< X4STEP_SIM_STATE: positions kept between programs, "" none
};

/// The set-1 make code of a key name (esc, enter, space, tab, backspace,
/// up, down, left, right, home, end, pgup, pgdn, insert, delete, or one
/// character of the main keyboard: a..z, 0..9, - = [ ] ; ' ` \ , . /),
/// as the module's default key map gives it; 0 if none.
unsigned key_code(const std::string &name);
/// "TIME:KEY,...": TIME as 250ms or 1.5s, KEY a name (a press and its
/// release) or a code 1..255 (that event alone). Throws an error naming
/// the entry and the good spellings.
std::vector<scripted_key> parse_keys(const std::string &spec);

/// A name meant for the simulator, good or bad: "sim" and "sim:N", and
/// names that start with "sim" without a '/' ("sim0", "simx": refused by
/// port_number(); a device node there is opened as "./sim0").
bool is_sim_name(const std::string &name);
/// The port number of "sim" (0) or "sim:0".."sim:3"; throws an error
/// naming the good spellings otherwise.
int port_number(const std::string &name);
/// X4STEP_SIM_TIME (virtual|real, default real), X4STEP_SIM_VCD,
/// X4STEP_SIM_KEYS (a script, "tty": the terminal's keys, "none"),
/// X4STEP_SIM_MACHINE, X4STEP_SIM_INPUTS and X4STEP_SIM_STATE; throws an error naming the
/// variable (or the machine file and line) and what to fix.
options options_from_env();
/// X4STEP_SIM=1: LPT1..4 are sim:0..3; unset, "" or "0": the devices.
/// Any other value throws an error naming it and the good ones.
bool env_wants_sim();

}  // namespace x4step::sim

#endif  // X4STEP_SIM_OPTIONS_HPP
