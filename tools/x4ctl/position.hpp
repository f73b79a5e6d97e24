// SPDX-License-Identifier: GPL-2.0
// x4ctl: the positioning subcommands (the ProStep4 model) on an open port:
// profile, limits, zero, goto, home. They take a port and a console, so
// that the host tests run them on a simulated port.
#ifndef X4CTL_POSITION_HPP
#define X4CTL_POSITION_HPP

#include <array>
#include <ostream>

#include "cli.hpp"
#include "io.hpp"

namespace x4ctl {

using coordinates = std::array<long, x4step::axes>;

/// `x4ctl profile`: changes the values c gives (read, modify, write) and
/// writes the profile the axis then has. A profile whose values do not fit
/// together throws usage_error, and nothing changes.
void profile_command(port &p, const config &c, std::ostream &out);

/// `x4ctl limits`: names the inputs c gives (read, modify, write) and
/// writes every axis' switches and every input's state.
void limits_command(port &p, const config &c, std::ostream &out);

/// `x4ctl zero`: stop and zero the axes of c.axis_mask at c.at.
void zero_command(port &p, const config &c, std::ostream &out);

/// `x4ctl goto`, part 1: writes what moves where and starts the moves.
/// Returns the coordinates the axes are to reach (relative moves: from
/// where they were).
coordinates start_goto_command(port &p, const config &c, std::ostream &out);

/// `x4ctl goto`, part 2: follows the moves to their end and writes the
/// coordinates; throws failure if an axis did not reach its target.
void finish_goto_command(port &p, console &con, const config &c, const coordinates &want, std::ostream &out);

/// `x4ctl home`: the reference run, followed to its end; throws failure
/// if it did not find the switch (or was halted).
void home_command(port &p, console &con, const config &c, std::ostream &out);

}  // namespace x4ctl

#endif  // X4CTL_POSITION_HPP
