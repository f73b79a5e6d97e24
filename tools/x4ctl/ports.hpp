// SPDX-License-Identifier: GPL-2.0
// x4ctl: what is known of a port's holder, for messages and `x4ctl list`.
#ifndef X4CTL_PORTS_HPP
#define X4CTL_PORTS_HPP

#include <sys/types.h>

#include <optional>
#include <string>

namespace x4ctl {

/// A process with the device open for writing: the port's controller.
struct holder {
  pid_t pid = 0;
  std::string name;  ///< its /proc/PID/comm
  bool is_x4ctl() const { return name.rfind("x4ctl", 0) == 0; }
};

/// A line of `x4ctl list`: a port, its module, who holds it.
struct port_entry {
  std::string device;      ///< /dev/x4stepN, or sim:N
  int parport = 0;         ///< N
  bool simulated = false;  ///< sim:N: libx4step's simulated port (LPT N+1)
  unsigned abi = 0;        ///< the module's interface version; 0: not read
  bool controlled = false;
  std::optional<holder> controller;  ///< the process, when visible here
  std::string claimant;              ///< the parport driver that has the port, "" none
  std::string error;                 ///< why the port could not be read, "" if it was
  int err = 0;                       ///< its errno, 0 unknown
};

}  // namespace x4ctl

#endif  // X4CTL_PORTS_HPP
