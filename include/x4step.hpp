// SPDX-License-Identifier: LGPL-2.1-or-later
/**
 * @file x4step.hpp
 * @brief C++ API of libx4step: stepper motors on the PC parallel port.
 *
 * A x4step::controller owns one port (/dev/x4stepN) for as long as it
 * lives; a x4step::monitor watches a port read-only. Errors are thrown as
 * x4step::error, a std::system_error whose code is either in
 * x4step::category() (the X4Step error numbers, same as the C API) or in
 * std::system_category() (an errno the library did not expect).
 *
 * @code
 *   x4step::controller c(1);                                  // LPT1
 *   c.load({{1000, 800, 600, 400}, 1000, std::chrono::milliseconds(50)});
 *   c.start();
 *   c.wait();                                                 // poll(), no spinning
 *   std::cout << c.get_status() << '\n';
 * @endcode
 *
 * Positioning (the ProStep4 model): each axis keeps a machine coordinate,
 * updated by every step of every kind of move, and can move on its own to
 * a coordinate with its own ramp, run a reference run, and stop at limit
 * switches. An axis is a x4step::axis (axis::x .. axis::a, or axis{1} ..
 * axis{4}), several are a x4step::axis_set (axis::x | axis::z): never a
 * bare integer, so that an axis number cannot be taken for a mask.
 *
 * @code
 *   using x4step::axis;
 *   x4step::controller c(1);
 *   x4step::switches sw;
 *   sw.ref[axis::x.index()] = 1;                              // REF of axis 1 on input 1 (pin 15)
 *   c.set_switches(sw);
 *   c.home(axis::x, x4step::homing{});                        // both phases
 *   c.wait_axes(axis::x);
 *   c.set_profile(axis::x, x4step::profile{}.top_speed(5000).accel(20000).decel(20000));
 *   c.move_to(axis::x, 12000);
 *   c.wait_axes(axis::x);
 *   std::cout << c.get_axes() << '\n';
 * @endcode
 *
 * Settings of several numbers (profile, homing, step_timing, config) are
 * built by name, with setters that return the object:
 * `x4step::profile{}.start_speed(100).top_speed(5000)`. A struct for C++20
 * designated initialisers would still accept a positional
 * `{100, 100, 5000, 20000, 20000}`, and this header serves C++17 programs.
 * Each setter has a getter of the same name.
 *
 * Threads: a controller or a monitor is one open descriptor; its calls
 * are not synchronized, so use an object from one thread at a time (or
 * lock around it). Distinct objects are independent, also on one port.
 * The free functions (check(), version(), ...) may be called from any
 * thread. The values (axis, axis_set, profile, homing, step_timing,
 * config, status, event, ...) hold no descriptor: copies of them may be
 * used in any thread.
 */
#ifndef X4STEP_HPP
#define X4STEP_HPP

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <iterator>
#include <memory>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

