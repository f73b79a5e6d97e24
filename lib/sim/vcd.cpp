// SPDX-License-Identifier: LGPL-2.1-or-later
// libx4step: the simulated port's VCD file (vcd.hpp). The header and the
// value lines are as tests/tools/x4trace writes them; the times are the
// simulation's, exact to the ns (writes at one instant 1 ns apart, as in
// x4trace, so that every pulse stays visible).
#include "vcd.hpp"

#include <cerrno>
#include <cstring>

#include "vcd_pins.hpp"
#include "x4step.hpp"

namespace x4step::sim {

static_assert(vcd_n_pins == 12, "pins 1..9, 14, 16, 17: level() and the VCD ids");

namespace {

// Pin i's level after a write: data bits are pins 2..9; the control
// outputs are signal 1, signal 2, BOOST, AKTIV.
int level(int i, std::uint8_t data, std::uint8_t ctl) {
  static const int ctl_bit[4] = {0, 1, 2, 3};
  if (i >= 1 && i <= 8) return (data >> (i - 1)) & 1;
  const int k = i == 0 ? 0 : i - 8;
  return (ctl >> ctl_bit[k]) & 1;
}

}  // namespace

vcd_writer::vcd_writer(const std::string &path) : f_(std::fopen(path.c_str(), "w")), path_(path) {
  if (!f_)
    throw error(make_error_code(errc::lpt_not_found),
                "X4STEP_SIM_VCD=" + path + ": cannot write the VCD file: " + std::strerror(errno) +
                    ": name a writable file");
  std::fputs(
      "$comment x4step simulated port: pin levels at the connector $end\n"
      "$version libx4step $end\n$timescale 1ns $end\n$scope module lpt $end\n",
      f_.get());
  for (int p = 0; p < 12; p++) std::fprintf(f_.get(), "$var wire 1 %c %s $end\n", '!' + p, vcd_pins[p].name);
  std::fputs("$upscope $end\n$enddefinitions $end\n#0\n$dumpvars\n", f_.get());
  for (int p = 0; p < 12; p++) std::fprintf(f_.get(), "x%c\n", '!' + p);
  std::fputs("$end\n", f_.get());
  std::fill(std::begin(levels_), std::end(levels_), -1);
}

vcd_writer::~vcd_writer() {
  if (any_) std::fprintf(f_.get(), "#%llu\n", static_cast<unsigned long long>(last_t_ + 1000));
}

void vcd_writer::write(std::uint64_t t_ns, std::uint8_t data, std::uint8_t ctl) {
  bool stamped = false;
  for (int p = 0; p < 12; p++) {
    const int l = level(p, data, ctl);
    if (l == levels_[p]) continue;
    if (!stamped) {
      const std::uint64_t t = any_ ? std::max(t_ns, last_t_ + 1) : t_ns;
      if (t) std::fprintf(f_.get(), "#%llu\n", static_cast<unsigned long long>(t));
      last_t_ = t;
      any_ = stamped = true;
    }
    levels_[p] = l;
    std::putc(l ? '1' : '0', f_.get());
    std::putc('!' + p, f_.get());
    std::putc('\n', f_.get());
  }
}

}  // namespace x4step::sim
