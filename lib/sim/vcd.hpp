// SPDX-License-Identifier: LGPL-2.1-or-later
// A VCD file of the simulated port's pins, with x4trace's signal names
// (pin01_signal1, pin02_dir1, pin03_clk1, ..., pin17_aktiv), so that the
// same viewer setup shows a simulated run and a QEMU trace. Internal.
#ifndef X4STEP_SIM_VCD_HPP
#define X4STEP_SIM_VCD_HPP

#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>

namespace x4step::sim {

class vcd_writer {
 public:
  /// Creates the file; throws an x4step::error naming it if it cannot.
  explicit vcd_writer(const std::string &path);
  vcd_writer(const vcd_writer &) = delete;
  vcd_writer &operator=(const vcd_writer &) = delete;
  ~vcd_writer();

  /// The pins after a port write at t_ns: data register, control outputs
  /// as pin levels (X4_CTL_*). Only changed pins are written.
  void write(std::uint64_t t_ns, std::uint8_t data, std::uint8_t ctl);

 private:
  struct closer {
    void operator()(std::FILE *f) const { std::fclose(f); }
  };
  std::unique_ptr<std::FILE, closer> f_;
  std::string path_;
  int levels_[12];
  bool any_ = false;
  std::uint64_t last_t_ = 0;
};

}  // namespace x4step::sim

#endif  // X4STEP_SIM_VCD_HPP