// The library builds with hidden symbols: what is declared here is its API.
#pragma GCC visibility push(default)
namespace x4step {

/// X4Step error numbers (chapter 4.1 of the manual), as in x4step.h.
enum class errc {
  ok = 0,               ///< X4NoErr
  no_steps = 1,         ///< X4ErrNoSteps: every path is 0
  freq_too_high = 2,    ///< X4ErrFreqTooHigh: above 20000 Hz
  freq_too_low = 3,     ///< X4ErrFreqTooLow: below 10 Hz
  ramp_too_high = 4,    ///< X4ErrRampTooHigh: above 1000 ms
  ramp_freq = 5,        ///< X4ErrRampFreq: ramp (ms) greater than freq (Hz)
  lpt_not_found = 6,    ///< X4ErrLPTNotFound: no such port, or it is taken
  not_active = 7,       ///< X4ErrNotActive: nothing runs
  param_fail = 8,       ///< X4ErrParamFail: a parameter is out of range
  init_not_done = 9,    ///< X4ErrInitNotDone: no port opened
  is_active = 10,       ///< X4ErrIsActive: a move runs
  not_loaded = 11,      ///< X4ErrNotLoaded: nothing loaded to start
  is_loaded = 12,       ///< X4ErrIsLoaded: a move is loaded already
  steps_too_high = 13,  ///< X4ErrStepsTooHigh: a path beyond 16777216 steps
};

/// The category of x4step::errc; its messages say what to fix.
const std::error_category &category() noexcept;
std::error_code make_error_code(errc e) noexcept;

/// What every failing call throws.
class error : public std::system_error {
 public:
  using std::system_error::system_error;
};

constexpr int axes = 4;
constexpr int freq_min_hz = 10;
constexpr int freq_max_hz = 20000;
constexpr std::chrono::milliseconds ramp_max{1000};
constexpr long steps_max = 16777216;
/// step_timing: any time at most timing_max; a pulse that is not 0 (the
/// symmetric clock) at least pulse_min.
constexpr std::chrono::nanoseconds timing_max{1000000};
constexpr std::chrono::nanoseconds pulse_min{1000};

/// One axis: 1..4, the X4Step manual's motor numbers. Made from a number
/// only explicitly, and checked: axis{5} throws param_fail (and does not
/// compile where a constant is needed).
class axis {
 public:
  constexpr explicit axis(int number)
      : n_(valid(number) ? number
                         : throw error(make_error_code(errc::param_fail),
                                       "axis " + std::to_string(number) + ": axes are 1..4")) {}
  /// Whether axis{number} would be made rather than throw.
  static constexpr bool valid(int number) noexcept { return number >= 1 && number <= axes; }

  constexpr int number() const noexcept { return n_; }               ///< 1..4
  constexpr int index() const noexcept { return n_ - 1; }            ///< 0..3, for the std::arrays here
  constexpr unsigned bit() const noexcept { return 1u << index(); }  ///< in an axis_set's mask

  /// The axes by name: x, y, z as the SMC boards call the first three, a
  /// for the fourth (as CNC names a rotary axis).
  static const axis x, y, z, a;

  friend constexpr bool operator==(axis l, axis r) noexcept { return l.n_ == r.n_; }
  friend constexpr bool operator!=(axis l, axis r) noexcept { return l.n_ != r.n_; }

 private:
  int n_;
};
inline constexpr axis axis::x{1}, axis::y{2}, axis::z{3}, axis::a{4};

/// A set of axes: axis::x | axis::z, or one axis (which converts), or
/// axis_set::all(). Made from a raw mask (bit i: axis i + 1) only
/// explicitly, and checked: axis_set{0x10u} throws param_fail. Iterates
/// its axes in increasing order: for (x4step::axis a : set) ...
class axis_set {
 public:
  constexpr axis_set() noexcept = default;  ///< no axis
  constexpr axis_set(axis a) noexcept : mask_(a.bit()) {}
  constexpr explicit axis_set(unsigned mask)
      : mask_(mask <= all_mask ? mask
                               : throw error(make_error_code(errc::param_fail),
                                             "axis mask " + std::to_string(mask) + ": axes are 1..4")) {}
  static constexpr axis_set all() noexcept { return axis_set(all_mask); }

  constexpr unsigned mask() const noexcept { return mask_; }  ///< bit i: axis i + 1
  constexpr bool empty() const noexcept { return mask_ == 0; }
  constexpr bool contains(axis a) const noexcept { return (mask_ & a.bit()) != 0; }
  constexpr axis_set &operator|=(axis_set o) noexcept {
    mask_ |= o.mask_;
    return *this;
  }
  constexpr axis_set &operator&=(axis_set o) noexcept {
    mask_ &= o.mask_;
    return *this;
  }
  /// The other axes of the four.
  constexpr axis_set operator~() const noexcept { return axis_set(~mask_ & all_mask); }
  friend constexpr bool operator==(axis_set l, axis_set r) noexcept { return l.mask_ == r.mask_; }
  friend constexpr bool operator!=(axis_set l, axis_set r) noexcept { return l.mask_ != r.mask_; }

  /// Walks the axes of the set, lowest first.
  class iterator {
   public:
    using iterator_category = std::input_iterator_tag;  // yields axes by value
    using value_type = axis;
    using difference_type = std::ptrdiff_t;
    using pointer = void;
    using reference = axis;

