// SPDX-License-Identifier: LGPL-2.1-or-later
// The simulated port as the library's seam sees it. Internal.
#ifndef X4STEP_SIM_SIM_HPP
#define X4STEP_SIM_SIM_HPP

#include <memory>
#include <string>

#include "../port_io.hpp"

namespace x4step::sim {

/// Open sim:N (name "sim" or "sim:N") with the settings of the
/// environment (options.hpp); O_RDWR: the controller, else a monitor.
std::unique_ptr<detail::port_io> open(const std::string &name, int flags);

}  // namespace x4step::sim

#endif  // X4STEP_SIM_SIM_HPP
