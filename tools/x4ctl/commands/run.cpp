// SPDX-License-Identifier: GPL-2.0
// x4ctl run: a script of the test program's commands.
#include <cerrno>
#include <cstring>
#include <fstream>
#include <iostream>

#include "commands.hpp"
#include "holder.hpp"
#include "lang.hpp"
#include "motion.hpp"
#include "options.hpp"
#include "subcommand.hpp"
#include "term.hpp"
#include "values.hpp"

namespace x4ctl {
namespace {

// For checking a script: says nothing, has no keys.
class null_console : public console {
 public:
  std::ostream &out() override { return null_; }
  bool live() const override { return false; }
  bool has_keyboard() const override { return false; }
  key read_key(milliseconds) override { return key::none; }

 private:
  std::ostream null_{nullptr};
};

struct script_line {
  int number;
  command cmd;
};

// Reads and parses the whole script, so that a bad line is found before anything moves.
std::vector<script_line> read_script(const std::string &file, const std::string &name) {
  std::ifstream f;
  if (file != "-") {
    f.open(file);
    if (!f) throw failure("cannot read " + file + ": " + std::strerror(errno));
  }
  std::istream &in = file == "-" ? std::cin : f;
  std::vector<script_line> lines;
  std::string text;
  for (int n = 1; std::getline(in, text); n++) {
    try {
      for (auto &cmd : parse_line(text)) lines.push_back({n, std::move(cmd)});
    } catch (const usage_error &e) {
      throw usage_error("run: " + name + ":" + std::to_string(n) + ": " + e.what());
    }
  }
  return lines;
}

void operands(parse_state &s, const std::vector<std::string> &ops) {
  need_operands(ops, 0, 1, s.prefix);
  if (!ops.empty()) s.c.file = ops[0];
}

int run(const config &c) {
  const std::string name = c.file == "-" ? "stdin" : c.file;
  const auto lines = read_script(c.file, name);
  auto where = [&](const script_line &l) { return name + ":" + std::to_string(l.number) + ": "; };

  // First a dry run: every value and combination (ramp against frequency,
  // C without a terminal) is checked before the port is opened.
  null_console quiet;
  interpreter dry(quiet, nullptr, true);
  for (const auto &l : lines) {
    try {
      if (!dry.execute(l.cmd)) break;
    } catch (const usage_error &e) {
      throw usage_error("run: " + where(l) + e.what());
    }
  }
  if (c.check) {
    std::cout << name << ": " << lines.size() << " commands, no errors\n";
    return 0;
  }

  controller_port p(open_controller(device_of(c)));
  std_console con(false);
  interpreter in(con, &p, true);
  for (const auto &l : lines) {
    if (quit_requested()) throw failure(where(l) + "interrupted before " + l.cmd.text);
    if (c.echo) std::cout << in.prompt() << l.cmd.text << "\n" << std::flush;
    try {
      if (!in.execute(l.cmd)) break;
    } catch (const std::exception &e) {
      throw failure(where(l) + what_of(e));
    }
  }
  return 0;
}

}  // namespace

const subcommand &run_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "run";
    c.usage = {"[OPTIONS] [FILE]"};
    c.synopsis = "[FILE]";
    c.summary = "run test program commands from FILE or standard input";
    c.prose =
        "Run test program commands from FILE (standard input if FILE is - or missing),\n"
        "without a terminal. The whole script is checked first, and nothing moves if\n"
        "a line is wrong; then the first error, or a G or A move that is braked, ends\n"
        "the run.\n";
    c.options = {
        check_option("only check the script; do not open the port"),
        {"echo", 'e', "", "print each command after the prompt before it runs",
         [](parse_state &s, const option_value &) { s.c.echo = true; }},
    };
    c.epilogue =
        "Commands of the test program (X4Step's TEST.EXE); case does not matter:\n"
        "  x->     the prompt shows the selected axis x\n"
        "  Q       quit\n"
        "  Sx      select axis x (1..4); D, F and R set values of the selected axis\n"
        "  Dx      distance of the axis in steps, -16777216..16777216 (0: it stays)\n"
        "  Fx      frequency of the axis, 10..20000 Hz (default 1000)\n"
        "  Rx      ramp time of the axis, 0..1000 ms, at most F in Hz (default 50)\n"
        "  G       go: move every axis with a distance, interpolated (all start and\n"
        "          stop together), at the frequency and ramp of the leader axis, the\n"
        "          one with the longest distance\n"
        "  I       show the values of all axes and the leader\n"
        "  M+      move the selected axis endlessly (its F and R) until ESC\n"
        "  M-      the same in the negative direction\n"
        "  C       jog the selected axis with the cursor keys LEFT and RIGHT: it moves\n"
        "          while the key is held and brakes when it is released; ESC ends\n"
        "  Ax,y,z  frequency sweep, to find resonances: the axis moves its distance at\n"
        "          x Hz, x+z Hz, ... y Hz, alternately forth and back (its R)\n"
        "  T       move the selected axis back and forth by its distance until ESC\n"
        "  E       show the five inputs continuously until ESC\n"
        "  H, ?    this help\n"
        "x4ctl's additions:\n"
        "  On,v    set output signal n (1: pin 1, 2: pin 14) on (v=1) or off (v=0)\n"
        "  Kc,...  brake keys: set-1 scan codes that brake a move (ESC always does)\n"
        "  Wt      wait t ms\n"
        "Several commands fit on a line, separated by ';'; '#' starts a comment.\n"
        "While a move runs, ESC or Ctrl-C brakes it (twice Ctrl-C: stop at once).\n"
        "Without a terminal (x4ctl run) there is no ESC: M+, M-, T and E take a time\n"
        "in ms, e.g. 'M+ 500' brakes after 500 ms, 'E 1000' shows the inputs for 1 s;\n"
        "without one, M+, M- and T run until a brake key or ESC on the console\n"
        "keyboard, Ctrl-C or 'x4ctl brake', and E shows the inputs once. C needs a\n"
        "terminal.\n";
    c.operands = operands;
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
