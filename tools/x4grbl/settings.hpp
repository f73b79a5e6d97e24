// SPDX-License-Identifier: GPL-2.0
// x4grbl: GRBL's $ settings on an x4step machine. What the machine file
// says ($11 $12 $100.. $110.. $120.. $130.., homing speeds) is read from
// it and written back into it, checked as the file is; what only the
// bridge uses ($1 $4 $10 $13 $26 $30 $31 and the startup blocks $N0 $N1)
// is kept in a file beside it, FILE.grbl ("$10=1" lines, as $$ prints
// them). What belongs to the port or the machine's wiring ($0, $2, $3,
// $5, $6, $20..$23, $27) is shown and can only be set where it is kept.
#ifndef X4GRBL_SETTINGS_HPP
#define X4GRBL_SETTINGS_HPP

#include <array>
#include <map>
#include <string>

#include "machine.hpp"
#include "x4step.hpp"

namespace x4grbl {

/// What the port says for the settings of its wiring.
struct port_facts {
  double pulse_us = 0;
  x4step::axis_set clock_invert, dir_invert;
  unsigned nc = 0;
};

class settings {
 public:
  settings() = default;
  /// Reads FILE.grbl beside the machine file (none: defaults). Throws
  /// std::runtime_error naming file and line for a bad one.
  explicit settings(std::string machine_path);

  /// Every setting, "$N=VALUE" lines, each ending "\r\n".
  std::string report(const x4step::machine::machine &mc, const port_facts &p) const;
  /// $N=VALUE: 0 when it was set (and kept), else GRBL's error code with
  /// `why` saying what to do instead. mc changes with the machine file.
  int set(int number, double value, x4step::machine::machine &mc, const port_facts &p, std::string &why);
  /// $RST=$: the bridge's own settings back to their defaults (0, else
  /// an error code and why: the settings file could not be written).
  int restore_defaults(std::string &why);

  /// $N0 and $N1.
  const std::array<std::string, 2> &startup() const noexcept { return startup_; }
  int set_startup(int n, const std::string &block, std::string &why);

  unsigned status_mask() const { return unsigned(value(10)); }
  bool report_inches() const { return value(13) != 0; }
  double value(int number) const;

 private:
  /// The machine file's part of set(): its lock, its text, its check.
  int change_machine_file(int number, double value, x4step::machine::machine &mc, std::string &why);
  /// Writes these as the settings file and takes them, or leaves all as
  /// it was and says why (a file that cannot be written is no end of x4grbl).
  int keep(const std::map<int, double> &own, const std::array<std::string, 2> &startup, std::string &why);

  std::string machine_path_, path_;
  std::map<int, double> own_;
  std::array<std::string, 2> startup_;
};

}  // namespace x4grbl

#endif  // X4GRBL_SETTINGS_HPP
