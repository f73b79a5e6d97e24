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
    c.epilogue = language_help();
    c.operands = operands;
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
