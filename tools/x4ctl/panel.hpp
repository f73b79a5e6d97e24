// SPDX-License-Identifier: GPL-2.0
// x4ctl panel: a full-screen operator panel for a machine file's machine,
// as the SMC1500 program's screen: positions in machine units, jog keys,
// feed, work zero, go to, home.
#ifndef X4CTL_PANEL_HPP
#define X4CTL_PANEL_HPP

#include "cli.hpp"

namespace x4ctl {

/// x4ctl panel: runs until q, Ctrl-C or a signal; every move braked by then.
int cmd_panel(const config &c);

}  // namespace x4ctl

#endif  // X4CTL_PANEL_HPP
