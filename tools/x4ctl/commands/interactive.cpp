// SPDX-License-Identifier: GPL-2.0
// x4ctl without a command: X4Step's test program TEST.EXE at a prompt,
// and the program's help (its usage, the options before a command, the
// commands of the registry).
#include <unistd.h>

#include <iostream>

#include "commands.hpp"
#include "holder.hpp"
#include "lang.hpp"
#include "subcommand.hpp"
#include "term.hpp"

namespace x4ctl {
namespace {

int run(const config &c) {
  const std::string dev = device_of(c);
  controller_port p(open_controller(dev));
  std_console con(true);
  interpreter in(con, &p, false);
  const bool tty = ::isatty(STDIN_FILENO);
  std::cout << "x4ctl: X4Step test program on " << dev << "\n";
  if (tty) std::cout << language_help();  // as TEST.EXE does at its start
  for (;;) {
    std::cout << in.prompt() << std::flush;
    std::string line;
    if (!std::getline(std::cin, line)) break;  // end of input, or Ctrl-C
    if (!tty) std::cout << line << "\n";       // a readable transcript
    try {
      for (const command &cmd : parse_line(strip_keys(line)))
        if (!in.execute(cmd)) return 0;
    } catch (const std::exception &e) {
      // The rest of the line is dropped: nothing moves after an error.
      std::cout << std::flush;
      std::cerr << "error: " << what_of(e) << "\n";
    }
    if (quit_requested()) break;
  }
  std::cout << "\n";
  return 0;
}

}  // namespace

const subcommand &main_command() {
  static const subcommand c = [] {
    subcommand c;
    c.usage = {"[-p LPT | -d PATH] [COMMAND [ARGS...]]", "[LPT]"};
    c.prose =
        "Drive up to four stepper motors on a PC parallel port through the x4step\n"
        "kernel module. Without a COMMAND, x4ctl is X4Step's test program: a prompt\n"
        "that takes the commands of TEST.EXE (H lists them, see also 'x4ctl run --help').\n";
    c.options = {
        common_option("port"),
        common_option("device"),
        common_option("sim"),
        common_option("help"),
        {"version", 'v', "", "show the version",
         [](parse_state &s, const option_value &) { s.c.version = true; }},
    };
    c.epilogue =
        "Run 'x4ctl COMMAND --help' for the options of a command. Axes are 1 to 4.\n"
        "Reading commands take --json ('x4ctl help list' describes the format).\n"
        "\n"
        "Exit status: 0 success; 1 the port refused, or a move did not reach its\n"
        "target; 2 bad usage (checked before the port is opened: nothing moved).\n";
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