    constexpr iterator() noexcept = default;
    constexpr axis operator*() const {
      int n = 1;
      while (!(rest_ >> (n - 1) & 1u)) n++;
      return axis(n);
    }
    constexpr iterator &operator++() noexcept {
      rest_ &= rest_ - 1;  // drop the lowest axis
      return *this;
    }
    constexpr iterator operator++(int) noexcept {
      iterator was = *this;
      ++*this;
      return was;
    }
    friend constexpr bool operator==(iterator l, iterator r) noexcept { return l.rest_ == r.rest_; }
    friend constexpr bool operator!=(iterator l, iterator r) noexcept { return l.rest_ != r.rest_; }

   private:
    friend class axis_set;
    constexpr explicit iterator(unsigned rest) noexcept : rest_(rest) {}
    unsigned rest_ = 0;  // the axes not walked yet
  };
  constexpr iterator begin() const noexcept { return iterator(mask_); }
  constexpr iterator end() const noexcept { return iterator(0); }

 private:
  static constexpr unsigned all_mask = (1u << axes) - 1;
  unsigned mask_ = 0;
};

constexpr axis_set operator|(axis_set l, axis_set r) noexcept { return l |= r; }
constexpr axis_set operator&(axis_set l, axis_set r) noexcept { return l &= r; }

/// An interpolated move (X4Load): the longest path leads at freq_hz.
struct move {
  std::array<long, axes> steps{};     ///< per axis, signed
  int freq_hz = 1000;                 ///< leader frequency, 10..20000
  std::chrono::milliseconds ramp{0};  ///< 0..1000 ms, and ms <= Hz
};

/// Why a move is invalid, or errc::ok.
/// The same checks, in the same order, as the kernel's.
errc check(const move &m) noexcept;
/// Checks of an endless move's frequency and ramp.
errc check_endless(int freq_hz, std::chrono::milliseconds ramp) noexcept;

enum class direction { positive, negative };

/// Output signals of X4SetOut.
enum class signal { one = 1, two = 2 };  ///< pin 1, pin 14

/// A snapshot of a port.
struct status {
  bool active = false;                  ///< a move runs (AKTIV)
  bool loaded = false;                  ///< a move is loaded
  bool controlled = false;              ///< a controller has the port
  std::array<long long, axes> steps{};  ///< since the last start
  unsigned inputs = 0;                  ///< X4GetIn bits
  /// The inputs were not read now: no controller has the port (another
  /// parport driver may own it, and the module leaves it alone), so they
  /// are the levels last read while one had it, at inputs_time. Never set
  /// for a controller's own reads.
  bool inputs_stale = false;
  std::chrono::steady_clock::time_point inputs_time{};  ///< when the inputs were read (epoch: never)
  unsigned outputs = 0;                                 ///< bit0 pin 1, bit1 pin 14, bit2 BOOST, bit3 AKTIV
  unsigned data = 0;                                    ///< pin levels of pins 2..9
  int last_brake_code = 0;                              ///< key code that braked the last move
  std::uint64_t moves_ended = 0;
};
std::ostream &operator<<(std::ostream &os, const status &s);

/// How a port drives its motors.
enum class output_mode {
  clock_dir = 0,       ///< step and direction signals (X4Step)
  smc_phase = 1,       ///< SMC800/SMC1500 half-step phase patterns, motors off at rest
  smc_phase_hold = 2,  ///< the same, reduced holding current at rest
};

/// Per-port wiring: config{}.clock_invert(axis::x).mode(output_mode::smc_phase).
class config {
 public:
  /// These axes take active-low clocks.
  constexpr config &clock_invert(axis_set s) noexcept { return set(clock_invert_, s); }
  /// These axes' directions are inverted.
  constexpr config &dir_invert(axis_set s) noexcept { return set(dir_invert_, s); }
  /// Brake keys pressed while moving do not reach applications.
  constexpr config &keys_swallow(bool on) noexcept { return set(keys_swallow_, on); }
  constexpr config &mode(output_mode m) noexcept { return set(mode_, m); }

