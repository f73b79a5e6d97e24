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
 * switches. Axes are numbered 1..4; in an axis mask bit i is axis i + 1.
 *
 * @code
 *   x4step::controller c(1);
 *   x4step::switches sw;
 *   sw.ref[0] = 1;                                            // REF of axis 1 on input 1 (pin 15)
 *   c.set_switches(sw);
 *   c.home(1, x4step::homing{});                              // both phases
 *   c.wait_axes(0x1);
 *   c.set_profile(1, {0, 0, 5000, 20000, 20000});
 *   c.move_to(1, 12000);
 *   c.wait_axes(0x1);
 *   std::cout << c.get_axes() << '\n';
 * @endcode
 */
#ifndef X4STEP_HPP
#define X4STEP_HPP

#include <array>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <iosfwd>
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

/// An interpolated move (X4Load): the longest path leads at freq_hz.
struct move {
  std::array<long, axes> steps{};     ///< per axis, signed
  int freq_hz = 1000;                 ///< leader frequency, 10..20000
  std::chrono::milliseconds ramp{0};  ///< 0..1000 ms, and ms <= Hz
};

/// Why a move is invalid, or errc::ok.
/// The same checks, in the same order, as the kernel's.
errc check(const move &m) noexcept;
/// Checks of an endless move's axis (1..4), frequency and ramp.
errc check_endless(int axis, int freq_hz, std::chrono::milliseconds ramp) noexcept;

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

/// Per-port wiring.
struct config {
  unsigned clock_invert = 0;  ///< bit i: axis i+1 takes active-low clocks
  unsigned dir_invert = 0;    ///< bit i: axis i+1 direction inverted
  bool keys_swallow = false;  ///< brake keys pressed while moving do not reach applications
  output_mode mode = output_mode::clock_dir;
};

/// Step signal timing of a port; each time at most 1 ms.
struct step_timing {
  std::chrono::nanoseconds pulse{0};           ///< clock high time; 0: symmetric clock (X4Step)
  std::chrono::nanoseconds space{0};           ///< minimum clock low time
  std::chrono::nanoseconds dir_setup{100000};  ///< directions before the first step
  std::chrono::nanoseconds dir_hold{0};        ///< directions after the last step
};

// ---- positioning -----------------------------------------------------------

constexpr unsigned vel_max = 45000;    ///< steps/s
constexpr unsigned acc_max = 1000000;  ///< steps/s^2

/// Ramp of an axis' own moves (ProStep4 section 2.5): the axis starts at
/// v0, accelerates with a0 to vm, decelerates with ae to ve and stops
/// there; a0 or ae 0: no ramp on that side. Rules: 1 <= vm <= vel_max,
/// v0 <= vm, ve <= vm, a0, ae <= acc_max, and a ramp from rest to vm at
/// most 3600 s long: vm / a0 and vm / ae (when not 0) at most 3600 s.
struct profile {
  unsigned v0 = 0;     ///< start velocity, steps/s
  unsigned ve = 0;     ///< stop velocity, steps/s
  unsigned vm = 1000;  ///< maximum velocity, steps/s
  unsigned a0 = 1000;  ///< acceleration, steps/s^2
  unsigned ae = 1000;  ///< deceleration, steps/s^2
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
struct homing {
  int vref1 = -1000;
  int vref2 = 100;
  unsigned long sref = 100000;
  bool phase1 = true;
  bool phase2 = true;
  bool brake = false;  ///< phase 1 brakes past REF along the axis' ae
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
  std::array<axis_status, axes> axis{};
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
enum class switch_kind { limit_pos = 1, limit_neg = 2, ref = 3 };
enum class controller_change { opened = 1, closed = 2, released = 3 };  ///< released: a controller may open

struct event {
  std::uint64_t seq = 0;                         ///< 1, 2, 3, ... per port: a gap is events missed
  std::chrono::steady_clock::time_point time{};  ///< CLOCK_MONOTONIC
  event_type type{};
  unsigned axis_mask = 0;             ///< the axes concerned: bit i is axis i + 1
  unsigned how = 0;                   ///< by type: move_kind, end_reason, ...
  unsigned value = 0;                 ///< key code (brake by key), input 1..5 (switch)
  bool ambiguous = false;             ///< switch: the input serves other limits too
  std::array<long, axes> position{};  ///< every axis' coordinate then
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

// Threads: a controller or a monitor is one open descriptor; its calls
// are not synchronized, so use an object from one thread at a time (or
// lock around it). Distinct objects are independent, also on one port.

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
  /// object; -1 when closed.
  int fd() const noexcept;

  void load(const move &m);  ///< prepare (or preload while running)
  void start();              ///< run the loaded move; clears the counters
  void brake();              ///< decelerate along the ramp to rest
  void stop();               ///< emergency stop, no ramp
  void move_endless(int axis, direction dir, int freq_hz, std::chrono::milliseconds ramp);

  status get_status() const;
  bool active() const;
  long long steps(int axis) const;  ///< axis 1..4
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

  // Positioning. Axes 1..4; bad arguments throw param_fail before the
  // kernel is asked. A move or setting of a moving axis: is_active.

  void set_profile(int axis, const profile &p);
  profile get_profile(int axis) const;
  /// Independent move of one axis to a coordinate (-2^31..2^31 - 1) with its
  /// profile; other axes may be moving meanwhile, this one must be idle.
  void move_to(int axis, long target);
  void move_by(int axis, long distance);
  /// Independent moves of the axes in axis_mask, all started at once: to
  /// targets[i], or by them if relative. An axis at its target does not move.
  void move_to(unsigned axis_mask, const std::array<long, axes> &targets, bool relative = false);
  /// A reference run of one axis; needs its REF input (set_switches).
  void home(int axis, const homing &h);
  /// Brake or stop the moves of the axes in axis_mask, with the axes moving
  /// interpolated with them. not_active if none of them moves.
  void halt(unsigned axis_mask, halt_mode how);
  /// "Stop and zero": stops the axis at once (with its interpolated
  /// partners), sets its coordinate and marks it synchronized.
  void set_position(int axis, long position);
  void zero(int axis) { set_position(axis, 0); }
  /// Reference and limit inputs; only while no move runs.
  void set_switches(const switches &s);
  switches get_switches() const;
  axes_status get_axes() const;
  axis_status axis(int axis) const;
  /// Block until none of the axes in axis_mask runs; false on timeout
  /// (negative: for ever). Other axes may go on moving.
  bool wait_axes(unsigned axis_mask, std::chrono::milliseconds timeout = std::chrono::milliseconds(-1)) const;

  /// The next event of the port (from the controller's open on), waiting
  /// up to timeout (negative: for ever); none on timeout or signal.
  /// Throws lpt_not_found once the port is gone and every event was read.
  std::optional<event> read_event(std::chrono::milliseconds timeout = std::chrono::milliseconds(-1)) const;

  /// Release the port now (what the destructor does); idempotent. Brakes
  /// running motors along their ramps and waits until they stand (for as
  /// long as the brake takes; the port going away ends the wait), so that
  /// the next controller can open at once. Never throws.
  void close() noexcept;

 private:
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
  bool wait_axes(unsigned axis_mask, std::chrono::milliseconds timeout = std::chrono::milliseconds(-1)) const;
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
