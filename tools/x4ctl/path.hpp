// SPDX-License-Identifier: GPL-2.0
// x4ctl path: a file of straight segments, in steps, streamed to the
// module's path queue (x4step_path.hpp).
#ifndef X4CTL_PATH_HPP
#define X4CTL_PATH_HPP

#include <iosfwd>
#include <string>
#include <vector>

#include "cli.hpp"
#include "x4step_path.hpp"

namespace x4ctl {

/// The path's unit: 1/1000 of a step along the path (lengths, speeds and
/// accelerations sent to the module are in it).
constexpr unsigned path_units_per_step = 1000;

/// Reads and checks a whole path, so that a bad line stops everything
/// before a step: usage_error "NAME:LINE:COLUMN: what is wrong". A line:
/// up to 4 signed step counts (axes 1..4), then optional speed=STEPS/S,
/// accel=STEPS/S^2, corner=STEPS/S (the speed allowed at its start; else
/// from the corner's angle and the junction deviation); '#' comments.
/// Each segment's tag is its line number.
std::vector<x4step::segment> read_path(std::istream &in, const std::string &name, const path_defaults &d);

/// x4ctl path: check, then stream the path and show its progress.
int cmd_path(const config &c);

}  // namespace x4ctl

#endif  // X4CTL_PATH_HPP
