// SPDX-License-Identifier: LGPL-2.1-or-later
// libx4step: which port a name opens (port_io.hpp): the module's device,
// or the simulated port.
#include "detail.hpp"
#include "port_io.hpp"
#include "sim/options.hpp"
#include "sim/sim.hpp"

namespace x4step::detail {

std::unique_ptr<port_io> open_port(const std::string &name, int flags) {
  if (sim::is_sim_name(name)) return sim::open(name, flags);
  return open_kernel_port(name, flags);
}

std::string port_name(int lpt) {
  if (lpt < 1 || lpt > 4) fail(errc::param_fail);
  if (sim::env_wants_sim()) return "sim:" + std::to_string(lpt - 1);
  return device_path(lpt);
}

}  // namespace x4step::detail
