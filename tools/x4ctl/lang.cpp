// SPDX-License-Identifier: GPL-2.0
// x4ctl: the TEST.EXE command language: its parser and its help (lang.hpp).
#include "lang.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <ostream>

#include "cli.hpp"

namespace x4ctl {
namespace {

std::string trim(const std::string &s) {
  const size_t b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

// "200, 500,20" -> numbers; an empty text is an empty list.
std::vector<long> number_list(const std::string &text, const std::string &ctx, const char *what) {
  std::vector<long> v;
  if (trim(text).empty()) return v;
  size_t at = 0;
  for (;;) {
    const size_t comma = text.find(',', at);
    v.push_back(parse_number(trim(text.substr(at, comma - at)), ctx + what));
    if (comma == std::string::npos) return v;
    at = comma + 1;
  }
}

}  // namespace

command parse_command(const std::string &text) {
  command c;
  c.text = trim(text);
  if (c.text.empty()) throw usage_error("empty command: H shows the commands");
  const char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(c.text[0])));
  std::string rest = trim(c.text.substr(1));
  const std::string ctx = c.text + ": ";

  auto no_argument = [&] {
    if (!rest.empty()) throw usage_error(ctx + std::string(1, letter) + " takes no argument");
  };
  auto numbers = [&](size_t n, const char *what, const char *example) {
    c.args = number_list(rest, ctx, what);
    if (c.args.size() != n)
      throw usage_error(ctx + std::string(1, letter) + " needs " +
                        (n == 1 ? "a number" : std::to_string(n) + " numbers") + ", e.g. " + example);
  };
  auto optional_time = [&] {
    if (rest.empty()) return;
    c.time_ms = parse_number(rest, ctx + "time");
    if (*c.time_ms < 0) throw usage_error(ctx + "time " + rest + " out of range: use 0 ms or more");
  };
  auto freq_check = [&](long f) {
    if (f > x4step::freq_max_hz) throw usage_error(ctx + message(x4step::errc::freq_too_high));
    if (f < x4step::freq_min_hz) throw usage_error(ctx + message(x4step::errc::freq_too_low));
  };

  switch (letter) {
    case 'S':
      c.what = verb::select;
      numbers(1, "axis", "S1");
      if (c.args[0] < 1 || c.args[0] > x4step::axes)
        throw usage_error(ctx + "axis " + std::to_string(c.args[0]) + " out of range: use 1 to 4");
      break;
    case 'D':
      c.what = verb::distance;
      numbers(1, "steps", "D1000");
      if (std::labs(c.args[0]) > x4step::steps_max)
        throw usage_error(ctx + message(x4step::errc::steps_too_high));
      break;
    case 'F':
      c.what = verb::frequency;
      numbers(1, "frequency", "F2000");
      freq_check(c.args[0]);
      break;
    case 'R':
      c.what = verb::ramp;
      numbers(1, "ramp", "R50");
      if (c.args[0] > x4step::ramp_max.count()) throw usage_error(ctx + message(x4step::errc::ramp_too_high));
      if (c.args[0] < 0) throw usage_error(ctx + "ramp " + rest + " out of range: use 0 to 1000 ms");
      break;
    case 'G':
      c.what = verb::go;
      no_argument();
      break;
    case 'I':
      c.what = verb::info;
      no_argument();
      break;
    case 'M':
      c.what = verb::endless;
      if (rest.empty() || (rest[0] != '+' && rest[0] != '-'))
        throw usage_error(ctx + "M needs a direction: M+ or M-");
      c.dir = rest[0] == '+' ? x4step::direction::positive : x4step::direction::negative;
      rest = trim(rest.substr(1));
      optional_time();
      break;
    case 'C':
      c.what = verb::cursor;
      no_argument();
      break;
    case 'A':
      c.what = verb::sweep;
      numbers(3, "frequency", "A200,500,20");
      freq_check(c.args[0]);
      freq_check(c.args[1]);
      if (c.args[2] < 1 || c.args[2] > x4step::freq_max_hz)
        throw usage_error(ctx + "frequency step " + std::to_string(c.args[2]) + " out of range: use 1 to " +
                          std::to_string(x4step::freq_max_hz) + " Hz");
      break;
    case 'T':
      c.what = verb::toggle;
      optional_time();
      break;
    case 'E':
      c.what = verb::inputs;
      optional_time();
      break;
    case 'H':
    case '?':
      c.what = verb::help;
      no_argument();
      break;
    case 'Q':
      c.what = verb::quit;
      no_argument();
      break;
    case 'O':
      c.what = verb::output;
      numbers(2, "output", "O1,1");
      if (c.args[0] != 1 && c.args[0] != 2)
        throw usage_error(ctx + "signal " + std::to_string(c.args[0]) + ": use 1 (pin 1) or 2 (pin 14)");
      if (c.args[1] != 0 && c.args[1] != 1)
        throw usage_error(ctx + "level " + std::to_string(c.args[1]) + ": use 1 (on) or 0 (off)");
      break;
    case 'K':
      c.what = verb::keys;
      c.args = number_list(rest, ctx, "key code");
      if (c.args.size() > 20) throw usage_error(ctx + "at most 20 key codes");
      for (long k : c.args)
        if (k < 1 || k > 255 || k == 128)
          throw usage_error(ctx + "key code " + std::to_string(k) +
                            " out of range: use 1..127 (press) or 129..255 (release)");
      break;
    case 'W':
      c.what = verb::wait;
      numbers(1, "time", "W500");
      if (c.args[0] < 0) throw usage_error(ctx + "time " + rest + " out of range: use 0 ms or more");
      break;
    default:
      throw usage_error(ctx + "unknown command: H shows the commands");
  }
  return c;
}

std::vector<command> parse_line(const std::string &line) {
  std::vector<command> v;
  const std::string code = line.substr(0, line.find('#'));
  size_t at = 0;
  for (;;) {
    const size_t semi = code.find(';', at);
    const std::string part = trim(code.substr(at, semi - at));
    if (!part.empty()) v.push_back(parse_command(part));
    if (semi == std::string::npos) return v;
    at = semi + 1;
  }
}

std::string language_help() {
  const std::string steps = std::to_string(x4step::steps_max);
  return "Commands of the test program (X4Step's TEST.EXE); case does not matter:\n"
         "  x->     the prompt shows the selected axis x\n"
         "  Q       quit\n"
         "  Sx      select axis x (1..4); D, F and R set values of the selected axis\n"
         "  Dx      distance of the axis in steps, -" +
         steps + ".." + steps +
         " (0: it stays)\n"
         "  Fx      frequency of the axis, " +
         std::to_string(x4step::freq_min_hz) + ".." + std::to_string(x4step::freq_max_hz) + " Hz (default " +
         std::to_string(default_freq_hz) +
         ")\n"
         "  Rx      ramp time of the axis, 0.." +
         std::to_string(x4step::ramp_max.count()) + " ms, at most F in Hz (default " +
         std::to_string(default_ramp_ms(default_freq_hz)) +
         ")\n"
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
}

}  // namespace x4ctl
