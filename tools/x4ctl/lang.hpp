// SPDX-License-Identifier: GPL-2.0
// x4ctl: the command language of X4Step's test program TEST.EXE (manual,
// chapter 3.4), parsed apart from its execution so the host tests need no
// device.
#ifndef X4CTL_LANG_HPP
#define X4CTL_LANG_HPP

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "io.hpp"
#include "motion.hpp"

namespace x4ctl {

enum class verb {
  select,     ///< Sx
  distance,   ///< Dx
  frequency,  ///< Fx
  ramp,       ///< Rx
  go,         ///< G
  info,       ///< I
  endless,    ///< M+ / M-
  cursor,     ///< C
  sweep,      ///< Ax,y,z
  toggle,     ///< T
  inputs,     ///< E
  help,       ///< H, ?
  quit,       ///< Q
  output,     ///< On,v   (x4ctl extension)
  keys,       ///< Kc,... (x4ctl extension)
  wait,       ///< Wt     (x4ctl extension)
};

/// One command, its numbers checked for range.
struct command {
  verb what = verb::help;
  std::vector<long> args;                               ///< S, D, F, R, W: 1; A: 3; O: 2; K: 0..20
  x4step::direction dir = x4step::direction::positive;  ///< M+ / M-
  std::optional<long> time_ms;                          ///< M, T, E: end after this (scripts have no ESC)
  std::string text;                                     ///< as written, for messages
};

/// Parses one command ("d1000", "A 200,500,20", "m+ 500"); case does not
/// matter. Throws usage_error saying what is wrong.
command parse_command(const std::string &text);

/// Parses a line: commands separated by ';', '#' starts a comment.
std::vector<command> parse_line(const std::string &line);

/// The help of H and ?, also part of `x4ctl run --help`.
std::string language_help();

/// What TEST.EXE keeps per axis.
struct axis_values {
  long distance = 0;
  int freq_hz = 1000;
  int ramp_ms = 50;
};

/// Runs commands on a port, keeping the selected axis and per-axis values.
class interpreter {
 public:
  /// p may be null: then commands are only checked (x4ctl run --check),
  /// nothing is opened or moved. With strict (scripts), a G or A move that
  /// is halted before its target throws failure. p is not owned.
  interpreter(console &con, port *p, bool strict);

  /// Runs one command; false after Q. Throws usage_error for values that
  /// do not fit together (nothing moved), failure or x4step::error when
  /// the port refuses.
  bool execute(const command &c);

  std::string prompt() const;  ///< "1-> "
  int selected() const { return axis_; }
  const axis_values &values(int axis) const { return values_.at(axis - 1); }
  /// The axis (1..4) with the longest distance, 0 if all are 0.
  int leader() const;
  /// The move G loads: every distance, at the leader's frequency and ramp.
  x4step::move go_move() const;
  /// The table of I.
  std::string info() const;

 private:
  void go();
  void endless(const command &c);
  void cursor();
  void sweep(const command &c);
  void toggle(const command &c);
  void inputs(const command &c);
  void wait(const command &c);
  x4step::move axis_move(long steps, int freq_hz) const;
  deadline until(const command &c) const;

  console &con_;
  port *port_;
  bool strict_;
  int axis_ = 1;
  std::array<axis_values, x4step::axes> values_{};
};

}  // namespace x4ctl

#endif  // X4CTL_LANG_HPP
