// SPDX-License-Identifier: LGPL-2.1-or-later
// The simulated port's names and settings (README: "Try it without a
// parallel port"). Internal to libx4step.
#ifndef X4STEP_SIM_OPTIONS_HPP
#define X4STEP_SIM_OPTIONS_HPP

#include <string>

#include "machine.hpp"

namespace x4step::sim {

enum class time_mode {
  real,     ///< events at their times, by a thread, as the hrtimer
  virtual_  ///< as fast as possible: the library's waits advance the clock
};

struct options {
  time_mode time = time_mode::real;
  std::string vcd;  ///< a VCD file of every pin change, "" none
  machine model;    ///< X4STEP_SIM_MACHINE and X4STEP_SIM_INPUTS
};

/// "sim" or "sim:..." (a name meant for the simulator, good or bad).
bool is_sim_name(const std::string &name);
/// The port number of "sim" (0) or "sim:0".."sim:3"; throws an error
/// naming the good spellings otherwise.
int port_number(const std::string &name);
/// X4STEP_SIM_TIME (virtual|real, default real), X4STEP_SIM_VCD,
/// X4STEP_SIM_MACHINE and X4STEP_SIM_INPUTS; throws an error naming the
/// variable (or the machine file and line) and what to fix.
options options_from_env();
/// X4STEP_SIM is set to anything but "" or "0": LPT1..4 are sim:0..3.
bool env_wants_sim();

}  // namespace x4step::sim

#endif  // X4STEP_SIM_OPTIONS_HPP
