// SPDX-License-Identifier: GPL-2.0
// x4ctl: every command, one line each, in the order and under the headings
// of `x4ctl --help`. A new command is its file in commands/ (its record,
// subcommand.hpp) and its line here.
#include "subcommand.hpp"

namespace x4ctl {

// C(NAME): the record NAME_subcommand() of commands/NAME.cpp.
#define X4CTL_MAIN_COMMANDS(C) \
  C(move)                      \
  C(jog)                       \
  C(brake)                     \
  C(stop)                      \
  C(status)                    \
  C(in)                        \
  C(out)                       \
  C(keys)                      \
  C(sweep)                     \
  C(monitor)                   \
  C(watch)                     \
  C(list)                      \
  C(run)                       \
  C(timing)                    \
  C(mode)                      \
  C(path)                      \
  C(gcode)                     \
  C(mdi)                       \
  C(touch_off)                 \
  C(panel)                     \
  C(machine)
#define X4CTL_POSITIONING_COMMANDS(C) \
  C(profile)                          \
  C(goto)                             \
  C(home)                             \
  C(zero)                             \
  C(limits)                           \
  C(halt)
#define X4CTL_OTHER_COMMANDS(C) C(help)

#define X4CTL_DECLARE(name) const subcommand &name##_subcommand();
X4CTL_MAIN_COMMANDS(X4CTL_DECLARE)
X4CTL_POSITIONING_COMMANDS(X4CTL_DECLARE)
X4CTL_OTHER_COMMANDS(X4CTL_DECLARE)
#undef X4CTL_DECLARE

const std::vector<command_group> &command_groups() {
#define X4CTL_RECORD(name) &name##_subcommand(),
  static const std::vector<command_group> groups = {
      {"Commands:", {X4CTL_MAIN_COMMANDS(X4CTL_RECORD)}},
      {"Positioning: coordinates, independent axes, homing, limit switches:",
       {X4CTL_POSITIONING_COMMANDS(X4CTL_RECORD)}},
      {nullptr, {X4CTL_OTHER_COMMANDS(X4CTL_RECORD)}},
  };
#undef X4CTL_RECORD
  return groups;
}

}  // namespace x4ctl
