// SPDX-License-Identifier: GPL-2.0
// x4ctl on a simulated port (--sim, X4STEP_SIM=1, -d sim:N): it lives in
// this process, so each x4ctl has a fresh one; its clock may be virtual.
#ifndef X4CTL_SIM_HPP
#define X4CTL_SIM_HPP

#include <chrono>
#include <string>

#include "x4step.hpp"

namespace x4ctl {

/// A simulated port's name: "sim", "sim:N" (or a misspelling of one, which
/// the library refuses saying so): no device node.
bool is_sim_device(const std::string &dev);

/// The library's refusal of a simulated port's name or settings, without
/// the general "is x4step loaded" that follows it.
std::string sim_error_text(const x4step::error &e);

/// Why a command that acts on another x4ctl's moves (brake, stop, halt) or
/// follows them (monitor, watch) cannot on a simulated port, and what does.
std::string sim_elsewhere_text(const std::string &dev, const char *command);

/// A setting made by a one-shot x4ctl on a simulated port ends with it.
std::string sim_forgets_text(const std::string &dev);

/// X4STEP_SIM_STATE: the file that keeps the simulated port's positions
/// and synchronization between x4ctl runs; "" none.
std::string sim_state_file();

/// A brake key comes without a terminal: X4STEP_SIM_KEYS holds a script.
bool sim_keys_scripted();

/// A simulated port with a machine (X4STEP_SIM_MACHINE): its switches are
/// named the engine's reference and limit inputs, as 'x4ctl limits' would
/// have set them once on the module (a simulated port keeps no settings
/// between x4ctl runs). Nothing for other ports.
void wire_machine_switches(x4step::controller &c);

}  // namespace x4ctl

#endif  // X4CTL_SIM_HPP
