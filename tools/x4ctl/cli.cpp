// SPDX-License-Identifier: GPL-2.0
// x4ctl: command line parsing and help texts.
//
// The options follow getopt_long (--name VALUE, --name=VALUE, -n VALUE,
// -nVALUE, bundled flags, "--"), but the parser is our own: getopt takes
// "-1000" for options, and negative step counts are everyday operands here.
#include "cli.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <string_view>

#include "lang.hpp"
#include "show.hpp"
#include "sim.hpp"

#ifndef X4CTL_VERSION
#define X4CTL_VERSION "0.1.0"
#endif

namespace x4ctl {
namespace {

using std::chrono::milliseconds;

enum opt_id {
  opt_port,
  opt_device,
  opt_sim,
  opt_help,
  opt_version,
  opt_freq,
  opt_ramp,
  opt_wait,
  opt_background,
  opt_then,
  opt_time,
  opt_json,
  opt_watch,
  opt_read_only,
  opt_count,
  opt_moves,
  opt_check,
  opt_echo,
  opt_pulse,
  opt_space,
  opt_setup,
  opt_hold,
  opt_v0,
  opt_ve,
  opt_vm,
  opt_a0,
  opt_ae,
  opt_relative,
  opt_no_wait,
  opt_vref1,
  opt_vref2,
  opt_sref,
  opt_phase,
  opt_brake,
  opt_at,
  opt_ref,
  opt_plus,
  opt_minus,
  opt_nc,
  opt_stop,
  opt_speed,
  opt_accel,
  opt_deviation,
  opt_override,
  opt_machine,
  opt_no_pause,
  opt_svg,
  opt_feed,
  opt_distance
};

struct option_spec {
  const char *name;
  char short_name;  // 0: none
  bool takes_value;
  opt_id id;
  bool list = false;  // the words after the value, up to the next option, are values too (--then)
};

const option_spec common_options[] = {
    {"port", 'p', true, opt_port},
    {"device", 'd', true, opt_device},
    {"sim", 0, false, opt_sim},
    {"help", 'h', false, opt_help},
};

struct option_value {
  opt_id id;
  std::string name;  // as written, for messages
  std::string value;
  std::vector<std::string> more;  // the further values
};

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
split_result split(const std::vector<std::string> &args, size_t from, const std::vector<option_spec> &specs,
                   const std::string &ctx, bool stop_at_operand) {
  split_result r;
  const std::string prefix = ctx.empty() ? "" : ctx + ": ";
  auto find_long = [&](std::string_view name) -> const option_spec * {
    for (const auto &s : specs)
      if (name == s.name) return &s;
    return nullptr;
  };
  auto find_short = [&](char c) -> const option_spec * {
    for (const auto &s : specs)
      if (c != 0 && c == s.short_name) return &s;
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
      const option_spec *s = find_long(name);
      if (!s) throw usage_error(prefix + "unknown option '--" + name + "'");
      if (!s->takes_value) {
        if (eq != std::string::npos) throw usage_error(prefix + "option '--" + name + "' takes no value");
        r.options.push_back({s->id, "--" + name, "", {}});
        continue;
      }
      option_value v{s->id, "--" + name, "", {}};
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
      const option_spec *s = find_short(a[k]);
      if (!s) throw usage_error(prefix + "unknown option '-" + std::string(1, a[k]) + "'");
      const std::string name = std::string("-") + a[k];
      if (!s->takes_value) {
        r.options.push_back({s->id, name, "", {}});
      } else if (k + 1 < a.size()) {
        r.options.push_back({s->id, name, a.substr(k + 1), {}});
        break;
      } else if (i + 1 < args.size()) {
        r.options.push_back({s->id, name, args[++i], {}});
      } else {
        throw usage_error(prefix + "option '" + name + "' needs a value");
      }
    }
  }
  return r;
}

struct command_entry {
  subcommand cmd;
  const char *name;
};

const command_entry commands[] = {
    {subcommand::move, "move"},       {subcommand::jog, "jog"},         {subcommand::brake, "brake"},
    {subcommand::stop, "stop"},       {subcommand::status, "status"},   {subcommand::in, "in"},
    {subcommand::out, "out"},         {subcommand::keys, "keys"},       {subcommand::sweep, "sweep"},
    {subcommand::monitor, "monitor"}, {subcommand::run, "run"},         {subcommand::timing, "timing"},
    {subcommand::mode, "mode"},       {subcommand::profile, "profile"}, {subcommand::go_to, "goto"},
    {subcommand::home, "home"},       {subcommand::zero, "zero"},       {subcommand::limits, "limits"},
    {subcommand::halt, "halt"},       {subcommand::watch, "watch"},     {subcommand::list, "list"},
    {subcommand::path, "path"},       {subcommand::gcode, "gcode"},     {subcommand::mdi, "mdi"},
    {subcommand::panel, "panel"},     {subcommand::help, "help"},
};

int parse_lpt(const std::string &text, const std::string &prefix) {
  const long v = parse_number(text, prefix + "port");
  if (v < 1 || v > 4) throw usage_error(prefix + "port " + text + " out of range: use 1 to 4 (LPT1..LPT4)");
  return static_cast<int>(v);
}

int parse_freq(const std::string &text, const std::string &prefix) {
  const long v = parse_number(text, prefix + "frequency");
  if (v > x4step::freq_max_hz) throw usage_error(prefix + message(x4step::errc::freq_too_high));
  if (v < x4step::freq_min_hz) throw usage_error(prefix + message(x4step::errc::freq_too_low));
  return static_cast<int>(v);
}

int parse_ramp(const std::string &text, const std::string &prefix) {
  const long v = parse_number(text, prefix + "ramp");
  if (v > x4step::ramp_max.count()) throw usage_error(prefix + message(x4step::errc::ramp_too_high));
  if (v < 0) throw usage_error(prefix + "ramp " + text + " out of range: use 0 to 1000 ms");
  return static_cast<int>(v);
}

long parse_steps(const std::string &text, const std::string &prefix) {
  const long v = parse_number(text, prefix + "steps");
  if (v > x4step::steps_max || v < -x4step::steps_max)
    throw usage_error(prefix + message(x4step::errc::steps_too_high));
  return v;
}

x4step::axis parse_axis(const std::string &text, const std::string &prefix) {
  const long v = parse_number(text, prefix + "axis");
  if (v < 1 || v > x4step::axes) throw usage_error(prefix + "axis " + text + " out of range: use 1 to 4");
  return x4step::axis(static_cast<int>(v));
}

milliseconds parse_time(const std::string &text, const std::string &prefix) {
  const long v = parse_number(text, prefix + "time");
  if (v < 0) throw usage_error(prefix + "time " + text + " out of range: use 0 ms or more");
  return milliseconds(v);
}

// A step time of `timing`: 0..1 ms; a pulse 0 (symmetric clock) or at least 1 us.
std::chrono::nanoseconds parse_ns(const std::string &text, const std::string &what, bool pulse,
                                  const std::string &prefix) {
  const long v = parse_number(text, prefix + what);
  if (pulse && (v < 0 || v > timing_max_ns || (v != 0 && v < pulse_min_ns)))
    throw usage_error(prefix + what + " " + text + " out of range: use 0 (symmetric clock) or " +
                      std::to_string(pulse_min_ns) + " to " + std::to_string(timing_max_ns) + " ns");
  if (v < 0 || v > timing_max_ns)
    throw usage_error(prefix + what + " " + text + " out of range: use 0 to " +
                      std::to_string(timing_max_ns) + " ns");
  return std::chrono::nanoseconds(v);
}

x4step::output_mode parse_mode(const std::string &text, const std::string &prefix) {
  std::string names;
  for (const auto m : output_modes) {
    if (text == mode_name(m)) return m;
    names += std::string(names.empty() ? "" : ", ") + mode_name(m);
  }
  throw usage_error(prefix + "no mode '" + text + "': use " + names);
}

// A number above 0 (not necessarily whole), else "WHAT 'TEXT': use a number above 0 UNIT".
double parse_positive(const std::string &text, const std::string &what, const std::string &unit,
                      const std::string &prefix) {
  char *end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end || !std::isfinite(v) || v <= 0)
    throw usage_error(prefix + what + " '" + text + "': use a number above 0" + unit);
  return v;
}

bool is_axis_letter(char ch) { return ch && std::strchr("XYZABCxyzabc", ch); }

char upper(char ch) { return static_cast<char>(std::toupper(static_cast<unsigned char>(ch))); }

// A number in min..max, else "WHAT TEXT out of range: use MIN to MAX UNIT".
long parse_range(const std::string &text, const std::string &what, long min, long max,
                 const std::string &unit, const std::string &prefix) {
  const long v = parse_number(text, prefix + what);
  if (v < min || v > max)
    throw usage_error(prefix + what + " " + text + " out of range: use " + std::to_string(min) + " to " +
                      std::to_string(max) + unit);
  return v;
}

