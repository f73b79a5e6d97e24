// SPDX-License-Identifier: LGPL-2.1-or-later
// libx4step: the simulated port's names and settings (options.hpp).
#include "options.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include "terminal.hpp"
#include "x4_keys.h"
#include "x4step.hpp"

namespace x4step::sim {
namespace {

[[noreturn]] void refuse(const std::string &what) { throw error(make_error_code(errc::lpt_not_found), what); }

// One character of the main keyboard (US layout) and its key's make code.
constexpr const char *rows[] = {"1234567890-=", "qwertyuiop[]", "asdfghjkl;'`", "\\zxcvbnm,./"};
constexpr unsigned row_start[] = {2, 16, 30, 43};

}  // namespace

unsigned key_code(const std::string &name) {
  // The named keys of the module's key map (engine/x4_keys.h).
  for (const x4_key &k : x4_keys)
    if (k.name && name == k.name) return k.code;
  if (name.size() != 1) return 0;
  const char c = static_cast<char>(std::tolower(static_cast<unsigned char>(name[0])));
  for (int r = 0; r < 4; r++)
    if (const char *at = std::strchr(rows[r], c); at && c)
      return row_start[r] + static_cast<unsigned>(at - rows[r]);
  return 0;
}

std::vector<scripted_key> parse_keys(const std::string &spec) {
  std::vector<scripted_key> keys;
  std::size_t at = 0;
  while (at <= spec.size()) {
    const std::size_t end = std::min(spec.find(',', at), spec.size());
    const std::string entry = spec.substr(at, end - at);
    at = end + 1;
    const auto bad = [&](const std::string &why) {
      refuse("X4STEP_SIM_KEYS: '" + entry + "': " + why +
             "; use TIME:KEY,... with TIME as 250ms or 1.5s (since the port was opened) and KEY a name "
             "(esc, enter, space, up, a, 1, ...: a press and its release) or a set-1 code 1..255");
    };
    const std::size_t colon = entry.find(':');
    if (colon == std::string::npos) bad("no ':'");
    const std::string t = entry.substr(0, colon), k = entry.substr(colon + 1);
    const bool ms = t.size() > 2 && t.compare(t.size() - 2, 2, "ms") == 0;
    const bool sec = !ms && t.size() > 1 && t.back() == 's';
    if (!ms && !sec) bad("its time has no unit");
    const std::string num = t.substr(0, t.size() - (ms ? 2 : 1));
    char *rest = nullptr;
    const double v = std::strtod(num.c_str(), &rest);
    if (num.empty() || *rest || !(v >= 0) || v > 1e6) bad("not a time");
    const auto t_ns = static_cast<std::uint64_t>(v * (ms ? 1e6 : 1e9) + 0.5);
    unsigned code = key_code(k);
    if (code) {
      keys.push_back({t_ns, code});
      keys.push_back({t_ns, code + 128});
      continue;
    }
    const unsigned long n = std::strtoul(k.c_str(), &rest, 10);
    if (k.empty() || *rest || n < 1 || n > 255) bad("no such key");
    keys.push_back({t_ns, static_cast<unsigned>(n)});
  }
  std::stable_sort(keys.begin(), keys.end(),
                   [](const scripted_key &a, const scripted_key &b) { return a.t_ns < b.t_ns; });
  return keys;
}

// "sim0", "simx", "sim:7" are misspelt simulated ports, refused as such
// rather than opened as files of the working directory ("./sim0" is one).
bool is_sim_name(const std::string &name) {
  return name.rfind("sim", 0) == 0 && name.find('/') == std::string::npos;
}

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
  // The terminal only when asked: reading it takes it out of canonical
  // mode while a move runs, which a program may not expect.
  if (const char *k = std::getenv("X4STEP_SIM_KEYS"); k && *k) {
    const std::string v(k);
    if (v == "tty") {
      if (!terminal::available())
        refuse(
            "X4STEP_SIM_KEYS=tty: standard input is not a terminal: run the program on one, or give "
            "the keys as TIME:KEY,... (e.g. 500ms:esc), or none");
      o.terminal_keys = true;
    } else if (v != "none")
      o.keys = parse_keys(v);
  }
  if (const char *m = std::getenv("X4STEP_SIM_MACHINE"); m && *m) {
    std::ifstream in(m);
    if (!in)
      refuse(std::string("X4STEP_SIM_MACHINE=") + m +
             ": cannot read the machine file: " + std::strerror(errno) + ": name a readable file");
    o.model.read(in, m);
  }
  if (const char *s = std::getenv("X4STEP_SIM_INPUTS"); s && *s) o.model.add_script(s);
  if (const char *s = std::getenv("X4STEP_SIM_STATE"); s && *s) o.state = s;
  return o;
}

bool env_wants_sim() {
  const char *s = std::getenv("X4STEP_SIM");
  if (!s || !*s || std::string(s) == "0") return false;
  if (std::string(s) == "1") return true;
  // X4STEP_SIM=2 is no port number: the program's LPTn still chooses.
  refuse(std::string("X4STEP_SIM=") + s +
         ": use 1 (LPT1..4 are the simulated ports sim:0..3) or 0 (the module's devices); the program's "
         "LPT number chooses the port");
}

}  // namespace x4step::sim
