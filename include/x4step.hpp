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
 */
#ifndef X4STEP_HPP
#define X4STEP_HPP

#include <array>
#include <chrono>
#include <cstdint>
#include <iosfwd>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

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
  unsigned outputs = 0;                 ///< bit0 pin 1, bit1 pin 14, bit2 BOOST, bit3 AKTIV
  unsigned data = 0;                    ///< pin levels of pins 2..9
  int last_brake_code = 0;              ///< key code that braked the last move
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

/// Device path of LPT1..4 (/dev/x4step0..3); throws param_fail otherwise.
std::string device_path(int lpt);

/// Owns one port: the only one that moves its motors. Move-only.
/// Destroying it while motors run brakes them along the ramp first.
class controller {
 public:
  /// Open LPT1..4. Throws lpt_not_found if the port is missing or taken.
  explicit controller(int lpt);
  /// Open a device node by path.
  explicit controller(const std::string &path);
  controller(controller &&other) noexcept;
  controller &operator=(controller &&other) noexcept;
  controller(const controller &) = delete;
  controller &operator=(const controller &) = delete;
  ~controller();

  explicit operator bool() const noexcept;
  const std::string &path() const noexcept;

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

  /// Release the port now (what the destructor does); idempotent.
  void close();

 private:
  struct impl;
  const impl &need() const;  // throws init_not_done after close()
  std::unique_ptr<impl> impl_;
};

/// Watches a port without disturbing its controller. Move-only.
class monitor {
 public:
  explicit monitor(int lpt);
  explicit monitor(const std::string &path);
  monitor(monitor &&other) noexcept;
  monitor &operator=(monitor &&other) noexcept;
  ~monitor();

  status get_status() const;
  bool wait(std::chrono::milliseconds timeout = std::chrono::milliseconds(-1)) const;

 private:
  struct impl;
  std::unique_ptr<impl> impl_;
};

}  // namespace x4step

namespace std {
template <>
struct is_error_code_enum<x4step::errc> : true_type {};
}  // namespace std

#endif  // X4STEP_HPP
