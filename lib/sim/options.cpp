// SPDX-License-Identifier: LGPL-2.1-or-later
// libx4step: the simulated port's names and settings (options.hpp).
#include "options.hpp"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include "x4step.hpp"

namespace x4step::sim {
namespace {

[[noreturn]] void refuse(const std::string &what) { throw error(make_error_code(errc::lpt_not_found), what); }

}  // namespace

bool is_sim_name(const std::string &name) { return name == "sim" || name.rfind("sim:", 0) == 0; }

int port_number(const std::string &name) {
  if (name == "sim") return 0;
  if (name.size() == 5 && name.rfind("sim:", 0) == 0 && name[4] >= '0' && name[4] <= '3')
    return name[4] - '0';
  refuse(name + ": no such simulated port: use sim (= sim:0) or sim:0 .. sim:3 (LPT1 .. LPT4)");
}

options options_from_env() {
  options o;
  if (const char *t = std::getenv("X4STEP_SIM_TIME"); t && *t) {
    const std::string v(t);
    if (v == "virtual")
      o.time = time_mode::virtual_;
    else if (v != "real")
      refuse("X4STEP_SIM_TIME=" + v + ": use virtual (as fast as possible) or real (the default)");
  }
  if (const char *v = std::getenv("X4STEP_SIM_VCD"); v && *v) o.vcd = v;
  if (const char *m = std::getenv("X4STEP_SIM_MACHINE"); m && *m) {
    std::ifstream in(m);
    if (!in)
      refuse(std::string("X4STEP_SIM_MACHINE=") + m +
             ": cannot read the machine file: " + std::strerror(errno) + ": name a readable file");
    o.model.read(in, m);
  }
  if (const char *s = std::getenv("X4STEP_SIM_INPUTS"); s && *s) o.model.add_script(s);
  return o;
}

bool env_wants_sim() {
  const char *s = std::getenv("X4STEP_SIM");
  return s && *s && std::string(s) != "0";
}

}  // namespace x4step::sim
