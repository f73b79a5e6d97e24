// SPDX-License-Identifier: LGPL-2.1-or-later
// The machine behind the simulated port: its axes move with the step and
// direction pins, its switches drive inputs, and a script sets the other
// inputs at given times. The model is the QEMU virtual port's
// (tests/qemu/fixtures/x4vport.c: positions, switches "below|above AT HYST no|nc",
// switches on one input in parallel), so that both machines agree; the
// file names the switches as ProStep4 does (REF, E+, E-), and a path's
// probe (a touch plate, a tool setter) as "probe". Internal.
#ifndef X4STEP_SIM_MACHINE_HPP
#define X4STEP_SIM_MACHINE_HPP

#include <array>
#include <cstdint>
#include <istream>
#include <string>
#include <vector>

namespace x4step::sim {

/// A switch on an axis (x4vport's struct x4v_switch).
struct machine_switch {
  enum class kind { ref, plus, minus, probe };
  kind what = kind::ref;
  int axis = 0;           ///< 0..3
  std::int64_t at = 0;    ///< machine position in steps
  bool above = false;     ///< active at position >= at, else <= at
  std::int64_t hyst = 0;  ///< stays active until more than hyst steps back
  int bit = 0;            ///< the input, X4GetIn bit 0..4
  bool nc = false;        ///< normally closed: the pin is LOW while active
  int line = 0;           ///< where it was given, for errors
  bool active = false;
};

/// Input levels set from a time on (engine time, ns).
struct input_change {
  std::uint64_t t_ns;
  unsigned mask;    ///< X4GetIn bits set
  unsigned levels;  ///< their levels
};

class machine {
 public:
  /// Reads a machine file (README, "Try it without a parallel port");
  /// `name` names it in errors. Throws an x4step::error naming the file,
  /// the line and what to fix.
  void read(std::istream &in, const std::string &name);
  /// Adds X4STEP_SIM_INPUTS ("T_MS:PIN=LEVEL,..."); throws as read().
  void add_script(const std::string &spec);

  /// A data register write: each rising clock edge moves its axis one
  /// step, up if the direction pin is HIGH (as x4vport counts).
  void write_data(std::uint8_t data);
  /// The input levels (X4GetIn bits) at engine time t_ns: the script's
  /// changes due by then, the switches over the inputs they drive.
  unsigned inputs(std::uint64_t t_ns);
  /// Sets the levels of the inputs no switch drives.
  void set_inputs(unsigned levels) { levels_ = levels & 0x1f; }

  const std::array<std::int64_t, 4> &positions() const noexcept { return pos_; }
  /// Puts the axes where a previous program left them (X4STEP_SIM_STATE).
  void set_positions(const std::array<std::int64_t, 4> &p) {
    pos_ = p;
    update_switches();
  }
  const std::vector<machine_switch> &switches() const noexcept { return sw_; }

 private:
  void add_switch(machine_switch s, const std::string &where);
  void add_change(input_change c, const std::string &where);
  void update_switches();

  std::vector<machine_switch> sw_;
  std::vector<input_change> script_;  // by time
  std::size_t script_next_ = 0;
  std::array<std::int64_t, 4> pos_{};
  unsigned levels_ = 0;  // the inputs no switch drives
  unsigned driven_ = 0;  // X4GetIn bits with a switch
  unsigned nc_ = 0;      // ... of which normally closed
  std::uint8_t data_ = 0;
};

}  // namespace x4step::sim

#endif  // X4STEP_SIM_MACHINE_HPP