// A coordinate or distance of the axes' own moves: signed 32 bits.
long parse_position(const std::string &text, const std::string &what, const std::string &prefix) {
  return parse_range(text, what, INT32_MIN, INT32_MAX, "", prefix);
}

unsigned parse_speed(const std::string &text, const std::string &what, long min, const std::string &prefix) {
  return static_cast<unsigned>(parse_range(text, what, min, x4step::vel_max, " steps/s", prefix));
}

unsigned parse_acceleration(const std::string &text, const std::string &what, const std::string &prefix) {
  return static_cast<unsigned>(parse_range(text, what, 0, x4step::acc_max, " steps/s^2", prefix));
}

// A signed reference speed: the sign is the direction.
int parse_vref(const std::string &text, const std::string &what, const std::string &prefix) {
  const long v = parse_number(text, prefix + what);
  const long max = x4step::vel_max;
  if (v == 0 || v < -max || v > max)
    throw usage_error(prefix + what + " " + text + " out of range: use -" + std::to_string(max) +
                      " to -1 or 1 to " + std::to_string(max) + " steps/s (the sign is the direction)");
  return static_cast<int>(v);
}

// An input 1..5, or 0 or "none".
int parse_input(const std::string &text, const std::string &prefix) {
  if (text == "none") return 0;
  const long v = parse_number(text, prefix + "input");
  if (v < 0 || v > 5)
    throw usage_error(prefix + "input " + text +
                      " out of range: use 1 to 5 (pins 15, 13, 12, 10, 11), or 0 for none");
  return static_cast<int>(v);
}

// Normally closed inputs: "none", a list "1,3", or a mask "0x05".
unsigned parse_nc(const std::string &text, const std::string &prefix) {
  if (text == "none") return 0;
  if (text.rfind("0x", 0) == 0) {
    char *end = nullptr;
    const unsigned long v = std::strtoul(text.c_str() + 2, &end, 16);
    if (text.size() == 2 || *end || v > 0x1f)
      throw usage_error(prefix + "nc mask " + text + " out of range: use 0x00 to 0x1f (bit k: input k+1)");
    return static_cast<unsigned>(v);
  }
  unsigned mask = 0;
  size_t from = 0;
  for (;;) {
    const size_t comma = text.find(',', from);
    const std::string one = text.substr(from, comma == std::string::npos ? comma : comma - from);
    const int in = parse_input(one, prefix + "--nc ");
    if (in == 0) throw usage_error(prefix + "--nc input " + one + ": use 1 to 5, e.g. --nc 1,3");
    mask |= 1u << (in - 1);
    if (comma == std::string::npos) return mask;
    from = comma + 1;
  }
}

// AXIS... as a mask: each 1..4, once.
x4step::axis_set parse_axes(const std::vector<std::string> &ops, const std::string &prefix) {
  x4step::axis_set axes;
  for (const auto &o : ops) {
    const x4step::axis a = parse_axis(o, prefix);
    if (axes.contains(a)) throw usage_error(prefix + "axis " + o + " given twice");
    axes |= a;
  }
  return axes;
}

void need_operands(const split_result &r, size_t min, size_t max, const std::string &prefix) {
  if (r.operands.size() < min) throw usage_error(prefix + "missing arguments");
  if (r.operands.size() > max) throw usage_error(prefix + "unexpected argument '" + r.operands[max] + "'");
}

// The options every subcommand has, and -p/-d/-h before the subcommand.
bool apply_common(config &c, const option_value &o, const std::string &prefix) {
  switch (o.id) {
    case opt_port:
      c.lpt = parse_lpt(o.value, prefix);
      c.device.clear();
      return true;
    case opt_device:
      if (o.value.empty()) throw usage_error(prefix + "--device needs a path");
      c.device = o.value;
      return true;
    case opt_sim:
      c.sim = true;
      return true;
    case opt_help:
      c.help = true;
      return true;
    default:
      return false;
  }
}

// move, jog, sweep: the shared --freq/--ramp/--wait/--time; ramp defaults last.
struct motion_options {
  int freq = default_freq_hz;
  std::optional<int> ramp;
};

