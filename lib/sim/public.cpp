// SPDX-License-Identifier: LGPL-2.1-or-later
// The simulator's public functions (x4step.hpp): whether a name or the
// environment asks for it, and the switches of its machine.
#include "options.hpp"
#include "x4step.hpp"

namespace x4step {

bool is_sim_name(const std::string &name) noexcept { return sim::is_sim_name(name); }

bool env_wants_sim() { return sim::env_wants_sim(); }

std::optional<switches> sim_machine_switches() {
  const sim::options o = sim::options_from_env();
  if (o.model.switches().empty()) return std::nullopt;
  switches s;
  for (const sim::machine_switch &w : o.model.switches()) {
    const int input = w.bit + 1;
    const auto axis = static_cast<std::size_t>(w.axis);
    switch (w.what) {
      case sim::machine_switch::kind::ref:
        s.ref[axis] = input;
        break;
      case sim::machine_switch::kind::plus:
        s.plus[axis] = input;
        break;
      case sim::machine_switch::kind::minus:
        s.minus[axis] = input;
        break;
      case sim::machine_switch::kind::probe:  // the path's (path_config::probe_input)
        continue;
    }
    if (w.nc) s.nc |= 1u << w.bit;
  }
  return s;
}

}  // namespace x4step
