// SPDX-License-Identifier: GPL-2.0
// x4ctl: the operator's commands in machine units (issue 20): homing as the
// machine file says, jogs and go-tos within its soft limits. They take a
// port and a console, as position.hpp's do, so that `x4ctl home`, `x4ctl
// jog` and the panel share them.
#ifndef X4CTL_OPERATE_HPP
#define X4CTL_OPERATE_HPP

#include <array>
#include <functional>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "machine_io.hpp"
#include "motion.hpp"

namespace x4ctl {

/// The axes (gcode::X ...) named by letters, each once; "" is every axis of
/// the machine. A letter the machine lacks is a usage_error.
std::vector<size_t> machine_axes(const m::machine &mc, const std::string &letters,
                                 const std::string &command);

/// The unit of axis a: "mm", "inch" or "deg".
std::string unit_of(const m::machine &mc, size_t a);

/// Homes the axes that home (HOME_SEARCH_VEL) among `axes`, in HOME_SEQUENCE
/// order, those of one sequence at the same time: each with the engine's
/// reference run on its HOME_INPUT (search at HOME_SEARCH_VEL until the
/// switch is active, latch at HOME_LATCH_VEL until it changes again), where
/// its coordinate becomes HOME_OFFSET; then they go to HOME, before the
/// next sequence starts. The port's REF inputs are set; their polarity
/// (normally open or closed) is the port's ('x4ctl limits --nc'). Throws
/// failure (the axes of later sequences do not move) if an axis does not
/// home, or usage_error if none of `axes` homes.
void home_machine(port &p, console &con, const m::machine &mc, const std::vector<size_t> &axes,
                  std::ostream &out);

/// Machine positions to go to, by axis (gcode::X ...); empty: stays.
using machine_targets = std::array<std::optional<double>, g::n_axes>;

/// Moves each axis with a target to it on its own (the positioning API's
/// independent moves, at once): at `speed` units/s, clamped to its
/// MAX_VELOCITY (0: at MAX_VELOCITY), accelerating at MAX_ACCELERATION; each
/// ends exactly at its target rounded to steps. A target the soft limits
/// refuse (refused_by_limits) is a usage_error, before anything moves. Follows the moves with
/// con (ESC, Ctrl-C and brake requests brake them). The axes' profiles are
/// restored afterwards.
axes_outcome move_machine(port &p, console &con, const m::machine &mc, const machine_targets &to,
                          double speed);

/// Why the soft limits refuse a move of axis a from `from` to `to`
/// (machine units); empty if they allow it: it ends within them, or it
/// starts beyond a limit and ends nearer to it (back toward the range,
/// after an overrun).
std::string refused_by_limits(const m::machine &mc, size_t a, double from, double to);

/// The soft limit a continuous jog of axis a heads for.
double jog_limit(const m::axis &a, bool positive);

/// A console on which every key brakes (is ESC) while a move is followed;
/// `each_read`, if given, is called before every key read (a screen's redraw).
class any_key_brakes : public console {
 public:
  any_key_brakes(console &inner, bool live, std::function<void()> each_read = {})
      : inner_(inner), live_(live), each_read_(std::move(each_read)) {}
  std::ostream &out() override { return inner_.out(); }
  bool live() const override { return live_; }
  bool has_keyboard() const override { return inner_.has_keyboard(); }
  void keys_on() override { inner_.keys_on(); }
  void keys_off() override { inner_.keys_off(); }
  key read_key(milliseconds timeout) override;
  x4step::axis_set requested_axes() const override { return inner_.requested_axes(); }
  /// Ctrl-C or SIGINT came while a move was followed.
  bool interrupted() const { return interrupted_; }

 private:
  console &inner_;
  bool live_;
  std::function<void()> each_read_;
  bool interrupted_ = false;
};

/// x4ctl home --machine FILE [LETTERS...].
int cmd_home_machine(const config &c);
/// x4ctl jog LETTER+|- --machine FILE [--feed F] [--distance D].
int cmd_jog_machine(const config &c);

}  // namespace x4ctl

#endif  // X4CTL_OPERATE_HPP