  constexpr axis_set clock_invert() const noexcept { return clock_invert_; }
  constexpr axis_set dir_invert() const noexcept { return dir_invert_; }
  constexpr bool keys_swallow() const noexcept { return keys_swallow_; }
  constexpr output_mode mode() const noexcept { return mode_; }

 private:
  template <typename T>
  constexpr config &set(T &field, T value) noexcept {
    field = value;
    return *this;
  }
  axis_set clock_invert_, dir_invert_;
  bool keys_swallow_ = false;
  output_mode mode_ = output_mode::clock_dir;
};

/// Step signal timing of a port; each time at most 1 ms:
/// step_timing{}.pulse(5us).space(5us).dir_setup(20us).
class step_timing {
 public:
  using ns = std::chrono::nanoseconds;
  /// Clock high time; 0 (default): the symmetric clock of X4Step.
  constexpr step_timing &pulse(ns t) noexcept { return set(pulse_, t); }
  /// Minimum clock low time; default 0.
  constexpr step_timing &space(ns t) noexcept { return set(space_, t); }
  /// Directions before the first step; default 100 us.
  constexpr step_timing &dir_setup(ns t) noexcept { return set(dir_setup_, t); }
  /// Directions held after the last step; default 0.
  constexpr step_timing &dir_hold(ns t) noexcept { return set(dir_hold_, t); }

  constexpr ns pulse() const noexcept { return pulse_; }
  constexpr ns space() const noexcept { return space_; }
  constexpr ns dir_setup() const noexcept { return dir_setup_; }
  constexpr ns dir_hold() const noexcept { return dir_hold_; }

 private:
  constexpr step_timing &set(ns &field, ns value) noexcept {
    field = value;
    return *this;
  }
  ns pulse_{0}, space_{0}, dir_setup_{100000}, dir_hold_{0};
};

// ---- positioning -----------------------------------------------------------

constexpr unsigned vel_max = 100000;   ///< steps/s
constexpr unsigned acc_max = 1000000;  ///< steps/s^2

/// Ramp of an axis' own moves (ProStep4 section 2.5): the axis starts at
/// v0, accelerates with a0 to vm, decelerates with ae to ve and stops
/// there; a0 or ae 0: no ramp on that side. Rules: 1 <= vm <= vel_max,
/// v0 <= vm, ve <= vm, a0, ae <= acc_max, and a ramp from rest to vm at
/// most 3600 s long: vm / a0 and vm / ae (when not 0) at most 3600 s.
/// profile{}.start_speed(100).top_speed(5000).accel(20000).decel(20000).end_speed(100)
class profile {
 public:
  /// v0, steps/s; default 0.
  constexpr profile &start_speed(unsigned v) noexcept { return set(v0_, v); }
  /// vm, steps/s; default 1000.
  constexpr profile &top_speed(unsigned v) noexcept { return set(vm_, v); }
  /// ve, steps/s; default 0.
  constexpr profile &end_speed(unsigned v) noexcept { return set(ve_, v); }
  /// a0, steps/s^2; default 1000.
  constexpr profile &accel(unsigned a) noexcept { return set(a0_, a); }
  /// ae, steps/s^2; default 1000.
  constexpr profile &decel(unsigned a) noexcept { return set(ae_, a); }

  constexpr unsigned start_speed() const noexcept { return v0_; }
  constexpr unsigned top_speed() const noexcept { return vm_; }
  constexpr unsigned end_speed() const noexcept { return ve_; }
  constexpr unsigned accel() const noexcept { return a0_; }
  constexpr unsigned decel() const noexcept { return ae_; }

  friend constexpr bool operator==(const profile &l, const profile &r) noexcept {
    return l.v0_ == r.v0_ && l.vm_ == r.vm_ && l.ve_ == r.ve_ && l.a0_ == r.a0_ && l.ae_ == r.ae_;
  }
  friend constexpr bool operator!=(const profile &l, const profile &r) noexcept { return !(l == r); }

