// SPDX-License-Identifier: GPL-2.0
// x4ctl: what the command interpreter needs from a port and from its user.
// Both are interfaces so that the host tests can run the interpreter
// against a simulated port and scripted keys.
#ifndef X4CTL_IO_HPP
#define X4CTL_IO_HPP

#include <array>
#include <chrono>
#include <ostream>
#include <utility>
#include <vector>

#include "sim.hpp"
#include "x4step.hpp"

namespace x4ctl {

using std::chrono::milliseconds;

/// The controller calls x4ctl makes; see x4step::controller.
class port {
 public:
  virtual ~port() = default;
  virtual void load(const x4step::move &m) = 0;
  virtual void start() = 0;
  virtual void brake() = 0;
  virtual void stop() = 0;
  virtual void move_endless(x4step::axis a, x4step::direction dir, int freq_hz, milliseconds ramp) = 0;
  virtual x4step::status get_status() const = 0;
  /// True once no move runs; false after timeout.
  virtual bool wait(milliseconds timeout) const = 0;
  virtual void set_output(x4step::signal s, bool high) = 0;
  virtual void set_brake_codes(const std::vector<int> &codes) = 0;
  /// Per-port settings; the module keeps them after the port is closed.
  virtual void set_config(const x4step::config &c) = 0;
  virtual x4step::config get_config() const = 0;
  virtual void set_step_timing(const x4step::step_timing &t) = 0;
  virtual x4step::step_timing get_step_timing() const = 0;
  // Positioning.
  virtual void set_profile(x4step::axis a, const x4step::profile &p) = 0;
  virtual x4step::profile get_profile(x4step::axis a) const = 0;
  virtual void move_to(x4step::axis_set axes, const std::array<long, x4step::axes> &targets,
                       bool relative) = 0;
  virtual void home(x4step::axis a, const x4step::homing &h) = 0;
  virtual void halt(x4step::axis_set axes, x4step::halt_mode how) = 0;
  virtual void set_position(x4step::axis a, long position) = 0;
  virtual void set_switches(const x4step::switches &s) = 0;
  virtual x4step::switches get_switches() const = 0;
  virtual x4step::axes_status get_axes() const = 0;
  /// True once none of the axes runs; false after timeout.
  virtual bool wait_axes(x4step::axis_set axes, milliseconds timeout) const = 0;
  /// The port's clock, which the times of commands count on (jog --time,
  /// out --time, M+ 500, W): a simulated port in virtual time has its own.
  virtual std::chrono::steady_clock::time_point now() const { return std::chrono::steady_clock::now(); }
  /// False for a simulated port in virtual time: its clock moves only in
  /// the library's calls, and pass() moves it on.
  virtual bool clock_runs() const { return true; }
  /// Virtual time: lets d pass on the port (its moves run meanwhile).
  virtual void pass(milliseconds d) { (void)d; }
  /// A simulated port: it lives in this process, no other x4ctl reaches it.
  virtual bool simulated() const { return false; }
};

/// A port that is a real x4step::controller.
class controller_port : public port {
 public:
  explicit controller_port(x4step::controller c) : c_(std::move(c)) {}
  /// The controller itself, for what a port does not offer (paths).
  x4step::controller &controller() { return c_; }
  void load(const x4step::move &m) override { c_.load(m); }
  void start() override { c_.start(); }
  void brake() override { c_.brake(); }
  void stop() override { c_.stop(); }
  void move_endless(x4step::axis a, x4step::direction dir, int freq_hz, milliseconds ramp) override {
    c_.move_endless(a, dir, freq_hz, ramp);
  }
  x4step::status get_status() const override { return c_.get_status(); }
  bool wait(milliseconds timeout) const override { return c_.wait(timeout); }
  void set_output(x4step::signal s, bool high) override { c_.set_output(s, high); }
  void set_brake_codes(const std::vector<int> &codes) override { c_.set_brake_codes(codes); }
  void set_config(const x4step::config &c) override { c_.set_config(c); }
  x4step::config get_config() const override { return c_.get_config(); }
  void set_step_timing(const x4step::step_timing &t) override { c_.set_step_timing(t); }
  x4step::step_timing get_step_timing() const override { return c_.get_step_timing(); }
  void set_profile(x4step::axis a, const x4step::profile &p) override { c_.set_profile(a, p); }
  x4step::profile get_profile(x4step::axis a) const override { return c_.get_profile(a); }
  void move_to(x4step::axis_set axes, const std::array<long, x4step::axes> &targets, bool relative) override {
    c_.move_to(axes, targets, relative);
  }
  void home(x4step::axis a, const x4step::homing &h) override { c_.home(a, h); }
  void halt(x4step::axis_set axes, x4step::halt_mode how) override { c_.halt(axes, how); }
  void set_position(x4step::axis a, long position) override { c_.set_position(a, position); }
  void set_switches(const x4step::switches &s) override { c_.set_switches(s); }
  x4step::switches get_switches() const override { return c_.get_switches(); }
  x4step::axes_status get_axes() const override { return c_.get_axes(); }
  bool wait_axes(x4step::axis_set axes, milliseconds timeout) const override {
    return c_.wait_axes(axes, timeout);
  }
  std::chrono::steady_clock::time_point now() const override { return c_.now(); }
  bool clock_runs() const override { return c_.clock_runs(); }
  void pass(milliseconds d) override {
    if (!c_.clock_runs()) c_.sleep_for(d);
  }
  bool simulated() const override { return is_sim_device(c_.path()); }

 private:
  x4step::controller c_;
};

/// What the user did while something runs.
enum class key {
  none,
  esc,
  left,
  right,
  up,
  down,
  page_up,
  page_down,
  space,
  plus,           ///< '+' (or '=', its key unshifted)
  minus,          ///< '-'
  other,          ///< any other key (std_console::last_char() tells a character)
  brake_request,  ///< SIGTERM, SIGHUP, SIGUSR1 (`x4ctl brake`, `x4ctl halt`)
  interrupt,      ///< Ctrl-C: brakes; a second one stops
  stop_request,   ///< SIGUSR2 (`x4ctl stop`, `x4ctl halt --stop`)
};

/// Every axis.
constexpr x4step::axis_set all_axes = x4step::axis_set::all();

/// The user's side: output, and keys while a move runs.
class console {
 public:
  virtual ~console() = default;
  virtual std::ostream &out() = 0;
  /// Output is a terminal: progress is redrawn in place.
  virtual bool live() const = 0;
  /// ESC and the cursor keys can be read (a terminal on stdin).
  virtual bool has_keyboard() const = 0;
  /// Keys are read from here on (raw terminal) until keys_off().
  virtual void keys_on() {}
  virtual void keys_off() {}
  /// The next key, waiting up to timeout; key::none on timeout.
  /// Signals (brake/stop requests) are reported even without a keyboard.
  virtual key read_key(milliseconds timeout) = 0;
  /// The axes the brake or stop request read last asks to halt:
  /// `x4ctl halt AXIS...` names some, everything else means all.
  virtual x4step::axis_set requested_axes() const { return all_axes; }
};

/// keys_on() for as long as it lives.
class keys_guard {
 public:
  explicit keys_guard(console &c) : c_(c) { c_.keys_on(); }
  ~keys_guard() { c_.keys_off(); }
  keys_guard(const keys_guard &) = delete;
  keys_guard &operator=(const keys_guard &) = delete;

 private:
  console &c_;
};

}  // namespace x4ctl

#endif  // X4CTL_IO_HPP