void parse_subcommand(config &c, const std::vector<std::string> &args, size_t from) {
  const std::string prefix = std::string(name_of(c.cmd)) + ": ";
  std::vector<option_spec> specs(std::begin(common_options), std::end(common_options));
  auto add = [&](const char *name, char s, bool value, opt_id id, bool list = false) {
    specs.push_back({name, s, value, id, list});
  };
  switch (c.cmd) {
    case subcommand::move:
      add("freq", 'f', true, opt_freq);
      add("ramp", 'r', true, opt_ramp);
      add("wait", 'w', false, opt_wait);
      add("background", 'b', false, opt_background);
      add("then", 0, true, opt_then, true);
      break;
    case subcommand::jog:
      add("freq", 'f', true, opt_freq);
      add("ramp", 'r', true, opt_ramp);
      add("time", 't', true, opt_time);
      add("wait", 'w', false, opt_wait);
      add("machine", 'm', true, opt_machine);
      add("feed", 0, true, opt_feed);
      add("distance", 0, true, opt_distance);
      break;
    case subcommand::panel:
      add("machine", 'm', true, opt_machine);
      add("feed", 0, true, opt_feed);
      break;
    case subcommand::sweep:
      add("ramp", 'r', true, opt_ramp);
      break;
    case subcommand::status:
      add("json", 'j', false, opt_json);
      break;
    case subcommand::in:
      add("json", 'j', false, opt_json);
      add("watch", 'w', false, opt_watch);
      add("read-only", 'r', false, opt_read_only);
      break;
    case subcommand::out:
      add("time", 't', true, opt_time);
      break;
    case subcommand::monitor:
      add("json", 'j', false, opt_json);
      add("moves", 'n', true, opt_moves);
      break;
    case subcommand::watch:
      add("json", 'j', false, opt_json);
      add("count", 'n', true, opt_count);
      break;
    case subcommand::run:
      add("check", 'c', false, opt_check);
      add("echo", 'e', false, opt_echo);
      break;
    case subcommand::timing:
      add("pulse", 0, true, opt_pulse);
      add("space", 0, true, opt_space);
      add("setup", 0, true, opt_setup);
      add("hold", 0, true, opt_hold);
      add("json", 'j', false, opt_json);
      break;
    case subcommand::profile:
      add("json", 'j', false, opt_json);
      add("v0", 0, true, opt_v0);
      add("ve", 0, true, opt_ve);
      add("vm", 0, true, opt_vm);
      add("a0", 0, true, opt_a0);
      add("ae", 0, true, opt_ae);
      break;
    case subcommand::go_to:
      add("relative", 0, false, opt_relative);
      add("no-wait", 0, false, opt_no_wait);
      break;
    case subcommand::home:
      add("vref1", 0, true, opt_vref1);
      add("vref2", 0, true, opt_vref2);
      add("sref", 0, true, opt_sref);
      add("phase", 0, true, opt_phase);
      add("brake", 0, false, opt_brake);
      add("machine", 'm', true, opt_machine);
      break;
    case subcommand::zero:
      add("at", 0, true, opt_at);
      break;
    case subcommand::limits:
      add("json", 'j', false, opt_json);
      add("ref", 0, true, opt_ref);
      add("plus", 0, true, opt_plus);
      add("minus", 0, true, opt_minus);
      add("nc", 0, true, opt_nc);
      break;
    case subcommand::halt:
      add("stop", 's', false, opt_stop);
      break;
    case subcommand::mode:
    case subcommand::list:
      add("json", 'j', false, opt_json);
      break;
    case subcommand::path:
      add("speed", 's', true, opt_speed);
      add("accel", 'a', true, opt_accel);
      add("deviation", 0, true, opt_deviation);
      add("override", 'o', true, opt_override);
      add("check", 'c', false, opt_check);
      add("json", 'j', false, opt_json);
      break;
    case subcommand::gcode:
    case subcommand::mdi:
      if (c.cmd == subcommand::gcode) add("svg", 0, true, opt_svg);
      add("machine", 'm', true, opt_machine);
      add("override", 'o', true, opt_override);
      add("check", 'c', false, opt_check);
      add("no-pause", 0, false, opt_no_pause);
      add("json", 'j', false, opt_json);
      break;
    default:
      break;
  }
  const split_result r = split(args, from, specs, name_of(c.cmd), false);
  motion_options mo;
  bool step_options = false;                         // jog, home: an option of the steps form
  std::vector<std::vector<std::string>> then_paths;  // checked once freq and ramp are known
  // A move stays in the foreground until it ends, as gpioset does: 'x4ctl
  // move 100; x4ctl move -100' runs one after the other.
  if (c.cmd == subcommand::move) c.wait = true;
  for (const auto &o : r.options) {
    if (apply_common(c, o, prefix)) continue;
    if (o.id != opt_machine && o.id != opt_feed && o.id != opt_distance) step_options = true;
    switch (o.id) {
      case opt_freq:
        mo.freq = parse_freq(o.value, prefix);
        break;
      case opt_ramp:
        mo.ramp = parse_ramp(o.value, prefix);
        break;
      case opt_wait:
        c.wait = true;
        break;
      case opt_background:
        c.wait = false;
        break;
      case opt_then:
        then_paths.push_back({o.value});
        then_paths.back().insert(then_paths.back().end(), o.more.begin(), o.more.end());
        break;
      case opt_time:
        c.time = parse_time(o.value, prefix);
        break;
      case opt_json:
        c.json = true;
        break;
      case opt_watch:
        c.watch = true;
        break;
      case opt_read_only:
        c.read_only = true;
        break;
      case opt_check:
        c.check = true;
        break;
      case opt_echo:
        c.echo = true;
        break;
      case opt_count: {
        const long n = parse_number(o.value, prefix + "count");
        if (n < 1) throw usage_error(prefix + "count " + o.value + " out of range: use 1 or more");
        c.count = n;
        break;
      }
      case opt_moves: {
        const long n = parse_number(o.value, prefix + "moves");
        if (n < 1) throw usage_error(prefix + "moves " + o.value + " out of range: use 1 or more");
        c.moves = n;
        break;
      }
      case opt_pulse:
        c.pulse = parse_ns(o.value, "pulse", true, prefix);
        break;
      case opt_space:
        c.space = parse_ns(o.value, "space", false, prefix);
        break;
      case opt_setup:
        c.dir_setup = parse_ns(o.value, "setup", false, prefix);
        break;
      case opt_hold:
        c.dir_hold = parse_ns(o.value, "hold", false, prefix);
        break;
      case opt_v0:
        c.v0 = parse_speed(o.value, "v0", 0, prefix);
        break;
      case opt_ve:
        c.ve = parse_speed(o.value, "ve", 0, prefix);
        break;
      case opt_vm:
        c.vm = parse_speed(o.value, "vm", 1, prefix);
        break;
      case opt_a0:
        c.a0 = parse_acceleration(o.value, "a0", prefix);
        break;
      case opt_ae:
        c.ae = parse_acceleration(o.value, "ae", prefix);
        break;
      case opt_relative:
        c.relative = true;
        break;
      case opt_no_wait:
        c.no_wait = true;
        break;
      case opt_vref1:
        c.homing.phase1_speed(parse_vref(o.value, "vref1", prefix));
        break;
      case opt_vref2:
        c.homing.phase2_speed(parse_vref(o.value, "vref2", prefix));
        break;
      case opt_sref:
        c.homing.max_travel(
            static_cast<unsigned long>(parse_range(o.value, "sref", 1, INT32_MAX, " steps", prefix)));
        break;
      case opt_phase: {
        const long ph = parse_number(o.value, prefix + "phase");
        if (ph != 1 && ph != 2)
          throw usage_error(prefix + "phase " + o.value + ": use 1 or 2 (both: no --phase)");
        c.homing.phase1(ph == 1).phase2(ph == 2);
        break;
      }
      case opt_brake:
        c.homing.brake(true);
        break;
      case opt_at:
        c.at = parse_position(o.value, "position", prefix);
        break;
      case opt_speed:
        c.path.speed = parse_speed(o.value, "speed", 1, prefix);
        break;
      case opt_accel:
        c.path.accel =
            static_cast<unsigned>(parse_range(o.value, "accel", 1, x4step::acc_max, " steps/s^2", prefix));
        break;
      case opt_deviation: {
        char *end = nullptr;
        const double v = std::strtod(o.value.c_str(), &end);
        if (o.value.empty() || *end || !(v > 0 && v <= 1000))
          throw usage_error(prefix + "deviation '" + o.value + "': use a number of steps, 0 < D <= 1000");
        c.path.deviation = v;
        break;
      }
      case opt_override:
        c.override_percent = static_cast<unsigned>(parse_range(o.value, "override", 1, 200, " %", prefix));
        break;
      case opt_machine:
        if (o.value.empty()) throw usage_error(prefix + "--machine needs a file");
        c.machine = o.value;
        break;
      case opt_no_pause:
        c.no_pause = true;
        break;
      case opt_svg:
        if (o.value.empty()) throw usage_error(prefix + "--svg needs a file");
        c.svg = o.value;
        break;
      case opt_feed:
        c.feed = parse_positive(o.value, "feed", " units/min", prefix);
        break;
      case opt_distance:
        c.distance = parse_positive(o.value, "distance", " units", prefix);
        break;
      case opt_ref:
        c.ref = parse_input(o.value, prefix);
        break;
      case opt_plus:
        c.plus = parse_input(o.value, prefix);
        break;
      case opt_minus:
        c.minus = parse_input(o.value, prefix);
        break;
      case opt_nc:
        c.nc = parse_nc(o.value, prefix);
        break;
      case opt_stop:
        c.halt_stop = true;
        break;
      default:
        break;
    }
  }
  if (c.help) return;  // --help wins over missing or bad operands

  const auto &ops = r.operands;
  c.move.freq_hz = mo.freq;
  c.move.ramp = milliseconds(mo.ramp.value_or(default_ramp_ms(mo.freq)));
  switch (c.cmd) {
    case subcommand::move: {
      need_operands(r, 1, x4step::axes, prefix);
      for (size_t i = 0; i < ops.size(); i++) c.move.steps[i] = parse_steps(ops[i], prefix);
      if (const auto e = x4step::check(c.move); e != x4step::errc::ok) throw usage_error(prefix + message(e));
      for (const auto &path : then_paths) {
        const std::string then = prefix + "--then ";
        if (path.size() > x4step::axes)
          throw usage_error(prefix + "--then: unexpected argument '" + path[x4step::axes] + "'");
        x4step::move m = c.move;  // the same frequency and ramp
        m.steps = {};
        for (size_t i = 0; i < path.size(); i++) m.steps[i] = parse_steps(path[i], then);
        if (const auto e = x4step::check(m); e != x4step::errc::ok) throw usage_error(then + message(e));
        c.then.push_back(m);
      }
      break;
    }
    case subcommand::jog: {
      need_operands(r, 1, 2, prefix);
      if (ops.size() == 1) {  // X+: machine units
        const std::string &o = ops[0];
        if (o.size() != 2 || !is_axis_letter(o[0]) || (o[1] != '+' && o[1] != '-'))
          throw usage_error(prefix + "'" + o +
                            "': give an axis letter and a sign (X+, Z-), or AXIS +|- in steps");
        if (step_options)
          throw usage_error(prefix + "--freq, --ramp, --time and --wait are for AXIS +|- in steps; " + o +
                            " takes --machine, --feed and --distance");
        c.letters = std::string(1, upper(o[0]));
        c.dir = o[1] == '+' ? x4step::direction::positive : x4step::direction::negative;
        break;
      }
      if (c.machine_units() || c.feed || c.distance)
        throw usage_error(
            prefix + "--machine, --feed and --distance jog an axis letter, e.g. 'jog X+ --machine FILE'");
      c.axis = parse_axis(ops[0], prefix);
      if (ops[1] == "+" || ops[1] == "pos")
        c.dir = x4step::direction::positive;
      else if (ops[1] == "-" || ops[1] == "neg")
        c.dir = x4step::direction::negative;
      else
        throw usage_error(prefix + "direction '" + ops[1] + "': use + or -");
      if (const auto e = x4step::check_endless(c.move.freq_hz, c.move.ramp); e != x4step::errc::ok)
        throw usage_error(prefix + message(e));
      break;
    }
    case subcommand::sweep: {
      need_operands(r, 5, 5, prefix);
      c.axis = parse_axis(ops[0], prefix);
      c.move.steps[c.axis.index()] = parse_steps(ops[1], prefix);
      c.sweep_from = parse_freq(ops[2], prefix);
      c.sweep_to = parse_freq(ops[3], prefix);
      const long step = parse_number(ops[4], prefix + "frequency step");
      if (step < 1 || step > x4step::freq_max_hz)
        throw usage_error(prefix + "frequency step " + ops[4] + " out of range: use 1 to 20000 Hz");
      c.sweep_step = static_cast<int>(step);
      // Resonance tests want constant speed: no ramp unless asked for.
      c.move.ramp = milliseconds(mo.ramp.value_or(0));
      c.move.freq_hz = std::min(c.sweep_from, c.sweep_to);  // the strictest for the ramp check
      if (const auto e = x4step::check(c.move); e != x4step::errc::ok) throw usage_error(prefix + message(e));
      break;
    }
    case subcommand::out: {
      need_operands(r, 2, 2, prefix);
      const long s = parse_number(ops[0], prefix + "signal");
      if (s != 1 && s != 2) throw usage_error(prefix + "signal " + ops[0] + ": use 1 (pin 1) or 2 (pin 14)");
      c.signal = s == 1 ? x4step::signal::one : x4step::signal::two;
      const std::string &v = ops[1];
      if (v == "on" || v == "1" || v == "high")
        c.level = true;
      else if (v == "off" || v == "0" || v == "low")
        c.level = false;
      else
        throw usage_error(prefix + "level '" + v + "': use on or off");
      break;
    }
    case subcommand::keys: {
      need_operands(r, 0, 20, prefix);
      for (const auto &o : ops) {
        const long k = parse_number(o, prefix + "key code");
        if (k < 1 || k > 255 || k == 128)
          throw usage_error(prefix + "key code " + o +
                            " out of range: use 1..127 (press) or 129..255 (release)");
        c.codes.push_back(static_cast<int>(k));
      }
      break;
    }
    case subcommand::run:
    case subcommand::path:
      need_operands(r, 0, 1, prefix);
      if (!ops.empty()) c.file = ops[0];
      break;
    case subcommand::gcode:  // read twice (checked, then run): a file, not standard input
      need_operands(r, 1, 1, prefix);
      c.file = ops[0];
      break;
    case subcommand::mdi:
      need_operands(r, 1, ops.size(), prefix);
      for (const std::string &b : ops)
        if (b.find_first_of("\n\r") != std::string::npos)
          throw usage_error(prefix + "a block holds no line break: give each line as its own argument");
      c.blocks = ops;
      break;
    case subcommand::mode:
      need_operands(r, 0, 1, prefix);
      if (!ops.empty()) c.mode = parse_mode(ops[0], prefix);
      break;
    case subcommand::home:
      // AXIS (1..4) without --machine: steps; axis letters or --machine: machine units. Nothing
      // given with $X4STEP_MACHINE set: all its axes (as panel and gcode take it without -m).
      if (c.machine.empty() && ops.empty())
        if (const char *env = std::getenv("X4STEP_MACHINE"); env && *env) c.machine = env;
      if (!c.machine.empty() || (!ops.empty() && std::isalpha(static_cast<unsigned char>(ops[0][0])))) {
        for (const std::string &o : ops)
          for (char ch : o) {
            if (!is_axis_letter(ch))
              throw usage_error(prefix + "'" + o + "': give axis letters (X Y Z A B C), or one AXIS 1..4");
            c.letters += upper(ch);
          }
        if (step_options)
          throw usage_error(prefix +
                            "--vref1, --vref2, --sref, --phase and --brake are for AXIS in steps; the "
                            "machine file gives the homing of axis letters");
        break;
      }
      [[fallthrough]];
    case subcommand::profile:
      need_operands(r, 1, 1, prefix);
      c.axis = parse_axis(ops[0], prefix);
      break;
    case subcommand::panel:
      need_operands(r, 0, 0, prefix);
      break;
    case subcommand::go_to: {
      need_operands(r, 1, x4step::axes, prefix);
      const std::string what = c.relative ? "distance" : "position";
      std::vector<std::string> names;  // AXIS of each AXIS=VALUE
      for (const auto &o : ops) {
        const size_t eq = o.find('=');
        if (eq == std::string::npos)
          throw usage_error(prefix + "'" + o + "': use AXIS=" + (c.relative ? "DISTANCE" : "POSITION") +
                            ", e.g. 1=1000");
        names.push_back(o.substr(0, eq));
      }
      c.axes = parse_axes(names, prefix);
      for (size_t i = 0; i < ops.size(); i++)
        c.targets[parse_axis(names[i], prefix).index()] =
            parse_position(ops[i].substr(names[i].size() + 1), what, prefix);
      break;
    }
    case subcommand::zero:
    case subcommand::halt:
      need_operands(r, 1, x4step::axes, prefix);
      c.axes = parse_axes(ops, prefix);
      break;
    case subcommand::limits:
      need_operands(r, 0, 1, prefix);
      if (!ops.empty()) {
        c.axis = parse_axis(ops[0], prefix);
        c.axes = c.axis;
      }
      if (ops.empty() && (c.ref || c.plus || c.minus))
        throw usage_error(prefix + "--ref, --plus and --minus need an AXIS, e.g. 'x4ctl limits 1 --ref 3'");
      break;
    case subcommand::help:
      need_operands(r, 0, 1, prefix);
      if (!ops.empty()) {
        const auto t = find_command(ops[0]);
        if (!t) throw usage_error(prefix + "no command '" + ops[0] + "'");
        c.topic = *t;
      }
      break;
    default:  // brake, stop, status, in, monitor, timing, watch, list
      need_operands(r, 0, 0, prefix);
      break;
  }
}