 private:
  constexpr profile &set(unsigned &field, unsigned value) noexcept {
    field = value;
    return *this;
  }
  unsigned v0_ = 0, vm_ = 1000, ve_ = 0, a0_ = 1000, ae_ = 1000;
};

/// How halt() ends moves.
enum class halt_mode {
  brake,  ///< along the ramp
  stop,   ///< at once: the axes lose their synchronization
};

/// A reference run (ProStep4 section 3), without ramps: phase 1 at vref1
/// until the REF input becomes active, where it stops (or, with `brake`,
/// brakes past it along the axis' profile ae: REF must stay active over
/// that distance, else axis_error::ref_passed); phase 2, 50 ms later from
/// rest, at vref2 until REF changes again, where it stops, zeroing the
/// coordinate and synchronizing the axis. Each phase travels at most sref
/// steps. Speeds are signed (the sign is the direction), 1..vel_max
/// steps/s; sref 1..2^31 - 1; at least one phase.
/// homing{}.phase1_speed(-2000).phase2_speed(200).max_travel(50000)
class homing {
 public:
  /// vref1, steps/s, signed; default -1000.
  constexpr homing &phase1_speed(int v) noexcept { return set(vref1_, v); }
  /// vref2, steps/s, signed; default 100.
  constexpr homing &phase2_speed(int v) noexcept { return set(vref2_, v); }
  /// sref, steps per phase; default 100000.
  constexpr homing &max_travel(unsigned long s) noexcept { return set(sref_, s); }
  /// Run phase 1; default true.
  constexpr homing &phase1(bool on) noexcept { return set(phase1_, on); }
  /// Run phase 2; default true.
  constexpr homing &phase2(bool on) noexcept { return set(phase2_, on); }
  /// Phase 1 brakes past REF along the axis' ae; default false.
  constexpr homing &brake(bool on) noexcept { return set(brake_, on); }

  constexpr int phase1_speed() const noexcept { return vref1_; }
  constexpr int phase2_speed() const noexcept { return vref2_; }
  constexpr unsigned long max_travel() const noexcept { return sref_; }
  constexpr bool phase1() const noexcept { return phase1_; }
  constexpr bool phase2() const noexcept { return phase2_; }
  constexpr bool brake() const noexcept { return brake_; }

