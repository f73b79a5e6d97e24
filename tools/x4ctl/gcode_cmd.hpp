// SPDX-License-Identifier: GPL-2.0
// x4ctl gcode: a G-code part program on a machine (lib/machine), checked
// whole, then streamed to the module's path queue.
#ifndef X4CTL_GCODE_CMD_HPP
#define X4CTL_GCODE_CMD_HPP

#include "cli.hpp"

namespace x4ctl {

/// x4ctl gcode: check (and with --check stop there), then run.
int cmd_gcode(const config &c);
/// x4ctl mdi: the blocks as a one-line program (c.blocks, then M2), as cmd_gcode.
int cmd_mdi(const config &c);

}  // namespace x4ctl

#endif  // X4CTL_GCODE_CMD_HPP