const char *const port_help =
    "  -p, --port=LPT       parallel port 1..4 (/dev/x4step0..3), default 1\n"
    "  -d, --device=PATH    device node to use instead of --port\n"
    "      --sim            a simulated port in this process (sim:0..3 for LPT\n"
    "                       1..4): no module, no root; X4STEP_SIM=1 does the same;\n"
    "                       a fresh one in each x4ctl (README: without a port)\n"
    "  -h, --help           show this help\n";

const char *const motion_help =
    "  -f, --freq=HZ        frequency of the leader axis, 10..20000 Hz (default 1000)\n"
    "  -r, --ramp=MS        ramp time, 0..1000 ms and at most the frequency in Hz\n"
    "                       (default 50, or the frequency if that is lower)\n";

const char *const background_help =
    "Without --wait, x4ctl returns once the motors run, and a background x4ctl\n"
    "holds the port until the move ends (the module brakes a move whose program\n"
    "exits). 'x4ctl brake', 'x4ctl stop' or ESC on the console keyboard end it\n"
    "early; 'x4ctl monitor' follows it.\n";

}  // namespace

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
// is -d sim:N. X4STEP_SIM as the library takes it: 1, or 0 / empty.
bool sim_wanted(const config &c) {
  if (c.sim || is_sim_device(c.device)) return true;
  const char *env = std::getenv("X4STEP_SIM");
  if (!env || !*env || std::string(env) == "0") return false;
  if (std::string(env) != "1")
    throw usage_error(std::string("X4STEP_SIM=") + env +
                      ": use 1 (the simulated ports sim:0..3 for LPT1..4) or 0; -p chooses the port");
  return true;
}

std::string device_of(const config &c) {
  if (!c.device.empty()) return c.device;
  return sim_wanted(c) ? "sim:" + std::to_string(c.lpt - 1) : x4step::device_path(c.lpt);
}

// --sim with -d naming a device: the simulator never touches one.
void check_sim(const config &c) {
  if (c.sim && !c.device.empty() && !is_sim_device(c.device))
    throw usage_error("--sim and -d " + c.device +
                      ": a simulated port never opens a device; use -d sim:N (N 0..3), or -p, with --sim");
  sim_wanted(c);  // a bad X4STEP_SIM
}

std::optional<subcommand> find_command(const std::string &name) {
  for (const auto &c : commands)
    if (name == c.name) return c.cmd;
  return std::nullopt;
}

const char *name_of(subcommand c) {
  for (const auto &e : commands)
    if (e.cmd == c) return e.name;
  return "x4ctl";
}

std::string version_text() { return "x4ctl " X4CTL_VERSION "\n"; }