 private:
  template <typename T>
  constexpr homing &set(T &field, T value) noexcept {
    field = value;
    return *this;
  }
  int vref1_ = -1000, vref2_ = 100;
  unsigned long sref_ = 100000;
  bool phase1_ = true, phase2_ = true, brake_ = false;
};

/// Inputs 1..5 (X4GetIn bit 0..4) per axis, 0 = none; nc bit k: input k+1
/// normally closed (active while LOW; normally open ones while HIGH). An
/// input may serve several axes and both directions (switches in parallel).
struct switches {
  std::array<int, axes> ref{};    ///< reference switch of each axis
  std::array<int, axes> plus{};   ///< limit E+
  std::array<int, axes> minus{};  ///< limit E-
  unsigned nc = 0;
};

/// Error bits of an axis (ProStep4's error register), cleared by its next move.
namespace axis_error {
constexpr unsigned ref_travel = 1;   ///< a reference phase went beyond sref
constexpr unsigned limit_pos = 2;    ///< stopped at E+
constexpr unsigned limit_neg = 4;    ///< stopped at E-
constexpr unsigned ambiguous = 8;    ///< the input serves other limits too: maybe not this axis' switch
constexpr unsigned ref_passed = 16;  ///< phase 1's brake ran off the REF switch
}  // namespace axis_error

/// One axis (ProStep4's status register).
struct axis_status {
  long position = 0;      ///< machine coordinate (signed 32 bits, wrapping)
  unsigned velocity = 0;  ///< current speed, steps/s
  unsigned error = 0;     ///< axis_error bits
  bool running = false;   ///< the axis moves
  bool synced = false;    ///< the coordinate is referenced
  bool ref1 = false;      ///< reference run, phase 1
  bool ref2 = false;      ///< reference run, phase 2
  bool accelerating = false, cruising = false, decelerating = false;
};

/// Every axis, the inputs, and which inputs' switches are active.
struct axes_status {
  std::array<axis_status, axes> axis{};  ///< axis[i]: axis i + 1; or use (*this)[a]
  const axis_status &operator[](x4step::axis a) const noexcept { return axis[a.index()]; }
  unsigned inputs = 0;           ///< X4GetIn bits
  unsigned switches_active = 0;  ///< bit k: input k + 1 is active (after NO/NC)
  bool inputs_stale = false;     ///< inputs and switches_active as last read (see status::inputs_stale)
};
std::ostream &operator<<(std::ostream &os, const axes_status &s);

// ---- events ------------------------------------------------------------------

/// What happened on a port (linux/x4step.h, x4step_event). A newer module
/// may send types and `how` values this library does not name: the enums
/// then hold the number, and a reader should skip what it does not know.
enum class event_type {
  move_started = 1,  ///< how: move_kind
  move_ended = 2,    ///< how: end_reason
  brake = 3,         ///< a brake was asked for; how: brake_source, value: the key's code
  switch_hit = 4,    ///< a switch stopped a move; how: switch_kind, value: the input 1..5
  controller = 5,    ///< how: controller_change
  port_gone = 6,     ///< the port went away: the last event
};
enum class move_kind { loaded = 1, endless = 2, go_to = 3, home = 4 };
enum class end_reason {
  completed = 1,   ///< as planned
  braked = 2,      ///< a brake was asked for while it ran
  stopped = 3,     ///< at once (stop, halt, set_position, the port's removal)
  limit = 4,       ///< a limit switch
  homed = 5,       ///< reference run done: at 0, synchronized
  ref_found = 6,   ///< a phase-1-only reference run found REF
  ref_travel = 7,  ///< a reference phase went beyond sref
  ref_passed = 8,  ///< phase 1's brake ran off the REF switch
};
/// brake()/halt(), a brake key, the controller's close, and
/// monitor::emergency_halt() (value: 0 brake, 1 stop, as halt_mode).
enum class brake_source { request = 1, key = 2, close = 3, emergency = 4 };
/// probe: a probing segment's input (path_config::probe_input) reached the
/// state it waits for; axes: the path's; its end follows (the queue flushed).
enum class switch_kind { limit_pos = 1, limit_neg = 2, ref = 3, probe = 4 };
enum class controller_change { opened = 1, closed = 2, released = 3 };  ///< released: a controller may open

struct event {
  std::uint64_t seq = 0;                         ///< 1, 2, 3, ... per port: a gap is events missed
  std::chrono::steady_clock::time_point time{};  ///< CLOCK_MONOTONIC
  event_type type{};
  axis_set axes;                              ///< the axes concerned
  unsigned how = 0;                           ///< by type: move_kind, end_reason, ...
  unsigned value = 0;                         ///< key code (brake by key), input 1..5 (switch)
  bool ambiguous = false;                     ///< switch: the input serves other limits too
  std::array<long, x4step::axes> position{};  ///< every axis' coordinate then
};
/// "#12 move ended: axes 1 2, braked, at 100 -50 0 0"
std::ostream &operator<<(std::ostream &os, const event &e);

/// Why a profile is invalid (param_fail), or errc::ok: the kernel's rules.
errc check(const profile &p) noexcept;
/// Why a reference run is invalid (param_fail), or errc::ok.
errc check(const homing &h) noexcept;

/// Device path of LPT1..4 (/dev/x4step0..3); throws param_fail otherwise.
std::string device_path(int lpt);

/// The library's version, "major.minor.patch" (libx4stepcxx.so.major).
const char *version() noexcept;

/// Whether name is meant for the simulated port rather than a device node:
/// "sim", "sim:N", and misspellings such as "sim0" or "sim:7" (names that
/// start with "sim" without a '/'), which the constructors refuse saying so.
bool is_sim_name(const std::string &name) noexcept;
/// Whether X4STEP_SIM asks for the simulated ports: true for "1" (LPT1..4
/// are sim:0..3), false when it is unset, "" or "0". Any other value throws
/// lpt_not_found, its what() naming the value and the good ones.
bool env_wants_sim();
/// The reference and limit switches of the simulated machine
/// (X4STEP_SIM_MACHINE), as set_switches() takes them: a simulated port
/// keeps no settings between programs, so a program that relies on the
/// switches sets them. None when no machine is set or it has no switches.
/// Throws lpt_not_found, naming the file and line, for a bad machine file
/// (as opening a simulated port does).
std::optional<switches> sim_machine_switches();

namespace detail {
struct access;
}

/// Owns one port: the only one that moves its motors. Move-only.
/// Destroying it while motors run brakes them along the ramp first, and
/// waits until they stand (see close()).
class controller {
 public:
  /// Open LPT1..4. Throws lpt_not_found if the port is missing or taken;
  /// when taken, what() says by whom: another controller (or the module
  /// still braking the motors of one that was killed), or another parport
  /// driver such as ppdev (a program using /dev/parportN) or lp.
  explicit controller(int lpt);
  /// Open a device node by path.
  explicit controller(const std::filesystem::path &path);
  controller(controller &&other) noexcept;
  controller &operator=(controller &&other) noexcept;
  controller(const controller &) = delete;
  controller &operator=(const controller &) = delete;
  ~controller();

