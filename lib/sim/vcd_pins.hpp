// SPDX-License-Identifier: LGPL-2.1-or-later
// The connector's output pins as VCD wires, in VCD order: the simulated
// port writes them (vcd.cpp), tools/x4trace writes and reads them. Header
// only and on its own, so that x4trace, built from one file, includes it.
#ifndef X4STEP_SIM_VCD_PINS_HPP
#define X4STEP_SIM_VCD_PINS_HPP

namespace x4step::sim {

/// A pin: its connector number and its wire's name.
struct vcd_pin {
  int number;
  const char *name;
};

inline constexpr vcd_pin vcd_pins[] = {
    {1, "pin01_signal1"}, {2, "pin02_dir1"},     {3, "pin03_clk1"},   {4, "pin04_dir2"},
    {5, "pin05_clk2"},    {6, "pin06_dir3"},     {7, "pin07_clk3"},   {8, "pin08_dir4"},
    {9, "pin09_clk4"},    {14, "pin14_signal2"}, {16, "pin16_boost"}, {17, "pin17_aktiv"},
};
inline constexpr int vcd_n_pins = sizeof vcd_pins / sizeof vcd_pins[0];

}  // namespace x4step::sim

#endif  // X4STEP_SIM_VCD_PINS_HPP
