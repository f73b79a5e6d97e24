// SPDX-License-Identifier: GPL-2.0
// x4ctl: the command line parser, one for every command: it reads the
// options and operands a command's record (command.hpp) names.
//
// The options follow getopt_long (--name VALUE, --name=VALUE, -n VALUE,
// -nVALUE, bundled flags, "--"), but the parser is our own: getopt takes
// "-1000" for options, and negative step counts are everyday operands here.
#include "cli.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <string_view>

#include "sim.hpp"
#include "subcommand.hpp"
#include "values.hpp"

#ifndef X4CTL_VERSION
#define X4CTL_VERSION "0.1.0"
#endif

namespace x4ctl {
namespace {

using std::chrono::milliseconds;

struct split_result {
  std::vector<option_value> options;
  std::vector<std::string> operands;
};

bool is_negative_number(const std::string &a) {
  return a.size() > 1 && a[0] == '-' && a[1] >= '0' && a[1] <= '9';
}

bool is_option(const std::string &a) { return a.size() > 1 && a[0] == '-' && !is_negative_number(a); }

// Splits args[from..] into options and operands. With stop_at_operand, the
// first operand and everything after it are operands (the global options
// end at the subcommand).
split_result split(const std::vector<std::string> &args, size_t from,
                   const std::vector<const option *> &specs, const std::string &ctx, bool stop_at_operand) {
  split_result r;
  const std::string prefix = ctx.empty() ? "" : ctx + ": ";
  auto find_long = [&](std::string_view name) -> const option * {
    for (const option *s : specs)
      if (name == s->name) return s;
    return nullptr;
  };
  auto find_short = [&](char c) -> const option * {
    for (const option *s : specs)
      if (c != 0 && c == s->short_name) return s;
    return nullptr;
  };
  for (size_t i = from; i < args.size(); i++) {
    const std::string &a = args[i];
    if (a == "--") {
      r.operands.insert(r.operands.end(), args.begin() + i + 1, args.end());
      break;
    }
    if (a.size() < 2 || a[0] != '-' || is_negative_number(a)) {
      if (stop_at_operand) {
        r.operands.insert(r.operands.end(), args.begin() + i, args.end());
        break;
      }
      r.operands.push_back(a);
      continue;
    }
    if (a[1] == '-') {
      const size_t eq = a.find('=');
      const std::string name = a.substr(2, eq == std::string::npos ? std::string::npos : eq - 2);
      const option *s = find_long(name);
      if (!s) throw usage_error(prefix + "unknown option '--" + name + "'");
      if (s->value.empty()) {
        if (eq != std::string::npos) throw usage_error(prefix + "option '--" + name + "' takes no value");
        r.options.push_back({s, "--" + name, "", {}});
        continue;
      }
      option_value v{s, "--" + name, "", {}};
      if (eq != std::string::npos)
        v.value = a.substr(eq + 1);
      else if (i + 1 < args.size())
        v.value = args[++i];
      else
        throw usage_error(prefix + "option '--" + name + "' needs a value");
      // --then 1 -2 3: the words up to the next option are its values too.
      while (s->list && i + 1 < args.size() && !is_option(args[i + 1])) v.more.push_back(args[++i]);
      r.options.push_back(std::move(v));
      continue;
    }
    for (size_t k = 1; k < a.size(); k++) {
      const option *s = find_short(a[k]);
      if (!s) throw usage_error(prefix + "unknown option '-" + std::string(1, a[k]) + "'");
      const std::string name = std::string("-") + a[k];
      if (s->value.empty()) {
        r.options.push_back({s, name, "", {}});
      } else if (k + 1 < a.size()) {
        r.options.push_back({s, name, a.substr(k + 1), {}});
        break;
      } else if (i + 1 < args.size()) {
        r.options.push_back({s, name, args[++i], {}});
      } else {
        throw usage_error(prefix + "option '" + name + "' needs a value");
      }
    }
  }
  return r;
}

// The options of cmd: its own, then the common ones it does not name.
std::vector<const option *> options_of(const subcommand &cmd) {
  std::vector<const option *> specs;
  for (const option &o : cmd.options) specs.push_back(&o);
  for (const option &o : common_options())
    if (std::none_of(cmd.options.begin(), cmd.options.end(),
                     [&](const option &m) { return m.name == o.name; }))
      specs.push_back(&o);
  return specs;
}

void parse_subcommand(config &c, const std::vector<std::string> &args, size_t from) {
  const subcommand &cmd = *c.cmd;
  parse_state s{c, cmd.name + ": ", default_freq_hz, std::nullopt, {}, {}};
  const split_result r = split(args, from, options_of(cmd), cmd.name, false);
  if (cmd.defaults) cmd.defaults(c);
  for (const option_value &o : r.options) {
    s.given.push_back(o.opt->name);
    o.opt->apply(s, o);
  }
  if (c.help) return;  // --help wins over missing or bad operands
  c.move.freq_hz = s.freq;
  c.move.ramp = milliseconds(s.ramp.value_or(default_ramp_ms(s.freq)));
  if (cmd.operands)
    cmd.operands(s, r.operands);
  else
    need_operands(r.operands, 0, 0, s.prefix);
}

}  // namespace

bool parse_state::gave(std::initializer_list<const char *> names) const {
  for (const char *n : names)
    if (std::find(given.begin(), given.end(), n) != given.end()) return true;
  return false;
}

void need_operands(const std::vector<std::string> &ops, size_t min, size_t max, const std::string &prefix) {
  if (ops.size() < min) throw usage_error(prefix + "missing arguments");
  if (ops.size() > max) throw usage_error(prefix + "unexpected argument '" + ops[max] + "'");
}

const std::vector<option> &common_options() {
  static const std::vector<option> common = {
      {"port", 'p', "LPT", "parallel port 1..4 (/dev/x4step0..3), default 1",
       [](parse_state &s, const option_value &o) {
         s.c.lpt = parse_lpt(o.value, s.prefix);
         s.c.device.clear();
       }},
      {"device", 'd', "PATH", "device node to use instead of --port",
       [](parse_state &s, const option_value &o) {
         if (o.value.empty()) throw usage_error(s.prefix + "--device needs a path");
         s.c.device = o.value;
       }},
      {"sim", 0, "",
       "a simulated port in this process (sim:0..3 for LPT\n"
       "1..4): no module, no root; X4STEP_SIM=1 does the same;\n"
       "a fresh one in each x4ctl, but for the positions\n"
       "X4STEP_SIM_STATE=FILE keeps (docs/simulator.md)",
       [](parse_state &s, const option_value &) { s.c.sim = true; }},
      {"help", 'h', "", "show this help", [](parse_state &s, const option_value &) { s.c.help = true; }},
  };
  return common;
}

const option &common_option(const std::string &name) {
  for (const option &o : common_options())
    if (o.name == name) return o;
  throw std::logic_error("no common option --" + name);
}

long parse_number(const std::string &text, const std::string &what) {
  const char *s = text.c_str();
  // strtol alone would take " 12", "0x1f" and "12abc".
  const bool digits = !text.empty() && text.find_first_not_of("+-0123456789") == std::string::npos;
  errno = 0;
  char *end = nullptr;
  const long v = std::strtol(s, &end, 10);
  if (!digits || end == s || *end != '\0') throw usage_error(what + " '" + text + "' is not a whole number");
  if (errno == ERANGE) throw usage_error(what + " " + text + " out of range");
  return v;
}

std::string message(x4step::errc e) { return x4step::make_error_code(e).message(); }

int default_ramp_ms(int freq_hz) { return std::min(50, freq_hz); }

// The simulated port of --sim (or X4STEP_SIM=1) is named sim:0..3; so
// is -d sim:N. X4STEP_SIM as the library takes it (x4step::env_wants_sim),
// a bad value said in x4ctl's words.
bool sim_wanted(const config &c) {
  if (c.sim || is_sim_device(c.device)) return true;
  try {
    return x4step::env_wants_sim();
  } catch (const x4step::error &) {
    throw usage_error(std::string("X4STEP_SIM=") + std::getenv("X4STEP_SIM") +
                      ": use 1 (the simulated ports sim:0..3 for LPT1..4) or 0; -p chooses the port");
  }
}

std::string device_of(const config &c) {
  if (!c.device.empty()) return c.device;
  return sim_wanted(c) ? "sim:" + std::to_string(c.lpt - 1) : x4step::device_path(c.lpt);
}

namespace {

// --sim with -d naming a device: the simulator never touches one.
void check_sim(const config &c) {
  if (c.sim && !c.device.empty() && !is_sim_device(c.device))
    throw usage_error("--sim and -d " + c.device +
                      ": a simulated port never opens a device; use -d sim:N (N 0..3), or -p, with --sim");
  sim_wanted(c);  // a bad X4STEP_SIM
}

}  // namespace

const subcommand *find_command(const std::string &name) {
  for (const command_group &g : command_groups())
    for (const subcommand *c : g.commands)
      if (name == c->name) return c;
  return nullptr;
}

std::string name_of(const subcommand &c) { return c.name.empty() ? "x4ctl" : c.name; }

std::string version_text() { return "x4ctl " X4CTL_VERSION "\n"; }

config parse_args(const std::vector<std::string> &args) {
  config c;
  parse_state s{c, "", default_freq_hz, std::nullopt, {}, {}};
  const split_result r = split(args, 1, options_of(main_command()), "", true);
  for (const option_value &o : r.options) o.opt->apply(s, o);
  const std::string name = r.operands.empty() ? "" : r.operands[0];
  if (c.help || c.version) {
    // "x4ctl --help move" shows the help of move.
    if (const subcommand *cmd = find_command(name); cmd && c.help) c.cmd = cmd;
    return c;
  }
  check_sim(c);
  if (r.operands.empty()) return c;  // interactive
  if (name.find_first_not_of("0123456789") == std::string::npos) {
    // TEST.EXE's "TEST 2": the test program on LPT2.
    if (r.operands.size() > 1) throw usage_error("unexpected argument '" + r.operands[1] + "'");
    c.lpt = parse_lpt(name, "");
    c.device.clear();
    return c;
  }
  const subcommand *cmd = find_command(name);
  if (!cmd) throw usage_error("unknown command '" + name + "'");
  c.cmd = cmd;
  const size_t at = args.size() - r.operands.size() + 1;  // after the command's name
  parse_subcommand(c, args, at);
  check_sim(c);
  // A simulated port lives in this process: no background holder.
  if (sim_wanted(c)) {
    c.wait = true;
    c.no_wait = false;
  }
  return c;
}

}  // namespace x4ctl