  explicit operator bool() const noexcept;  ///< open (not closed)
  const std::string &path() const noexcept;
  /// The descriptor, for event loops (poll, epoll, Qt's QSocketNotifier,
  /// asyncio): readable (POLLIN) while no move runs, POLLPRI when an event
  /// is there to read_event(), POLLERR | POLLHUP once the port is gone
  /// (with PORT_GONE the last event). Opened O_NONBLOCK; owned by this
  /// object; -1 when closed. A simulated port ("sim") gives an eventfd,
  /// readable while the module's would poll POLLIN or POLLPRI: read_event()
  /// or get_status() tell which; it has no POLLOUT of its own. In virtual
  /// time the clock moves only in this library's calls (waits, status),
  /// so a loop that only polls fd() waits for ever.
  int fd() const noexcept;

  void load(const move &m);  ///< prepare (or preload while running)
  void start();              ///< run the loaded move; clears the counters
  void brake();              ///< decelerate along the ramp to rest
  void stop();               ///< emergency stop, no ramp
  void move_endless(axis a, direction dir, int freq_hz, std::chrono::milliseconds ramp);

  status get_status() const;
  bool active() const;
  long long steps(axis a) const;
  unsigned inputs() const;

  /// Block until no move runs (poll(), no spinning). False on timeout;
  /// a negative timeout waits for ever.
  bool wait(std::chrono::milliseconds timeout = std::chrono::milliseconds(-1)) const;

  void set_output(signal s, bool high);
  /// Up to 20 set-1 key codes (1..127 make, 129..255 break); ESC always brakes.
  void set_brake_codes(const std::vector<int> &codes);
  void set_config(const config &c);
  config get_config() const;
  /// Moves that cannot fit the timing are then refused with freq_too_high.
  void set_step_timing(const step_timing &t);
  step_timing get_step_timing() const;

  // Positioning. Bad arguments throw param_fail before the kernel is
  // asked; so does an empty axis_set. A move or setting of a moving axis:
  // is_active.

  void set_profile(axis a, const profile &p);
  profile get_profile(axis a) const;
  /// Independent move of one axis to a coordinate (-2^31..2^31 - 1) with its
  /// profile; other axes may be moving meanwhile, this one must be idle.
  void move_to(axis a, long target);
  void move_by(axis a, long distance);
  /// Independent moves of the axes in the set, all started at once: to
  /// targets[i], or by them if relative. An axis at its target does not move.
  void move_to(axis_set s, const std::array<long, axes> &targets, bool relative = false);
  /// A reference run of one axis; needs its REF input (set_switches).
  void home(axis a, const homing &h);
  /// Brake or stop the moves of the axes in the set, with the axes moving
  /// interpolated with them. not_active if none of them moves.
  void halt(axis_set s, halt_mode how);
  /// "Stop and zero": stops the axis at once (with its interpolated
  /// partners), sets its coordinate and marks it synchronized.
  void set_position(axis a, long position);
  void zero(axis a) { set_position(a, 0); }
  /// Reference and limit inputs; only while no move runs.
  void set_switches(const switches &s);
  switches get_switches() const;
  axes_status get_axes() const;
  axis_status get_axis(axis a) const;
  /// Block until none of the axes in the set runs; false on timeout
  /// (negative: for ever). Other axes may go on moving.
  bool wait_axes(axis_set s, std::chrono::milliseconds timeout = std::chrono::milliseconds(-1)) const;

