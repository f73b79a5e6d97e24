// SPDX-License-Identifier: LGPL-2.1-or-later
/**
 * @file stepconf.hpp
 * @brief A LinuxCNC configuration as StepConf writes it (its INI file and,
 *        if given, its HAL file) made into an x4step machine file: what
 *        carries over (units, axes, scales, speeds, accelerations, soft
 *        limits, homing, the home switches' inputs, spindle and coolant on
 *        pins 1 and 14) and a list of what does not.
 */
#ifndef X4STEP_STEPCONF_HPP
#define X4STEP_STEPCONF_HPP

#include <iosfwd>
#include <string>
#include <vector>

namespace x4step::machine {

struct imported {
  std::string text;                      ///< the machine file
  std::vector<std::string> not_carried;  ///< what x4step could not take, a line each
  std::vector<std::string> notes;        ///< what was changed or chosen on the way, a line each
};

/// Makes a machine file of a StepConf INI (`ini`, named ini_name in the
/// file's header) and its HAL file (hal may be null: then no home switch
/// inputs nor spindle pins are known). tool_table: the INI's [EMCIO]
/// TOOL_TABLE as the machine file should name it ("" leaves it out).
imported import_stepconf(std::istream &ini, const std::string &ini_name, std::istream *hal,
                         const std::string &hal_name, const std::string &tool_table);

}  // namespace x4step::machine

#endif