config parse_args(const std::vector<std::string> &args) {
  config c;
  const std::vector<option_spec> specs = {{"port", 'p', true, opt_port},
                                          {"device", 'd', true, opt_device},
                                          {"sim", 0, false, opt_sim},
                                          {"help", 'h', false, opt_help},
                                          {"version", 'v', false, opt_version}};
  const split_result r = split(args, 1, specs, "", true);
  for (const auto &o : r.options)
    if (!apply_common(c, o, "") && o.id == opt_version) c.version = true;
  const std::string name = r.operands.empty() ? "" : r.operands[0];
  if (c.help || c.version) {
    // "x4ctl --help move" shows the help of move.
    if (const auto cmd = find_command(name); cmd && c.help) c.cmd = *cmd;
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
  const auto cmd = find_command(name);
  if (!cmd) throw usage_error("unknown command '" + name + "'");
  c.cmd = *cmd;
  const size_t at = args.size() - r.operands.size() + 1;  // after the subcommand's name
  parse_subcommand(c, args, at);
  check_sim(c);
  // A simulated port lives in this process: no background holder.
  if (sim_wanted(c)) {
    c.wait = true;
    c.no_wait = false;
  }
  return c;
}

std::string help_text(subcommand c) {
  switch (c) {
    case subcommand::interactive:
    case subcommand::help:
      return "Usage: x4ctl [-p LPT | -d PATH] [COMMAND [ARGS...]]\n"
             "       x4ctl [LPT]\n"
             "\n"
             "Drive up to four stepper motors on a PC parallel port through the x4step\n"
             "kernel module. Without a COMMAND, x4ctl is X4Step's test program: a prompt\n"
             "that takes the commands of TEST.EXE (H lists them, see also 'x4ctl run --help').\n"
             "\n"
             "Options:\n" +
             std::string(port_help) +
             "  -v, --version        show the version\n"
             "\n"
             "Commands:\n"
             "  move STEPS...        interpolated move of up to four axes\n"
             "  jog AXIS +|-         endless move of one axis until braked; 'jog X+' (a\n"
             "                       letter): an axis of a machine file, in its units\n"
             "  brake                brake the running move along its ramp\n"
             "  stop                 stop the running move at once (emergency stop)\n"
             "  status               show the state of the port\n"
             "  in                   show the five inputs\n"
             "  out SIGNAL on|off    set output signal 1 (pin 1) or 2 (pin 14)\n"
             "  keys [CODE...]       set the keys that brake a move (ESC always does)\n"
             "  sweep AXIS STEPS FROM TO STEP\n"
             "                       frequency sweep of one axis, to find resonances\n"
             "  monitor              follow the moves on the port, read-only\n"
             "  watch                print the port's events as they happen, read-only\n"
             "  list                 the ports, their module's version, who holds them\n"
             "  run [FILE]           run test program commands from FILE or standard input\n"
             "  timing               show or set the step signal timing (pulse, space, ...)\n"
             "  mode [MODE]          show or set the output mode: clock-dir, or smc-phase and\n"
             "                       smc-hold for SMC800/SMC1500 boards\n"
             "  path [FILE]          run a continuous path of straight segments in steps\n"
             "  gcode FILE           run a G-code part program on a machine (machine file)\n"
             "  mdi BLOCK...         run G-code blocks given as arguments (\"G1 X10 F300\")\n"
             "  panel                full-screen operator panel of a machine: positions, jog,\n"
             "                       set zero, go to, home\n"
             "\n"
             "Positioning: coordinates, independent axes, homing, limit switches:\n"
             "  profile AXIS         show or set the ramp of an axis' own moves\n"
             "  goto AXIS=POS...     move axes on their own to coordinates\n"
             "  home AXIS            reference run: find the reference switch, zero there;\n"
             "                       'home --machine FILE [LETTERS]': a machine's axes\n"
             "  zero AXIS...         stop the axes and set their coordinates (stop and zero)\n"
             "  limits               show or set the reference and limit switch inputs\n"
             "  halt AXIS...         brake (or stop) the moves of some axes\n"
             "\n"
             "  help [COMMAND]       show the help of a command\n"
             "\n"
             "Run 'x4ctl COMMAND --help' for the options of a command. Axes are 1 to 4.\n"
             "Reading commands take --json ('x4ctl help list' describes the format).\n"
             "\n"
             "Exit status: 0 success; 1 the port refused, or a move did not reach its\n"
             "target; 2 bad usage (checked before the port is opened: nothing moved).\n";
    case subcommand::move:
      return "Usage: x4ctl move [OPTIONS] STEPS1 [STEPS2 [STEPS3 [STEPS4]]]\n"
             "       x4ctl move [OPTIONS] STEPS... --then STEPS... [--then STEPS...]...\n"
             "\n"
             "Move axes 1..4 by the given steps (signed, -16777216..16777216; missing\n"
             "axes stay) interpolated (X4Load, X4Start): the axis with the longest path\n"
             "runs at the frequency, the others follow it, all start and stop together.\n"
             "Each --then is one more move at the same frequency and ramp: it is\n"
             "preloaded while the move before it runs, and started the moment that one ends\n"
             "(X4Load during the move, X4Start once X4GetState is 0): no pause for planning.\n"
             "A move that is braked or stopped ends the sequence: the rest do not start.\n"
             "\n"
             "Options:\n" +
             std::string(motion_help) +
             "      --then STEPS1 [STEPS2 [STEPS3 [STEPS4]]]\n"
             "                       one more move after the one before (repeatable)\n"
             "  -w, --wait           stay until the moves end, showing progress (the\n"
             "                       default); Ctrl-C brakes, a second Ctrl-C stops\n"
             "  -b, --background     return once the motors run (see below)\n" +
             port_help + "\n" +
             "With --background, x4ctl returns once the motors run, and a background\n"
             "x4ctl holds the port until the moves end, starting the --then moves too\n"
             "(the module brakes a move whose program exits). 'x4ctl brake', 'x4ctl stop'\n"
             "or ESC on the console keyboard end it early; 'x4ctl monitor' follows it.\n"
             "\n"
             "Exit status: 0 every move reached its target (with --background: the move\n"
             "runs); 1 the port refused, or a move was braked or stopped; 2 bad usage (a\n"
             "bad value after --then too: nothing moved).\n"
             "Examples: x4ctl move 1000 800 600 400 --freq 1000 --ramp 50\n"
             "          x4ctl move 1000 800 600 400 --then -1000 -800 -600 -400\n"
             "          x4ctl move 100000 --background; x4ctl brake\n";
    case subcommand::jog:
      return "Usage: x4ctl jog [OPTIONS] AXIS +|-\n"
             "       x4ctl jog [--machine FILE] [--feed F] [--distance D] LETTER+|LETTER-\n"
             "\n"
             "Move AXIS (1..4) endlessly in the positive (+) or negative (-) direction\n"
             "(X4MovePos, X4MoveNeg) until it is braked: by ESC or a brake key on the\n"
             "console keyboard, by 'x4ctl brake' or 'x4ctl stop', or after --time.\n"
             "\n"
             "With an axis letter and a sign (X+, Z-), the axis of a machine file\n"
             "(machines/README.md) moves in its units, in machine coordinates: by the\n"
             "distance D, ending exactly at round(position x SCALE) steps (a target\n"
             "beyond a soft limit is refused, nothing moves); without it toward its soft\n"
             "limit (MAX_LIMIT for +, MIN_LIMIT for -) until any key, Ctrl-C or 'x4ctl\n"
             "brake' brakes it, or it stops there. Soft limits apply whether the axis is\n"
             "homed or not. At --feed, ramps at the axis' MAX_ACCELERATION (the axis'\n"
             "own move: 'x4ctl profile' is put back afterwards).\n"
             "\n"
             "Options:\n" +
             std::string(motion_help) +
             "  -t, --time=MS        brake after MS milliseconds\n"
             "  -w, --wait           stay until the move ends, showing the steps; Ctrl-C\n"
             "                       brakes, a second Ctrl-C stops\n"
             "  -m, --machine=FILE   the machine file of LETTER+|- (default: $X4STEP_MACHINE,\n"
             "                       else /etc/x4step/machine.ini); its PORT is the port\n"
             "      --feed=F         units/min (degrees for A B C); at most MAX_VELOCITY\n"
             "                       (default: a quarter of it)\n"
             "      --distance=D     jog by D units (> 0) in the sign's direction\n" +
             port_help + "\n" + background_help +
             "\n"
             "Exit status: 0 the axis ran (and, with --wait, was braked; LETTER+|-: the jog\n"
             "ended or was braked); 1 the port refused, a --distance jog was braked, or a\n"
             "continuous one stood at its soft limit already; 2 bad usage or machine file,\n"
             "or a target beyond a soft limit (nothing moved).\n"
             "Examples: x4ctl jog 1 + --time 2000\n"
             "          x4ctl jog X+ --machine machines/smc1500-mill.ini --distance 0.5\n"
             "          x4ctl jog Z- --machine machines/smc1500-mill.ini --feed 60\n";
    case subcommand::brake:
    case subcommand::stop: {
      const bool brake = c == subcommand::brake;
      return std::string("Usage: x4ctl ") + (brake ? "brake" : "stop") +
             " [OPTIONS]\n"
             "\n" +
             (brake ? "Brake the running move along its ramp (X4Brake).\n"
                    : "Stop the running move at once, without ramp (X4Stop): an emergency stop,\n"
                      "the motors may lose steps.\n") +
             "It reaches every move on the port, whichever program controls it (an x4ctl\n"
             "in the background or in another shell, any other program, or the module\n"
             "braking the moves of a program that exited): the module's emergency halt\n"
             "is allowed to anyone who may read the port (group lp). The event stream\n"
             "('x4ctl watch') shows it as an emergency " +
             (brake ? "brake" : "stop") +
             ". Waits until the motors stand and\n"
             "shows the steps made.\n"
             "\n"
             "Options:\n" +
             port_help +
             "\n"
             "Exit status: 0 done; 1 no move was running, or the port is missing.\n";
    }
    case subcommand::status:
      return "Usage: x4ctl status [OPTIONS]\n"
             "\n"
             "Show the state of the port, read-only (also while another program moves the\n"
             "motors): running, loaded, controlled, the steps of the last move, inputs,\n"
             "outputs, the key that braked the last move, the number of moves ended; and\n"
             "per axis its coordinate, whether it is synchronized (referenced by 'home' or\n"
             "'zero'), its state and its errors (a limit switch hit, reference travel\n"
             "exceeded). 'x4ctl limits' shows the switches.\n"
             "\n"
             "Options:\n"
             "  -j, --json           one JSON object instead of text\n" +
             std::string(port_help);
    case subcommand::in:
      return "Usage: x4ctl in [OPTIONS]\n"
             "\n"
             "Show the levels of the five inputs (X4GetIn), 1 = HIGH: pins 15, 13, 12, 10\n"
             "and 11 are bits 0..4 of the value. The module reads the port only while it\n"
             "has claimed it, for a controller: while another program controls the port\n"
             "they are read through its claim; while none does, x4ctl takes the port for\n"
             "as long as it runs (as 'x4ctl out' does). When another driver (lp, ppdev)\n"
             "holds the port, or with --read-only, the levels shown are the last ones read,\n"
             "marked 'stale' with their age.\n"
             "\n"
             "Options:\n"
             "  -w, --watch          show them continuously until Ctrl-C\n"
             "  -r, --read-only      never take the port (stale levels if nobody controls it)\n\n"
             "  -j, --json           JSON instead of text (one object per line with --watch)\n" +
             std::string(port_help);
    case subcommand::out:
      return "Usage: x4ctl out [OPTIONS] SIGNAL on|off\n"
             "\n"
             "Set output signal 1 (pin 1) or 2 (pin 14) high (on) or low (off) (X4SetOut).\n"
             "The module drives every output low when its controller lets go of the port,\n"
             "so x4ctl holds the port, and the level, until Ctrl-C or SIGTERM, or for\n"
             "--time; no move can run meanwhile. To switch outputs around moves, use the\n"
             "O command in 'x4ctl run'.\n"
             "\n"
             "Options:\n"
             "  -t, --time=MS        let go of the port after MS milliseconds\n" +
             std::string(port_help);
    case subcommand::keys:
      return "Usage: x4ctl keys [OPTIONS] [CODE...]\n"
             "\n"
             "Set up to 20 keys that brake a running move (X4BrakeCodes), as PC/AT set-1\n"
             "scan codes: CODE (1..127) brakes when the key is pressed, CODE+128 when it\n"
             "is released; e.g. 28 Enter, 57 Space, 72/75/77/80 the cursor keys. ESC (1)\n"
             "always brakes; without codes only ESC does. The module keeps the codes\n"
             "after x4ctl exits, until they are set again.\n"
             "\n"
             "Options:\n" +
             std::string(port_help) + "\nExample: x4ctl keys 28 156   (Enter pressed or released)\n";
    case subcommand::sweep:
      return "Usage: x4ctl sweep [OPTIONS] AXIS STEPS FROM TO STEP\n"
             "\n"
             "Frequency sweep of one axis to find its resonances (TEST.EXE's A command):\n"
             "AXIS moves STEPS at FROM Hz, FROM+STEP Hz, ... up to TO Hz, alternately\n"
             "forth and back so that it stays within its travel. FROM > TO sweeps down.\n"
             "Ctrl-C or ESC on the console keyboard brakes and ends the sweep.\n"
             "\n"
             "Options:\n"
             "  -r, --ramp=MS        ramp time, at most FROM and TO in Hz (default 0)\n" +
             std::string(port_help) +
             "\n"
             "Exit status: 0 every frequency ran; 1 the port refused or a move was braked;\n"
             "2 bad usage.\n"
             "Example: x4ctl sweep 2 1000 200 500 20\n";
    case subcommand::watch:
      return "Usage: x4ctl watch [OPTIONS]\n"
             "\n"
             "Print the events of the port as the module reports them, one line each,\n"
             "until Ctrl-C (read-only): moves started (and their kind) and ended (completed,\n"
             "braked, stopped, at a limit, homed, ...), brake requests and who made them\n"
             "(a program, a brake key and its code, a controller's close), limit and\n"
             "reference switches hit, controllers opening and closing, the port going\n"
             "away. Each line starts with the event's number and its CLOCK_MONOTONIC\n"
             "time in seconds. The module keeps the last 256 events: events a slow reader\n"
             "missed show as 'missed N events'.\n"
             "\n"
             "Options:\n"
             "  -j, --json           one JSON object per line instead of text\n"
             "  -n, --count=N        end after N events\n" +
             std::string(port_help) +
             "\n"
             "Exit status: 0 at Ctrl-C or after N events; 1 the port is missing or went away.\n";
    case subcommand::monitor:
      return "Usage: x4ctl monitor [OPTIONS]\n"
             "\n"
             "Follow the moves on the port without disturbing the program that controls\n"
             "it (read-only): a line when a move starts and when it ends, with the steps\n"
             "of the four axes; on a terminal the steps count live. Ends with Ctrl-C.\n"
             "\n"
             "Options:\n"
             "  -n, --moves=N        end after N moves have ended\n\n"
             "  -j, --json           one JSON object per line: idle, running, started, ended\n" +
             std::string(port_help);
    case subcommand::run:
      return "Usage: x4ctl run [OPTIONS] [FILE]\n"
             "\n"
             "Run test program commands from FILE (standard input if FILE is - or missing),\n"
             "without a terminal. The whole script is checked first, and nothing moves if\n"
             "a line is wrong; then the first error, or a G or A move that is braked, ends\n"
             "the run.\n"
             "\n"
             "Options:\n"
             "  -c, --check          only check the script; do not open the port\n"
             "  -e, --echo           print each command after the prompt before it runs\n" +
             std::string(port_help) + "\n" + language_help();
    case subcommand::timing:
      return "Usage: x4ctl timing [OPTIONS]\n"
             "\n"
             "Show the step signal timing of the port, or change the times given (the\n"
             "others stay) and show the result. The module keeps the timing for the port\n"
             "after x4ctl exits, until it is set again. Every time is a minimum, in ns.\n"
             "\n"
             "Options:\n"
             "      --pulse=NS       clock high time: 0 (symmetric clock, half a period high,\n"
             "                       as X4Step does) or 1000..1000000 ns\n"
             "      --space=NS       minimum clock low time, 0..1000000 ns\n"
             "      --setup=NS       directions out before the first step, 0..1000000 ns\n"
             "                       (X4Step: 100000)\n"
             "      --hold=NS        directions kept after the last step, 0..1000000 ns\n"
             "  -j, --json           one JSON object instead of text\n" +
             std::string(port_help) +
             "\n"
             "A move or jog whose frequency leaves no room for pulse + space (with the\n"
             "symmetric clock: for space in half a period) is refused later by the module\n"
             "with \"frequency too high\"; 'max freq' shows the limit. In the smc-phase and\n"
             "smc-hold modes (see 'x4ctl mode') pulse and space do not apply.\n"
             "\n"
             "Exit status: 0 done; 1 the port refused, or another program holds it;\n"
             "2 bad usage (a time out of range: nothing changed).\n"
             "Example: x4ctl timing --pulse 10000 --space 40000   (moves up to 20000 Hz)\n";
    case subcommand::mode:
      return "Usage: x4ctl mode [OPTIONS] [clock-dir|smc-phase|smc-hold]\n"
             "\n"
             "Show or set how the port drives its motors. The module keeps the mode for\n"
             "the port after x4ctl exits, until it is set again.\n"
             "  clock-dir   a clock and a direction signal per axis (X4Step, the default)\n"
             "  smc-phase   half-step phase patterns for SMC800/SMC1500 boards, which have\n"
             "              no clock and direction inputs; motors off at rest\n"
             "  smc-hold    the same, with reduced holding current at rest\n"
             "The SMC boards drive three motors: in smc-phase and smc-hold, moves of axis 4\n"
             "are refused, and the pulse and space of 'x4ctl timing' do not apply.\n"
             "\n"
             "Options:\n"
             "  -j, --json           one JSON object instead of text\n" +
             std::string(port_help) +
             "\n"
             "Exit status: 0 done; 1 the port refused, or another program holds it;\n"
             "2 bad usage.\n";
    case subcommand::profile:
      return "Usage: x4ctl profile [OPTIONS] AXIS\n"
             "\n"
             "Show the ramp of the axis' own moves ('goto'), or change the values given (the\n"
             "others stay) and show the result (ProStep4 section 2.5). The axis starts at\n"
             "v0, speeds up with a0 to vm, slows down with ae to ve and stops there; a move\n"
             "too short for vm turns where the ramps meet. The module keeps the profile\n"
             "after x4ctl exits.\n"
             "\n"
             "Options:\n"
             "      --v0=V           start velocity, 0..100000 steps/s (default 0)\n"
             "      --ve=V           stop velocity, 0..100000 steps/s (default 0)\n"
             "      --vm=V           maximum velocity, 1..100000 steps/s (default 1000)\n"
             "      --a0=A           acceleration, 0..1000000 steps/s^2 (default 1000);\n"
             "                       0: no ramp, the axis jumps to vm\n"
             "      --ae=A           deceleration, 0..1000000 steps/s^2 (default 1000)\n\n"
             "  -j, --json           one JSON object instead of text\n" +
             std::string(port_help) +
             "\n"
             "v0 and ve must not exceed vm, and a ramp from rest to vm must last at most\n"
             "3600 s (vm / a0 and vm / ae).\n"
             "\n"
             "Exit status: 0 done; 1 the port refused (the axis moves), or another program\n"
             "holds it; 2 bad usage (nothing changed).\n"
             "Example: x4ctl profile 1 --v0 200 --vm 8000 --a0 40000 --ae 20000\n";
    case subcommand::go_to:
      return "Usage: x4ctl goto [OPTIONS] AXIS=POSITION [AXIS=POSITION...]\n"
             "\n"
             "Move each axis named on its own, with its profile ('x4ctl profile'), to the\n"
             "machine coordinate POSITION (-2147483648..2147483647); all start at once, each\n"
             "ends at its own time. Waits until they end and shows the coordinates of the\n"
             "four axes. An axis moving toward an active limit switch is stopped there by\n"
             "the module. ESC or Ctrl-C brakes, a second Ctrl-C stops.\n"
             "\n"
             "Options:\n"
             "      --relative       the numbers are distances from where the axes are\n"
             "      --no-wait        return once the axes run: a background x4ctl holds the\n"
             "                       port until they end (the module brakes the moves of a\n"
             "                       program that exits); 'x4ctl halt' or 'x4ctl brake'\n"
             "                       ends them early\n" +
             std::string(port_help) +
             "\n"
             "Exit status: 0 every axis reached its target (without waiting: they run);\n"
             "1 the port refused, or an axis was halted or stopped at a limit switch;\n"
             "2 bad usage (nothing moved).\n"
             "Examples: x4ctl goto 1=12000 2=-500\n"
             "          x4ctl goto 3=100 --relative\n";
    case subcommand::home:
      return "Usage: x4ctl home [OPTIONS] AXIS\n"
             "       x4ctl home [--machine FILE] [LETTERS...]\n"
             "\n"
             "Reference run of AXIS (ProStep4 section 3), without ramps: phase 1 runs at\n"
             "vref1 until the reference switch becomes active and stops there (--brake:\n"
             "brakes past it along the axis' profile deceleration, 'x4ctl profile AXIS\n"
             "--ae'); 50 ms later phase 2 runs from rest at vref2 until the switch changes\n"
             "again; there the coordinate becomes 0 and the axis synchronized. Each\n"
             "phase travels at most sref steps. Needs the axis' reference switch input\n"
             "('x4ctl limits AXIS --ref INPUT'). Waits until the run ends; ESC or Ctrl-C\n"
             "brakes it.\n"
             "\n"
             "With axis letters or --machine, or nothing with $X4STEP_MACHINE set, the axes\n"
             "of a machine file (all that home, or those named: 'home Z', 'home X Y')\n"
             "home as its [JOINT_n] HOME_* keys say (machines/README.md), in HOME_SEQUENCE\n"
             "order, those of one sequence at\n"
             "the same time: the reference run above on HOME_INPUT at HOME_SEARCH_VEL,\n"
             "then HOME_LATCH_VEL (units/s, times SCALE), each phase within 1.25 times\n"
             "the travel between the soft limits; there the axis' coordinate becomes\n"
             "HOME_OFFSET (the switch's place in machine coordinates), and it goes to\n"
             "HOME at MAX_VELOCITY before the next sequence starts. The inputs' polarity\n"
             "is the port's ('x4ctl limits --nc'). ESC or Ctrl-C brakes; an axis that\n"
             "does not home stops the later sequences.\n"
             "\n"
             "Options:\n"
             "      --vref1=V        phase 1 speed, signed: -100000..-1 or 1..100000 steps/s,\n"
             "                       the sign is the direction (default -1000)\n"
             "      --vref2=V        phase 2 speed, the same way (default 100)\n"
             "      --sref=N         the longest travel of a phase, 1..2147483647 steps\n"
             "                       (default 100000)\n"
             "      --phase=1|2      only this phase (semi-automatic); default both\n"
             "      --brake          phase 1 brakes past the switch (it must stay active\n"
             "                       over the brake distance, vref1^2 / 2 ae steps)\n"
             "  -m, --machine=FILE   the machine file of LETTERS (default: $X4STEP_MACHINE,\n"
             "                       else /etc/x4step/machine.ini); its PORT is the port\n" +
             std::string(port_help) +
             "\n"
             "Exit status: 0 done (both phases or phase 2: the axis is synchronized);\n"
             "1 the port refused, no reference switch, sref exceeded, a limit switch hit,\n"
             "or the run was halted; 2 bad usage.\n"
             "Examples: x4ctl home 1 --vref1 -2000 --vref2 200 --sref 50000\n"
             "          x4ctl home --machine machines/smc1500-mill.ini\n";
    case subcommand::zero:
      return "Usage: x4ctl zero [OPTIONS] AXIS...\n"
             "\n"
             "Stop and zero (ProStep4 command bit 5): stop the axes at once if they move\n"
             "(with the axes moving interpolated with them), set their coordinates to 0, or\n"
             "to --at, and mark them synchronized.\n"
             "\n"
             "Options:\n"
             "      --at=POSITION    the coordinate to set, -2147483648..2147483647\n"
             "                       (default 0)\n" +
             std::string(port_help) +
             "\n"
             "Exit status: 0 done; 1 the port refused, or another program holds it;\n"
             "2 bad usage.\n";
    case subcommand::limits:
      return "Usage: x4ctl limits [OPTIONS] [AXIS]\n"
             "\n"
             "Show which inputs are the reference and limit switches of each axis, and\n"
             "the state of the five inputs; or name the switch inputs of AXIS, or the\n"
             "normally closed inputs, and show the result. Inputs 1..5 are pins 15, 13,\n"
             "12, 10 and 11 (X4GetIn bits 0..4); 0 or 'none': no switch. An input may\n"
             "serve several axes and both directions (switches in parallel, as on the\n"
             "SMC1500): a hit is then given to the axis that moved toward it, and flagged\n"
             "ambiguous if more than one did. An axis moving toward an active limit is\n"
             "stopped by the module on that very step; moving away from it is allowed.\n"
             "The module keeps the settings after x4ctl exits. Only while nothing moves.\n"
             "\n"
             "Options:\n"
             "      --ref=INPUT      reference switch of AXIS (for 'home')\n"
             "      --plus=INPUT     limit switch E+ of AXIS (end of the positive travel)\n"
             "      --minus=INPUT    limit switch E- of AXIS\n"
             "      --nc=INPUTS      the normally closed inputs (active while LOW): a list\n"
             "                       like 1,3, a mask like 0x05, or none; the others are\n"
             "                       normally open (active while HIGH)\n\n"
             "  -j, --json           one JSON object instead of text\n" +
             std::string(port_help) +
             "\n"
             "Exit status: 0 done; 1 the port refused (a move runs), or another program\n"
             "holds it; 2 bad usage.\n"
             "Example: x4ctl limits 1 --ref 3 --plus 1 --minus 2 --nc 1,2\n";
    case subcommand::path:
      return "Usage: x4ctl path [OPTIONS] [FILE]\n"
             "\n"
             "Run a continuous path: straight segments one after the other without\n"
             "stopping between them, planned ahead by the module so that the motors\n"
             "always come to rest on the path. FILE (default: standard input) has one\n"
             "segment per line: up to 4 step counts (axes 1..4, signed), then optionally\n"
             "speed=STEPS/S (along the path), accel=STEPS/S^2 and corner=STEPS/S (the\n"
             "most the corner before it allows; else from the corner's angle and the\n"
             "junction deviation). '#' starts a comment. The whole file is checked\n"
             "before the first step: a bad line is named as FILE:LINE:COLUMN. Then it is\n"
             "streamed to the module while it runs, with the progress shown.\n"
             "Ctrl-C (or 'x4ctl brake') holds the path along it and flushes it; 'x4ctl\n"
             "stop' stops at once.\n"
             "\n"
             "Options:\n"
             "  -s, --speed=STEPS/S  speed along the path where a line has none (1000)\n"
             "  -a, --accel=STEPS/S^2 acceleration where a line has none (10000)\n"
             "      --deviation=D    junction deviation in steps (0.5): how far from a\n"
             "                       corner the path may round it at speed (as GRBL's)\n"
             "  -o, --override=PCT   feed override, 1..200 percent (100)\n"
             "  -c, --check          check the file and stop there: nothing moves\n"
             "  -j, --json           progress as JSON lines (state, line, done, speed)\n" +
             std::string(port_help) +
             "\n"
             "Exit status: 0 the path ran to its end; 1 it was aborted or the port\n"
             "refused; 2 bad usage or a bad line.\n"
             "Example: printf '4000 0\\n0 4000\\n-4000 0\\n0 -4000\\n' | x4ctl path -s 2000\n";
    case subcommand::gcode:
      return "Usage: x4ctl gcode [OPTIONS] FILE\n"
             "\n"
             "Run a G-code part program (RS274/NGC as CAM post-processors for LinuxCNC\n"
             "and GRBL write it) on a machine described by a machine file (axes, steps\n"
             "per unit, speeds, soft limits, port: machines/README.md). The whole program\n"
             "is checked first, from where the machine stands: a bad line, or a point\n"
             "beyond a soft limit, is named as FILE:LINE:COLUMN and nothing moves. Then\n"
             "it runs on the module's path queue, with its progress: percent of the path\n"
             "length, line, feed, elapsed and remaining time.\n"
             "Keys on a terminal: space holds and resumes, ESC aborts (hold, then flush),\n"
             "+ and - change the feed override by 10 %. Ctrl-C aborts too; 'x4ctl stop'\n"
             "stops at once. M0, M1 and M6 wait for space (or ESC) with the path at\n"
             "rest: such a program needs a terminal, or --no-pause. Outputs the machine\n"
             "file names for spindle and coolant follow M3/M4/M5 and M7/M8/M9, and are\n"
             "switched off at the end. The machine file's PORT is the port unless -d is\n"
             "given.\n"
             "\n"
             "Options:\n"
             "  -m, --machine=FILE   the machine file (default: $X4STEP_MACHINE, else\n"
             "                       /etc/x4step/machine.ini)\n"
             "  -c, --check          check the program and stop there: a summary (lines,\n"
             "                       segments, path length, estimated time, extents), as\n"
             "                       if the machine stood at machine zero; nothing moves\n"
             "  -o, --override=PCT   feed override, 1..200 percent (100)\n"
             "      --no-pause       M0, M1 and M6 stop the path, say so and go on without\n"
             "                       waiting (a preview on the simulated port, a script)\n"
             "      --svg=FILE       draw the planned toolpath and what the motors did\n"
             "                       (positions read during the run), top view X Y and\n"
             "                       side view X Z, in the machine's units; with --check\n"
             "                       the planned path only\n"
             "  -j, --json           the summary, progress and result as JSON lines\n" +
             std::string(port_help) +
             "\n"
             "Exit status: 0 the program ran to its end (or --check found it good); 1 it\n"
             "was aborted or the port refused; 2 bad usage, a bad machine file or program.\n"
             "Example: x4ctl gcode --machine machines/smc1500-mill.ini --check part.ngc\n";
    case subcommand::mdi:
      return "Usage: x4ctl mdi [OPTIONS] BLOCK...\n"
             "\n"
             "Run G-code blocks typed on the command line (manual data input), each\n"
             "argument one line, as a program of those lines followed by M2: checked\n"
             "whole first (a bad word is named as mdi:LINE:COLUMN and nothing moves),\n"
             "then run as 'x4ctl gcode' runs a file, from where the machine stands, with\n"
             "its keys and options. Nothing persists between invocations: each starts\n"
             "in the machine file's units, G90, G17, G94, G54 with every offset zero (so\n"
             "coordinates are machine coordinates), no tool length offset and no feed\n"
             "rate: give G91, G20 or F again in the blocks that need them.\n"
             "\n"
             "Options:\n"
             "  -m, --machine=FILE   the machine file (default: $X4STEP_MACHINE, else\n"
             "                       /etc/x4step/machine.ini)\n"
             "  -c, --check          check the blocks and stop there; nothing moves\n"
             "  -o, --override=PCT   feed override, 1..200 percent (100)\n"
             "      --no-pause       M0, M1 and M6 stop the path, say so and go on\n"
             "  -j, --json           progress and result as JSON lines\n" +
             std::string(port_help) +
             "\n"
             "Exit status: 0 the blocks ran to their end (or --check found them good);\n"
             "1 aborted or the port refused; 2 bad usage, a bad machine file or block.\n"
             "Example: x4ctl mdi --machine machines/smc1500-mill.ini \"G0 Z-1\" \"G1 X10 Y5 F300\"\n";
    case subcommand::panel:
      return "Usage: x4ctl panel [OPTIONS]\n"
             "\n"
             "A full-screen operator panel for a machine file's machine, as the SMC1500\n"
             "program's screen: each axis' position in work and machine coordinates\n"
             "(updated while it moves), homed or not, the jog feed and step, the state.\n"
             "Keys:\n"
             "  Right/Left  jog X+/X-        Up/Down  jog Y+/Y-     PgUp/PgDn  jog Z+/Z-\n"
             "  ] / [       jog A+/A-\n"
             "  i           jog step: continuous (to the soft limit), or 1, 0.1, 0.01 units\n"
             "  + / -       jog and go-to feed up/down (1-2-5 steps, at most MAX_VELOCITY)\n"
             "  z or 0      set the work zero of every axis where it stands: a work offset\n"
             "              for this session only (machine coordinates and soft limits\n"
             "              stay; nothing is written to the port)\n"
             "  g           go to a position in work coordinates (typed: X10 Y-5; Enter\n"
             "              goes, ESC cancels); each axis on its own at the feed\n"
             "  h           home (as 'x4ctl home --machine FILE')\n"
             "  space, ESC  stop: while anything moves, every key brakes it\n"
             "  q           quit (also Ctrl-C)\n"
             "Moves keep to the soft limits. Nothing is left running when the panel ends:\n"
             "a move is braked first (also at SIGINT, SIGTERM or a hang-up). Needs a\n"
             "terminal; the machine file's PORT is the port unless -d is given.\n"
             "\n"
             "Options:\n"
             "  -m, --machine=FILE   the machine file (default: $X4STEP_MACHINE, else\n"
             "                       /etc/x4step/machine.ini)\n"
             "      --feed=F         the feed to start with, units/min, at most the fastest\n"
             "                       axis' MAX_VELOCITY (default: a quarter of that)\n" +
             std::string(port_help) +
             "\n"
             "Exit status: 0 quit; 1 the port refused, or no terminal; 2 bad usage or\n"
             "machine file.\n"
             "Example: x4ctl panel --machine machines/smc1500-mill.ini\n";
    case subcommand::list:
      return "Usage: x4ctl list [OPTIONS]\n"
             "\n"
             "List the ports x4step serves (/dev/x4stepN for parportN), read-only: the\n"
             "interface (ABI) version of the module, and who holds each port: a\n"
             "controller (its PID and name, where this user may see its process), another\n"
             "parport driver that has claimed it (lp, or ppdevN for a program using\n"
             "/dev/parportN), or nobody. The first line is the library's version.\n"
             "With --sim (or X4STEP_SIM=1): the simulated ports sim:0..3 instead, which\n"
             "live in the program that opens them (a fresh one in each).\n"
             "\n"
             "Options:\n"
             "  -j, --json           one JSON object instead of text\n"
             "      --sim            the simulated ports\n"
             "  -h, --help           show this help\n"
             "\n"
             "JSON, of every command with --json: each object (one per line) starts with\n"
             "\"schema\":1, the version of this format, raised when a field changes or goes\n"
             "(new fields keep it); yes/no values and pin levels (true: HIGH) are JSON\n"
             "booleans. An error is such an object too, on standard output:\n"
             "{\"schema\":1,\"error\":{\"message\":\"...\",\"errno\":13}} (errno null when none\n"
             "applies); the exit status is the same as without --json.\n"
             "\n"
             "Exit status: 0 done; 1 no port (is x4step loaded?).\n";
    case subcommand::halt:
      return "Usage: x4ctl halt [OPTIONS] AXIS...\n"
             "\n"
             "Brake the moves of the axes along their ramps, or with --stop stop them at\n"
             "once (they lose their synchronization); the axes moving interpolated with\n"
             "them halt too, other axes go on. The moves belong to the x4ctl that started\n"
             "them ('goto --no-wait', 'move' in the background, ...): it is asked to halt\n"
             "them, and this command waits until they stand and shows their coordinates.\n"
             "\n"
             "Options:\n"
             "  -s, --stop           stop at once rather than brake\n" +
             std::string(port_help) +
             "\n"
             "Exit status: 0 done; 1 none of the axes moves, or another program holds the\n"
             "port; 2 bad usage.\n";
  }
  return "";
}

}  // namespace x4ctl