  /// The next event of the port (from the controller's open on), waiting
  /// up to timeout (negative: for ever); none on timeout or signal.
  /// Throws lpt_not_found once the port is gone and every event was read.
  std::optional<event> read_event(std::chrono::milliseconds timeout = std::chrono::milliseconds(-1)) const;

  /// The port's clock, on which the timeouts of the waits count: the
  /// steady clock, or a simulated port's own in virtual time
  /// (X4STEP_SIM_TIME=virtual).
  std::chrono::steady_clock::time_point now() const;
  /// False for a simulated port in virtual time: its clock moves only in
  /// this library's calls (waits, status reads, sleep_for()).
  bool clock_runs() const;
  /// Lets d pass on the port's clock: sleeps for d; a simulated port in
  /// virtual time instead moves its clock by d at once, running the moves
  /// and events due meanwhile.
  void sleep_for(std::chrono::nanoseconds d);

  /// Release the port now (what the destructor does); idempotent. Brakes
  /// running motors along their ramps and waits until they stand (for as
  /// long as the brake takes; the port going away ends the wait), so that
  /// the next controller can open at once. Never throws.
  void close() noexcept;

 private:
  friend struct detail::access;
  struct impl;
  const impl &need() const;  // throws init_not_done after close()
  std::unique_ptr<impl> impl_;
};

/// Watches a port without disturbing its controller. Move-only.
class monitor {
 public:
  explicit monitor(int lpt);
  explicit monitor(const std::filesystem::path &path);
  monitor(monitor &&other) noexcept;
  monitor &operator=(monitor &&other) noexcept;
  ~monitor();

  explicit operator bool() const noexcept;  ///< open (not closed)
  const std::string &path() const noexcept;
  int fd() const noexcept;  ///< as controller::fd()
  /// Close the descriptor now; idempotent. Afterwards calls throw
  /// init_not_done.
  void close() noexcept;

  status get_status() const;
  /// As controller::wait; after a controller closed during a brake, until
  /// the module has braked to rest and released the port, so that a
  /// controller can open when this returns true.
  bool wait(std::chrono::milliseconds timeout = std::chrono::milliseconds(-1)) const;
  axes_status get_axes() const;
  /// As controller::wait_axes.
  bool wait_axes(axis_set s, std::chrono::milliseconds timeout = std::chrono::milliseconds(-1)) const;
  /// The next event of the port, from this monitor's construction on: as
  /// controller::read_event. The module keeps the last 256 events; a
  /// monitor that fell further behind sees a gap in event::seq.
  std::optional<event> read_event(std::chrono::milliseconds timeout = std::chrono::milliseconds(-1)) const;
  /// The emergency halt (X4STEP_ESTOP): brakes or stops every move on the
  /// port, whoever controls it; a read-only open (group lp) is enough.
  /// Returns at once (wait() for the rest). Throws not_active if no move
  /// runs; with a module older than the ioctl, std::errc::not_supported.
  void emergency_halt(halt_mode how) const;
  /// The interface version of the module serving the port (X4STEP_GET_INFO).
  unsigned abi_version() const;

 private:
  struct impl;
  std::unique_ptr<impl> impl_;
};

}  // namespace x4step

#pragma GCC visibility pop

namespace std {
template <>
struct is_error_code_enum<x4step::errc> : true_type {};
}  // namespace std

#endif  // X4STEP_HPP
