// SPDX-License-Identifier: GPL-2.0
// x4ctl: options that several commands share (command.hpp), each with the
// help text of the command that names it where the wording differs.
#ifndef X4CTL_OPTIONS_HPP
#define X4CTL_OPTIONS_HPP

#include <string>

#include "subcommand.hpp"

namespace x4ctl {

/// -f, --freq=HZ: the leader axis' frequency (move, jog).
option freq_option();
/// -r, --ramp=MS: the ramp time; help: the default's (move, jog), or another.
option ramp_option();
option ramp_option(const std::string &help);
/// -w, --wait: stay until the move ends.
option wait_option(const std::string &help);
/// -t, --time=MS.
option time_option(const std::string &help);
/// -j, --json.
option json_option(const std::string &help);
/// -m, --machine=FILE.
option machine_option(const std::string &help);
/// --feed=F, units/min.
option feed_option(const std::string &help);
/// -o, --override=PCT: the feed override.
option override_option();
/// -c, --check.
option check_option(const std::string &help);
/// --no-pause: M0, M1 and M6 do not wait.
option no_pause_option(const std::string &help);

/// The machine file's help of gcode, mdi and panel.
extern const char *const machine_file_help;

}  // namespace x4ctl

#endif  // X4CTL_OPTIONS_HPP
