// SPDX-License-Identifier: GPL-2.0
// x4ctl: one record per command. A command is its name, its help (usage,
// summary, prose), its options (each with its help and what it does to the
// config), what it does with its operands, and the function that runs it.
// The parser (cli.cpp) and the help (help.cpp) read nothing else; the
// registry (registry.cpp) lists the commands, one line each.
#ifndef X4CTL_SUBCOMMAND_HPP
#define X4CTL_SUBCOMMAND_HPP

#include <optional>
#include <string>
#include <vector>

#include "cli.hpp"

namespace x4ctl {

struct option;

/// An option as the command line gave it.
struct option_value {
  const option *opt;
  std::string name;               ///< as written, for messages: --freq, -f
  std::string value;              ///< "" for a flag
  std::vector<std::string> more;  ///< a list option's further values (--then 1 2 3)
};

/// What the options said, for the command's operands to finish the config.
struct parse_state {
  config &c;
  std::string prefix;                                ///< "move: ", for messages
  int freq = default_freq_hz;                        ///< --freq
  std::optional<int> ramp;                           ///< --ramp; none: the default for freq
  std::vector<std::vector<std::string>> then_paths;  ///< each --then and its values
  std::vector<std::string> given;                    ///< the long names of the options given
  /// Whether any of the options named (long names) was given.
  bool gave(std::initializer_list<const char *> names) const;
};

/// One option of a command: its names, its help and what it does.
struct option {
  std::string name;     ///< the long name, without "--"
  char short_name = 0;  ///< 0: none
  std::string value;    ///< its value's name in the help (HZ); empty: a flag
  std::string help;     ///< the help's text, lines split by '\n'; empty: not shown
  void (*apply)(parse_state &, const option_value &) = nullptr;
  bool list = false;  ///< the words after the value, up to the next option, are values too
};

/// One x4ctl command.
struct subcommand {
  std::string name;                      ///< empty: x4ctl without a command (the test program)
  std::vector<std::string> usage;        ///< the Usage lines, after "x4ctl NAME "
  std::string synopsis;                  ///< the overview's operands after the name ("STEPS...")
  std::string summary;                   ///< the overview's text, lines split by '\n'
  std::string prose;                     ///< the help between the usage and the options
  std::vector<option> options;           ///< its own; common_options() follow unless named here
  std::string epilogue;                  ///< the help after the options; may be empty
  bool overview = false;                 ///< its help is the program's (help)
  void (*defaults)(config &) = nullptr;  ///< before the options: what differs from config's
  /// The operands, once the options are applied: fill the config, check it
  /// whole (throws usage_error). nullptr: the command takes none.
  void (*operands)(parse_state &, const std::vector<std::string> &) = nullptr;
  int (*run)(const config &) = nullptr;  ///< the exit status
};

/// -p, -d, --sim, -h: every command's.
const std::vector<option> &common_options();
/// The option of common_options() named name.
const option &common_option(const std::string &name);

/// x4ctl without a command: the test program, and the program's help.
const subcommand &main_command();

/// A heading of the overview and its commands.
struct command_group {
  const char *heading;  ///< nullptr: none
  std::vector<const subcommand *> commands;
};
/// Every command, in the overview's groups and order.
const std::vector<command_group> &command_groups();

/// The command called name; nullptr if none.
const subcommand *find_command(const std::string &name);

/// The operands' count is within min..max (else usage_error).
void need_operands(const std::vector<std::string> &ops, size_t min, size_t max, const std::string &prefix);

}  // namespace x4ctl

#endif  // X4CTL_SUBCOMMAND_HPP
