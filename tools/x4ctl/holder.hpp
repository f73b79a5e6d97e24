// SPDX-License-Identifier: GPL-2.0
// x4ctl: who holds a port. The module brakes a move when its controller
// closes the device, so a one-shot `x4ctl move` keeps the port in a
// background process until the move ends, and `x4ctl brake` asks that
// process (by signal) to brake.
#ifndef X4CTL_HOLDER_HPP
#define X4CTL_HOLDER_HPP

#include <sys/types.h>

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "motion.hpp"
#include "ports.hpp"

namespace x4ctl {

/// Looks through /proc for the controller of device (processes of other
/// users stay hidden unless we may read their /proc/PID/fd).
std::optional<holder> find_controller(const std::string &device);

/// The program that has /dev/parportN open, N being the parport of the
/// x4step device at path (ppdev's users, when ppdev holds the port).
std::optional<holder> parport_user(const std::string &device);

/// The parport driver that has claimed parportN now, as the parport core
/// names it ("x4step", "lp", "ppdev0", ...); "" when none has, or unknown.
std::string parport_claimant(int parport);

/// The /dev/x4stepN nodes there are, by N.
std::vector<std::string> x4step_devices();

/// Forks: the parent prints the child's PID and exits 0 at once, without
/// closing the port (no destructors run); the child leaves the terminal
/// and runs follow_it on a console without terminal, which follows what
/// runs on the port (and starts what comes after it) until it ends; then
/// the child returns.
void hold_in_background(port &p, const std::function<void(console &)> &follow_it);

}  // namespace x4ctl

#endif  // X4CTL_HOLDER_HPP
