// SPDX-License-Identifier: GPL-2.0
// x4ctl on a simulated port (sim.hpp), through the library's public API.
#include "sim.hpp"

#include <cstdlib>
#include <string>

namespace x4ctl {

bool is_sim_device(const std::string &dev) { return x4step::is_sim_name(dev); }

std::string sim_error_text(const x4step::error &e) {
  std::string text = e.what();
  const std::string general = ": " + e.code().message();
  if (text.size() > general.size() &&
      text.compare(text.size() - general.size(), general.size(), general) == 0)
    text.resize(text.size() - general.size());
  return text;
}

std::string sim_elsewhere_text(const std::string &dev, const char *command) {
  const bool follows = std::string(command) == "monitor" || std::string(command) == "watch";
  return dev +
         " is a simulated port: it lives inside the program that opened it, so this x4ctl has a fresh one "
         "of its own, where nothing runs" +
         (follows ? ", and no other program's moves or events can be seen here. Follow a simulated run "
                    "from within: its VCD (X4STEP_SIM_VCD=FILE), or 'x4ctl --sim run FILE' with I and E "
                    "between the moves"
                  : ", and another x4ctl's simulated move cannot be reached. Brake it where it runs: "
                    "Ctrl-C or ESC on its terminal, a brake key script (X4STEP_SIM_KEYS=500ms:esc), or "
                    "a time ('jog --time', 'M+ 500')");
}

std::string sim_forgets_text(const std::string &dev) {
  return "note: " + dev +
         " is a simulated port of this x4ctl alone: the setting ends with it (the module keeps its "
         "settings; a simulated port starts afresh in every program" +
         (sim_state_file().empty()
              ? ")"
              : ", but for the axes' coordinates and synchronization, which X4STEP_SIM_STATE=" +
                    sim_state_file() + " keeps)");
}

std::string sim_state_file() {
  const char *s = std::getenv("X4STEP_SIM_STATE");
  return s ? s : "";
}

bool sim_keys_scripted() {
  const char *k = std::getenv("X4STEP_SIM_KEYS");
  if (!k || !*k) return false;
  const std::string v(k);
  return v != "none" && v != "tty";
}

void wire_machine_switches(x4step::controller &c) {
  if (!is_sim_device(c.path())) return;
  // The library has read the file when it opened the port: it is good.
  if (const auto s = x4step::sim_machine_switches()) c.set_switches(*s);
}

}  // namespace x4ctl
