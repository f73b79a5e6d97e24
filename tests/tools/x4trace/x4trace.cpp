// SPDX-License-Identifier: GPL-2.0
//
// x4trace: read QEMU's trace of parallel port writes (-trace parallel_ioport_write)
// and show what the 25-pin connector did: edges, a summary, a VCD, an SVG plot.
//
// QEMU (7.2, "log" trace backend, -msg timestamp=on) writes lines like
//   12345@1700000000.123456:parallel_ioport_write write [SW] addr 0x00 val 0x02
// Only "[SW]" writes to addr 0x00 (data) and 0x02 (control) are used.
// The timestamps are host time: under TCG they are noisy, and x4trace only
// reports them.
//
// Build: g++ -std=c++17 -O2 -Wall -Wextra -Werror -o x4trace x4trace.cpp

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "../../../lib/sim/vcd_pins.hpp"
#include "../../../tools/json_string.hpp"  // x4ctl's too

namespace {

using x4tools::json_string;

const char *const kUsage =
    "usage: x4trace edges TRACE\n"
    "       x4trace summary TRACE [--json]\n"
    "       x4trace vcd TRACE OUT.vcd\n"
    "       x4trace svg TRACE OUT.svg [--bin-ms N]\n"
    "       x4trace moves TRACE\n"
    "       x4trace compare TRACE1 TRACE2 [--within-ns N] [--max-ns N] [--late-ns N] [--permille N]\n"
    "TRACE is QEMU's log of -trace parallel_ioport_write (with -msg timestamp=on),\n"
    "x4vport's trace (\"<t_ns> d|c|s 0xVV\" lines) or a VCD file with x4trace's pin\n"
    "names (the simulated port's X4STEP_SIM_VCD); '-' reads standard input.\n";

[[noreturn]] void fail(const std::string &msg, int status = 1) {
  std::cerr << "x4trace: " << msg << "\n";
  std::exit(status);
}

[[noreturn]] void usage_error(const std::string &msg) {
  std::cerr << "x4trace: " << msg << "\n" << kUsage;
  std::exit(2);
}

// ---------------------------------------------------------------- the trace

struct Write {
  int64_t t_ns;  // relative to the first kept write
  uint8_t reg;   // 0 data, 2 control
  uint8_t val;
};

struct Trace {
  std::vector<Write> writes;
  size_t lines = 0;
  size_t ignored_writes = 0;  // other addresses or not [SW]
  bool timestamps = true;     // false if any kept line had none
  int64_t t0_abs_ns = 0;      // host time of the first kept write
};

// "SEC.FRAC" -> ns; false if malformed.
bool parse_time(const char *s, const char *end, int64_t *ns) {
  int64_t sec = 0, frac = 0, scale = 1000000000;
  const char *p = s;
  if (p == end || *p < '0' || *p > '9') return false;
  for (; p < end && *p >= '0' && *p <= '9'; p++) sec = sec * 10 + (*p - '0');
  if (p < end && *p == '.') {
    for (p++; p < end && *p >= '0' && *p <= '9'; p++) {
      if (scale > 1) {
        scale /= 10;
        frac += (*p - '0') * scale;
      }
    }
  }
  if (p != end) return false;
  *ns = sec * 1000000000 + frac;
  return true;
}

bool parse_hex(const char *&p, unsigned *out) {
  char *end;
  errno = 0;
  unsigned long v = std::strtoul(p, &end, 16);
  if (end == p || errno) return false;
  p = end;
  *out = static_cast<unsigned>(v);
  return true;
}

// x4vport's trace line "<t_ns> <d|c|s> 0xVV" (tests/qemu/fixtures/x4vport.c), guest
// time in ns: data and control as QEMU's addresses 0 and 2, status ignored.
bool parse_x4vport(const std::string &line, int64_t *t_ns, unsigned *addr, unsigned *val) {
  unsigned long long t;
  char reg;
  int end = 0;
  if (std::sscanf(line.c_str(), "%llu %c 0x%x%n", &t, &reg, val, &end) != 3 || end != (int)line.size() ||
      *val > 0xff || (reg != 'd' && reg != 'c' && reg != 's'))
    return false;
  *t_ns = static_cast<int64_t>(t);
  *addr = reg == 'd' ? 0 : reg == 'c' ? 2 : 1;
  return true;
}

Trace read_vcd(std::istream &in, const std::string &path);

Trace read_trace(const std::string &path) {
  std::ifstream file;
  std::istream *in = &std::cin;
  if (path != "-") {
    file.open(path);
    if (!file) fail("cannot read " + path + ": " + std::strerror(errno));
    in = &file;
  }
  if (in->peek() == '$') return read_vcd(*in, path);
  static const char kEvent[] = "parallel_ioport_write ";
  Trace tr;
  bool have_t0 = false;
  int64_t last_abs = 0;
  std::string line;
  while (std::getline(*in, line)) {
    tr.lines++;
    int64_t vt;
    unsigned vaddr, vval;
    if (parse_x4vport(line, &vt, &vaddr, &vval)) {
      if (vaddr == 1) continue;
      if (!have_t0) {
        tr.t0_abs_ns = vt;
        have_t0 = true;
      }
      tr.writes.push_back({vt - tr.t0_abs_ns, static_cast<uint8_t>(vaddr), static_cast<uint8_t>(vval)});
      continue;
    }
    size_t ev = line.find(kEvent);
    if (ev == std::string::npos) continue;
    // Optional "PID@SEC.FRAC:" prefix.
    std::optional<int64_t> abs;
    if (ev > 0 && line[ev - 1] == ':') {
      size_t at = line.find('@');
      int64_t ns;
      if (at != std::string::npos && at < ev && parse_time(line.data() + at + 1, line.data() + ev - 1, &ns))
        abs = ns;
    }
    const char *p = line.c_str() + ev + sizeof(kEvent) - 1;
    if (std::strncmp(p, "write [", 7) != 0) continue;
    p += 7;
    const char *close = std::strchr(p, ']');
    if (!close) continue;
    bool sw = close - p == 2 && p[0] == 'S' && p[1] == 'W';
    p = close + 1;
    unsigned addr, val;
    if (std::strncmp(p, " addr ", 6) != 0) continue;
    p += 6;
    if (!parse_hex(p, &addr) || std::strncmp(p, " val ", 5) != 0) continue;
    p += 5;
    if (!parse_hex(p, &val)) continue;
    if (!sw || (addr != 0 && addr != 2)) {
      tr.ignored_writes++;
      continue;
    }
    if (!abs) {
      tr.timestamps = false;
      abs = last_abs;
    }
    if (!have_t0) {
      tr.t0_abs_ns = *abs;
      have_t0 = true;
    }
    last_abs = *abs;
    tr.writes.push_back({*abs - tr.t0_abs_ns, static_cast<uint8_t>(addr), static_cast<uint8_t>(val & 0xff)});
  }
  if (in->bad()) fail("error reading " + path);
  if (!tr.timestamps)
    std::cerr << "x4trace: warning: trace lines without timestamps "
                 "(run QEMU with -msg timestamp=on); times are meaningless\n";
  return tr;
}

// ---------------------------------------------------------------- the connector

// Output pins in connector order, with the simulated port's VCD names.
constexpr const auto &kPins = x4step::sim::vcd_pins;
constexpr int kNumPins = x4step::sim::vcd_n_pins;
constexpr int kAxes = 4;
int clk_pin(int axis) { return 3 + 2 * axis; }  // axis 0..3 = "axis 1..4"
int dir_pin(int axis) { return 2 + 2 * axis; }

int pin_index(int number) {
  for (int i = 0; i < kNumPins; i++)
    if (kPins[i].number == number) return i;
  return -1;
}

// Connector levels after writing VAL to REG: pairs (pin, level).
// Data D0..D7 drive pins 2..9; control C0, C1, C3 are inverted by the port.
void pin_levels(uint8_t reg, uint8_t val, int levels[kNumPins]) {
  if (reg == 0) {
    for (int bit = 0; bit < 8; bit++) levels[pin_index(2 + bit)] = (val >> bit) & 1;
  } else {
    levels[pin_index(1)] = !(val & 1);
    levels[pin_index(14)] = !(val & 2);
    levels[pin_index(16)] = (val & 4) != 0;
    levels[pin_index(17)] = !(val & 8);
  }
}

// A VCD file with x4trace's pin names (ours, or the simulated port's) as
// register writes: at each time, a data write if a data pin changed and a
// control write if a control pin did. Unknown levels ('x') are no write.
Trace read_vcd(std::istream &in, const std::string &path) {
  Trace tr;
  std::vector<int> id_pin(128, -1);  // VCD id (one character) -> kPins index
  int level[kNumPins] = {};
  bool data_changed = false, ctl_changed = false;
  int64_t t = 0;
  auto flush = [&] {
    uint8_t data = 0, ctl;
    for (int bit = 0; bit < 8; bit++) data |= (level[pin_index(2 + bit)] & 1) << bit;
    ctl = static_cast<uint8_t>((!level[pin_index(1)]) | (!level[pin_index(14)]) << 1 |
                               level[pin_index(16)] << 2 | (!level[pin_index(17)]) << 3);
    if (data_changed) tr.writes.push_back({t, 0, data});
    if (ctl_changed) tr.writes.push_back({t, 2, ctl});
    data_changed = ctl_changed = false;
  };
  std::string line;
  bool defs = true;
  while (std::getline(in, line)) {
    tr.lines++;
    if (line.empty()) continue;
    if (defs) {
      std::istringstream w(line);
      std::string kw, type, size, id, name;
      if (w >> kw >> type >> size >> id >> name && kw == "$var" && id.size() == 1 && id[0] > ' ' &&
          id[0] < 127) {
        for (int p = 0; p < kNumPins; p++)
          if (name == kPins[p].name) id_pin[static_cast<unsigned char>(id[0])] = p;
      }
      if (line.rfind("$enddefinitions", 0) == 0) defs = false;
      continue;
    }
    if (line[0] == '#') {
      flush();
      t = std::strtoll(line.c_str() + 1, nullptr, 10);
    } else if ((line[0] == '0' || line[0] == '1') && line.size() == 2) {
      const int p = id_pin[static_cast<unsigned char>(line[1]) & 127];
      if (p < 0) continue;
      level[p] = line[0] == '1';
      (kPins[p].number >= 2 && kPins[p].number <= 9 ? data_changed : ctl_changed) = true;
    }
  }
  flush();
  if (in.bad()) fail("error reading " + path);
  if (defs) fail(path + ": not a VCD file (no $enddefinitions)");
  return tr;
}

struct Change {
  size_t seq;  // index of the write
  int64_t t_ns;
  int pin;  // index into kPins
  int level;
  bool initial;  // first write of its register: a setting, not an edge
};

// Calls fn(const Change &) for every level change, in write order.
template <typename Fn>
void for_each_change(const Trace &tr, Fn fn) {
  int cur[kNumPins];
  std::fill(cur, cur + kNumPins, -1);
  for (size_t i = 0; i < tr.writes.size(); i++) {
    const Write &w = tr.writes[i];
    int next[kNumPins];
    std::copy(cur, cur + kNumPins, next);
    pin_levels(w.reg, w.val, next);
    for (int p = 0; p < kNumPins; p++) {
      if (next[p] != cur[p]) fn(Change{i, w.t_ns, p, next[p], cur[p] < 0});
      cur[p] = next[p];
    }
  }
}

std::string us(int64_t ns) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.3f", ns / 1000.0);
  return buf;
}

// ---------------------------------------------------------------- summary

struct PinStats {
  long rising = 0, falling = 0;
  int final_level = -1;
};

struct AxisStats {
  long steps = 0;  // rising clock edges
  long steps_dir_high = 0, steps_dir_low = 0;
  std::optional<int64_t> first_rise, last_rise;
  std::optional<int64_t> min_high, min_low, min_period, min_dir_setup;
  int dir_at_first_step = -1;
  long dir_changes_during_move = 0;
};

struct Summary {
  PinStats pins[kNumPins];
  AxisStats axes[kAxes];
  size_t data_writes = 0, control_writes = 0;
  int64_t duration_ns = 0;
};

void keep_min(std::optional<int64_t> &m, int64_t v) {
  if (!m || v < *m) m = v;
}

Summary summarize(const Trace &tr) {
  Summary s;
  for (const Write &w : tr.writes) (w.reg == 0 ? s.data_writes : s.control_writes)++;
  if (!tr.writes.empty()) s.duration_ns = tr.writes.back().t_ns;

  int level[kNumPins];
  std::fill(level, level + kNumPins, -1);
  std::optional<int64_t> last_edge[kNumPins];  // time of the pin's last edge
  std::optional<int64_t> dir_change[kAxes];    // dir edge not yet followed by a step
  // Direction edges after the axis' first step, counted by write order since
  // host timestamps can tie; the value at its last step is the result.
  long dir_edges_after_first[kAxes] = {};
  std::optional<size_t> dir_edge_seq[kAxes];

  for_each_change(tr, [&](const Change &c) {
    level[c.pin] = c.level;
    s.pins[c.pin].final_level = c.level;
    if (c.initial) return;
    (c.level ? s.pins[c.pin].rising : s.pins[c.pin].falling)++;
    int number = kPins[c.pin].number;
    for (int a = 0; a < kAxes; a++) {
      AxisStats &ax = s.axes[a];
      if (number == dir_pin(a)) {
        dir_change[a] = c.t_ns;
        dir_edge_seq[a] = c.seq;
        if (ax.first_rise) dir_edges_after_first[a]++;
      } else if (number == clk_pin(a)) {
        if (c.level) {
          int dir = level[pin_index(dir_pin(a))];
          ax.steps++;
          (dir ? ax.steps_dir_high : ax.steps_dir_low)++;
          if (!ax.first_rise) {
            ax.first_rise = c.t_ns;
            ax.dir_at_first_step = dir;
          }
          // A direction edge in this very write is not "during" the move.
          ax.dir_changes_during_move =
              dir_edges_after_first[a] - (dir_edge_seq[a] == c.seq && ax.steps > 1 ? 1 : 0);
          if (ax.last_rise) keep_min(ax.min_period, c.t_ns - *ax.last_rise);
          if (last_edge[c.pin]) keep_min(ax.min_low, c.t_ns - *last_edge[c.pin]);
          if (dir_change[a]) keep_min(ax.min_dir_setup, c.t_ns - *dir_change[a]);
          dir_change[a].reset();
          ax.last_rise = c.t_ns;
        } else if (last_edge[c.pin]) {
          keep_min(ax.min_high, c.t_ns - *last_edge[c.pin]);
        }
      }
    }
    last_edge[c.pin] = c.t_ns;
  });
  return s;
}

std::string opt_us(const std::optional<int64_t> &v, const char *none) {
  return v ? us(*v) : std::string(none);
}

std::string level_str(int level, const char *none) {
  return level < 0 ? std::string(none) : std::to_string(level);
}

// ---------------------------------------------------------------- moves

// One line per move, a move being AKTIV (pin 17) high until low:
//   MOVE <i> steps <s1> <s2> <s3> <s4> dirchanges <n> rampend <r> signal1 <level>
// steps are rising clock edges, positive when the direction pin is HIGH;
// dirchanges counts direction edges after the move's first step; rampend
// counts the leader's last steps in a row made with BOOST (pin 16, high
// while the engine is on a ramp) high: a move that ended on a ramp (a
// brake along it) ends with rampend > 0, one cut in its cruise with 0.
// Levels and counts only, no time: the trace's timestamps are host time.
// signal1 is pin 1 at the move's end.
void print_moves(const Trace &tr) {
  struct Move {
    long steps[kAxes] = {};
    long dir_changes = 0;
    bool stepped = false;
    long rises[kAxes] = {};
    long ramp_rises[kAxes] = {};  // the last rises in a row with BOOST high
  };
  int level[kNumPins];
  std::fill(level, level + kNumPins, -1);
  std::optional<Move> cur;
  int n = 0;
  auto emit = [&](const Move &m) {
    int lead = 0;
    for (int a = 1; a < kAxes; a++)
      if (m.rises[a] > m.rises[lead]) lead = a;
    std::cout << "MOVE " << ++n << " steps";
    for (long s : m.steps) std::cout << ' ' << s;
    std::cout << " dirchanges " << m.dir_changes << " rampend " << m.ramp_rises[lead] << " signal1 "
              << level_str(level[pin_index(1)], "?") << "\n";
  };
  for_each_change(tr, [&](const Change &c) {
    level[c.pin] = c.level;
    const int number = kPins[c.pin].number;
    if (number == 17) {
      if (c.level && !c.initial) cur = Move{};
      if (!c.level && cur) {
        emit(*cur);
        cur.reset();
      }
      return;
    }
    if (!cur || c.initial) return;
    for (int a = 0; a < kAxes; a++) {
      if (number == dir_pin(a) && cur->stepped) cur->dir_changes++;
      if (number == clk_pin(a) && c.level) {
        cur->steps[a] += level[pin_index(dir_pin(a))] ? 1 : -1;
        cur->rises[a]++;
        cur->ramp_rises[a] = level[pin_index(16)] == 1 ? cur->ramp_rises[a] + 1 : 0;
        cur->stepped = true;
      }
    }
  });
}

void print_summary_text(const std::string &path, const Trace &tr, const Summary &s) {
  std::cout << "trace: " << path << "\n"
            << "writes: " << tr.writes.size() << " (data " << s.data_writes << ", control "
            << s.control_writes << "), duration " << us(s.duration_ns) << " us"
            << (tr.timestamps ? "" : " (no timestamps)") << "\n"
            << "pin  name           rising  falling  final\n";
  for (int p = 0; p < kNumPins; p++) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "%3d  %-13s %7ld  %7ld  %s\n", kPins[p].number, kPins[p].name,
                  s.pins[p].rising, s.pins[p].falling, level_str(s.pins[p].final_level, "?").c_str());
    std::cout << buf;
  }
  for (int a = 0; a < kAxes; a++) {
    const AxisStats &ax = s.axes[a];
    std::cout << "axis " << a + 1 << " (clk pin " << clk_pin(a) << ", dir pin " << dir_pin(a)
              << "): " << ax.steps << " steps (dir high " << ax.steps_dir_high << ", dir low "
              << ax.steps_dir_low << ")\n";
    if (!ax.steps) continue;
    std::cout << "  first rise " << us(*ax.first_rise) << " us, last rise " << us(*ax.last_rise)
              << " us, min period " << opt_us(ax.min_period, "-") << " us, min high "
              << opt_us(ax.min_high, "-") << " us, min low " << opt_us(ax.min_low, "-") << " us\n"
              << "  dir at first step " << level_str(ax.dir_at_first_step, "?")
              << ", dir changes during move " << ax.dir_changes_during_move << ", min dir setup "
              << opt_us(ax.min_dir_setup, "-") << " us\n";
  }
}

void print_summary_json(const std::string &path, const Trace &tr, const Summary &s) {
  auto level = [](int l) { return l < 0 ? std::string("null") : std::to_string(l); };
  auto opt = [](const std::optional<int64_t> &v) { return v ? us(*v) : std::string("null"); };
  std::ostringstream o;
  o << "{\n  \"trace\": " << json_string(path) << ",\n"
    << "  \"writes\": " << tr.writes.size() << ",\n"
    << "  \"data_writes\": " << s.data_writes << ",\n"
    << "  \"control_writes\": " << s.control_writes << ",\n"
    << "  \"timestamps\": " << (tr.timestamps ? "true" : "false") << ",\n"
    << "  \"duration_us\": " << us(s.duration_ns) << ",\n"
    << "  \"pins\": [\n";
  for (int p = 0; p < kNumPins; p++)
    o << "    {\"pin\": " << kPins[p].number << ", \"name\": " << json_string(kPins[p].name)
      << ", \"rising\": " << s.pins[p].rising << ", \"falling\": " << s.pins[p].falling
      << ", \"final\": " << level(s.pins[p].final_level) << "}" << (p + 1 < kNumPins ? ",\n" : "\n");
  o << "  ],\n  \"axes\": [\n";
  for (int a = 0; a < kAxes; a++) {
    const AxisStats &ax = s.axes[a];
    o << "    {\"axis\": " << a + 1 << ", \"clk_pin\": " << clk_pin(a) << ", \"dir_pin\": " << dir_pin(a)
      << ", \"steps\": " << ax.steps << ", \"steps_dir_high\": " << ax.steps_dir_high
      << ", \"steps_dir_low\": " << ax.steps_dir_low << ",\n     \"first_rise_us\": " << opt(ax.first_rise)
      << ", \"last_rise_us\": " << opt(ax.last_rise) << ", \"min_period_us\": " << opt(ax.min_period)
      << ", \"min_high_us\": " << opt(ax.min_high) << ", \"min_low_us\": " << opt(ax.min_low)
      << ",\n     \"dir_at_first_step\": " << level(ax.dir_at_first_step)
      << ", \"dir_changes_during_move\": " << ax.dir_changes_during_move
      << ", \"min_dir_setup_us\": " << opt(ax.min_dir_setup) << "}" << (a + 1 < kAxes ? ",\n" : "\n");
  }
  o << "  ]\n}\n";
  std::cout << o.str();
}

// ---------------------------------------------------------------- VCD

void write_vcd(const std::string &path, const std::string &out_path, const Trace &tr) {
  std::ofstream out(out_path);
  if (!out) fail("cannot write " + out_path + ": " + std::strerror(errno));
  out << "$comment x4trace " << path
      << ": QEMU host timestamps since the first port write; writes with equal\n"
         "  timestamps are spread 1 ns apart so that short pulses stay visible $end\n"
      << "$version x4trace $end\n$timescale 1ns $end\n$scope module lpt $end\n";
  for (int p = 0; p < kNumPins; p++)
    out << "$var wire 1 " << static_cast<char>('!' + p) << " " << kPins[p].name << " $end\n";
  out << "$upscope $end\n$enddefinitions $end\n#0\n$dumpvars\n";
  for (int p = 0; p < kNumPins; p++) out << "x" << static_cast<char>('!' + p) << "\n";
  out << "$end\n";
  int64_t last_t = 0;  // "#0" is open: the first write's values go there
  std::optional<size_t> last_seq;
  for_each_change(tr, [&](const Change &c) {
    if (!last_seq || c.seq != *last_seq) {
      int64_t t = last_seq ? std::max(c.t_ns, last_t + 1) : c.t_ns;
      if (t != 0) out << "#" << t << "\n";
      last_t = t;
      last_seq = c.seq;
    }
    out << c.level << static_cast<char>('!' + c.pin) << "\n";
  });
  if (!tr.writes.empty()) out << "#" << std::max(tr.writes.back().t_ns, last_t) + 1000 << "\n";
  out.close();
  if (!out) fail("error writing " + out_path);
}

// ---------------------------------------------------------------- SVG

// A "nice" tick step (1, 2 or 5 times a power of ten) for about N ticks.
double nice_step(double range, int n) {
  if (!(range > 0)) return 1;
  double raw = range / n, mag = std::pow(10.0, std::floor(std::log10(raw)));
  double f = raw / mag;
  return (f <= 1 ? 1 : f <= 2 ? 2 : f <= 5 ? 5 : 10) * mag;
}

std::string fmt_tick(double v, double step) {
  int dec = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", dec, std::fabs(v) < step * 1e-6 ? 0.0 : v);
  return buf;
}

std::string fmt_num(double v, int prec = 4, char conv = 'g') {
  char buf[64];
  std::snprintf(buf, sizeof buf, conv == 'f' ? "%.*f" : "%.*g", prec, v);
  return buf;
}

std::string xml_escape(const std::string &s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

// Bins of about span/150, widened (1-2-5 steps) until the busiest bin holds at
// least 20 steps, so that counting does not alias into a +-1 step ripple.
double auto_bin_ms(const std::vector<int64_t> rises[kAxes], int64_t span_ns) {
  double bin = std::max(nice_step(span_ns / 1e6, 150), 0.001);
  for (;;) {
    int64_t bin_ns = std::max<int64_t>(std::llround(bin * 1e6), 1);
    long busiest = 0;
    for (int a = 0; a < kAxes; a++) {
      std::vector<long> count(static_cast<size_t>(span_ns / bin_ns + 2), 0);
      for (int64_t t : rises[a]) {
        long &c = count[static_cast<size_t>((t - rises[a].front()) / bin_ns)];
        busiest = std::max(busiest, ++c);
      }
    }
    if (busiest >= 20 || span_ns / bin_ns < 30) return bin;
    bin = nice_step(bin * 1.5, 1);
  }
}

// bin_ms > 0: steps counted per bin; bin_ms == 0: 1/interval of successive steps;
// bin_ms < 0: bin chosen by auto_bin_ms().
void write_svg(const std::string &path, const std::string &out_path, const Trace &tr, double bin_ms) {
  std::vector<int64_t> rises[kAxes];
  for_each_change(tr, [&](const Change &c) {
    for (int a = 0; a < kAxes; a++)
      if (!c.initial && c.level && kPins[c.pin].number == clk_pin(a)) rises[a].push_back(c.t_ns);
  });

  int64_t t_first = std::numeric_limits<int64_t>::max(), t_last = 0;
  for (auto &r : rises)
    if (!r.empty()) {
      t_first = std::min(t_first, r.front());
      t_last = std::max(t_last, r.back());
    }
  bool any = t_first <= t_last;
  if (!any) t_first = t_last = 0;
  int64_t span = std::max<int64_t>(t_last - t_first, 1000);

  if (bin_ms < 0) bin_ms = auto_bin_ms(rises, span);
  int64_t bin_ns = static_cast<int64_t>(std::llround(bin_ms * 1e6));
  if (bin_ms > 0 && bin_ns < 1) usage_error("--bin-ms too small");

  // Series: (t_ns, steps/s) points per axis.
  std::vector<std::pair<double, double>> series[kAxes];
  double y_max = 0;
  int64_t x_lo = t_first, x_hi = t_last;
  if (bin_ns > 0) {
    x_lo = t_first / bin_ns * bin_ns;
    x_hi = (t_last / bin_ns + 1) * bin_ns;
    size_t nbins = static_cast<size_t>((x_hi - x_lo) / bin_ns);
    if (nbins > 200000) usage_error("--bin-ms gives too many bins (" + std::to_string(nbins) + ")");
    for (int a = 0; a < kAxes; a++) {
      if (rises[a].empty()) continue;
      std::vector<long> count(nbins, 0);
      for (int64_t t : rises[a]) count[static_cast<size_t>((t - x_lo) / bin_ns)]++;
      for (size_t b = 0; b < nbins; b++) {
        double rate = count[b] / (bin_ns / 1e9);
        double t0 = static_cast<double>(x_lo + static_cast<int64_t>(b) * bin_ns);
        series[a].push_back({t0, rate});
        series[a].push_back({t0 + bin_ns, rate});
        y_max = std::max(y_max, rate);
      }
    }
  } else {
    for (int a = 0; a < kAxes; a++)
      for (size_t i = 1; i < rises[a].size(); i++) {
        int64_t dt = rises[a][i] - rises[a][i - 1];
        if (dt <= 0) continue;  // equal host timestamps: no rate
        double rate = 1e9 / dt;
        series[a].push_back({static_cast<double>(rises[a][i]), rate});
        y_max = std::max(y_max, rate);
      }
    x_hi = std::max(x_hi, x_lo + 1000);
  }
  if (y_max <= 0) y_max = 1;

  // Layout.
  const double W = 960, H = 540, L = 90, R = 230, T = 60, B = 60;
  const double pw = W - L - R, ph = H - T - B;
  bool in_s = (x_hi - x_lo) > 5e9;
  double unit = in_s ? 1e9 : 1e6;  // ns per displayed unit
  double xu_lo = x_lo / unit, xu_hi = x_hi / unit;
  double xstep = nice_step(xu_hi - xu_lo, 8);
  double ystep = nice_step(y_max, 5);
  double y_top = std::ceil(y_max * 1.04 / ystep) * ystep;
  auto X = [&](double t_ns) { return L + (t_ns / unit - xu_lo) / (xu_hi - xu_lo) * pw; };
  auto Y = [&](double rate) { return T + ph - rate / y_top * ph; };

  std::ofstream out(out_path);
  if (!out) fail("cannot write " + out_path + ": " + std::strerror(errno));
  static const char *const kColor[kAxes] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd"};
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
      << "\" viewBox=\"0 0 " << W << " " << H << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << "<text x=\"" << L << "\" y=\"24\" font-size=\"16\" font-weight=\"bold\">"
      << "Step rate per axis (from the parallel port trace)</text>\n"
      << "<text x=\"" << L << "\" y=\"42\" fill=\"#555\">" << xml_escape(path) << " \u2014 "
      << (bin_ns > 0 ? "steps counted in " + fmt_num(bin_ms) + " ms bins"
                     : std::string("1 / interval between successive steps"))
      << "; QEMU host timestamps" << (tr.timestamps ? "" : " (missing!)") << "</text>\n";

  // Grid, ticks and labels.
  out << "<g stroke=\"#e0e0e0\" stroke-width=\"1\">\n";
  double xt0 = std::ceil(xu_lo / xstep - 1e-9) * xstep;
  for (double v = xt0; v <= xu_hi + xstep * 1e-6; v += xstep)
    out << "<line x1=\"" << X(v * unit) << "\" y1=\"" << T << "\" x2=\"" << X(v * unit) << "\" y2=\""
        << T + ph << "\"/>\n";
  for (double v = 0; v <= y_top + ystep * 1e-6; v += ystep)
    out << "<line x1=\"" << L << "\" y1=\"" << Y(v) << "\" x2=\"" << L + pw << "\" y2=\"" << Y(v) << "\"/>\n";
  out << "</g>\n<g fill=\"#333\">\n";
  for (double v = xt0; v <= xu_hi + xstep * 1e-6; v += xstep)
    out << "<text x=\"" << X(v * unit) << "\" y=\"" << T + ph + 18 << "\" text-anchor=\"middle\">"
        << fmt_tick(v, xstep) << "</text>\n";
  for (double v = 0; v <= y_top + ystep * 1e-6; v += ystep)
    out << "<text x=\"" << L - 8 << "\" y=\"" << Y(v) + 4 << "\" text-anchor=\"end\">" << fmt_tick(v, ystep)
        << "</text>\n";
  out << "<text x=\"" << L + pw / 2 << "\" y=\"" << H - 14 << "\" text-anchor=\"middle\">"
      << "time since the first port write [" << (in_s ? "s" : "ms") << "]</text>\n"
      << "<text transform=\"translate(22 " << T + ph / 2
      << ") rotate(-90)\" text-anchor=\"middle\">step rate [steps/s]</text>\n</g>\n"
      << "<rect x=\"" << L << "\" y=\"" << T << "\" width=\"" << pw << "\" height=\"" << ph
      << "\" fill=\"none\" stroke=\"#333\"/>\n";

  // One polyline per axis, then the legend.
  for (int a = 0; a < kAxes; a++) {
    if (series[a].empty()) continue;
    out << "<polyline fill=\"none\" stroke=\"" << kColor[a]
        << "\" stroke-width=\"1.5\" stroke-linejoin=\"round\" points=\"";
    for (auto &pt : series[a]) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "%.2f,%.2f ", X(pt.first), Y(pt.second));
      out << buf;
    }
    out << "\"/>\n";
  }
  double lx = L + pw + 20, ly = T + 10;
  out << "<text x=\"" << lx << "\" y=\"" << ly << "\" font-weight=\"bold\">Axis (clock pin)</text>\n";
  for (int a = 0; a < kAxes; a++) {
    double y = ly + 24 + a * 38;
    double peak = 0;
    for (auto &pt : series[a]) peak = std::max(peak, pt.second);
    out << "<line x1=\"" << lx << "\" y1=\"" << y - 4 << "\" x2=\"" << lx + 24 << "\" y2=\"" << y - 4
        << "\" stroke=\"" << kColor[a] << "\" stroke-width=\"3\"/>\n"
        << "<text x=\"" << lx + 30 << "\" y=\"" << y << "\">axis " << a + 1 << " (pin " << clk_pin(a)
        << "): " << rises[a].size() << " steps</text>\n"
        << "<text x=\"" << lx + 30 << "\" y=\"" << y + 15 << "\" fill=\"#555\">"
        << (rises[a].empty() ? std::string("no steps")
                             : "peak " + fmt_num(peak, peak < 10 ? 2 : 0, 'f') + " steps/s")
        << "</text>\n";
  }
  if (!any)
    out << "<text x=\"" << L + pw / 2 << "\" y=\"" << T + ph / 2
        << "\" text-anchor=\"middle\" font-size=\"16\">no steps in this trace</text>\n";
  out << "</svg>\n";
  out.close();
  if (!out) fail("error writing " + out_path);
}

// ---------------------------------------------------------------- compare

// Each pin's edges, in order, with the move they fall in: a move begins
// with a write that raises AKTIV (pin 17) and ends with the one that drops
// it. Edges of a move are timed from its beginning; edges between moves
// (outputs, rest patterns) only count and keep their order; edges before
// the first move (the port's setup) are not compared.
struct PinEdge {
  int move;
  bool timed;
  int64_t rel_ns;
  int level;
};

int pin_edges(const Trace &tr, std::vector<PinEdge> (&out)[kNumPins]) {
  std::vector<Change> ch;
  for_each_change(tr, [&](const Change &c) { ch.push_back(c); });
  const int aktiv = pin_index(17);
  int move = 0;
  bool high = false;
  int64_t start = 0;
  for (size_t i = 0; i < ch.size();) {
    size_t j = i;
    bool rise = false, fall = false;
    for (; j < ch.size() && ch[j].seq == ch[i].seq; j++)
      if (ch[j].pin == aktiv && !ch[j].initial) (ch[j].level ? rise : fall) = true;
    if (rise) {
      move++;
      start = ch[i].t_ns;
    }
    high = rise || (high && !fall);
    const bool timed = high || fall;
    for (; i < j; i++)
      if (!ch[i].initial && move > 0)
        out[ch[i].pin].push_back({move, timed, ch[i].t_ns - start, ch[i].level});
  }
  return move;
}

// The same edges? Counts and order per pin exactly; the times of a move's
// edges the same after aligning the move: TRACE1 (the module) is late by
// its timer's latency, so its median lateness in the move is taken off
// (it must lie in 0..late_ns: never early). Then every edge lies within
// `max_ns`, and all but `permille` per mille of them within `within_ns`
// (a timer interrupt now and then is late). 0 if so, else 1 with `DIFF`.
int compare(const std::string &p1, const std::string &p2, int64_t within_ns, int64_t max_ns, int64_t late_ns,
            long permille) {
  std::vector<PinEdge> a[kNumPins], b[kNumPins];
  const int ma = pin_edges(read_trace(p1), a), mb = pin_edges(read_trace(p2), b);
  long edges = 0, timed = 0, bad = 0, over = 0;
  auto report = [&](const std::string &msg) {
    if (++bad <= 20) std::cout << "DIFF " << msg << "\n";
  };
  if (ma != mb)
    report("moves: " + std::to_string(ma) + " in " + p1 + ", " + std::to_string(mb) + " in " + p2);
  // Counts, order, and each move's differences.
  std::vector<std::vector<int64_t>> diff(static_cast<size_t>(ma) + 1);
  size_t same[kNumPins];
  for (int p = 0; p < kNumPins; p++) {
    const std::string pin = "pin " + std::to_string(kPins[p].number);
    if (a[p].size() != b[p].size())
      report(pin + ": " + std::to_string(a[p].size()) + " edges in " + p1 + ", " +
             std::to_string(b[p].size()) + " in " + p2);
    for (same[p] = 0; same[p] < std::min(a[p].size(), b[p].size()); same[p]++) {
      const PinEdge &x = a[p][same[p]], &y = b[p][same[p]];
      if (x.move != y.move || x.level != y.level || x.timed != y.timed) {
        report(pin + " edge " + std::to_string(same[p] + 1) + ": level " + std::to_string(x.level) +
               " in move " + std::to_string(x.move) + " vs level " + std::to_string(y.level) + " in move " +
               std::to_string(y.move));
        break;  // the rest of this pin is out of step
      }
      edges++;
      if (x.timed) diff[static_cast<size_t>(x.move)].push_back(x.rel_ns - y.rel_ns);
    }
  }
  std::vector<int64_t> late(diff.size(), 0), worst(diff.size(), 0);
  for (size_t m = 1; m < diff.size(); m++) {
    std::vector<int64_t> v = diff[m];
    if (v.empty()) continue;
    std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
    late[m] = v[v.size() / 2];
    if (late[m] < 0 || late[m] > late_ns)
      report("move " + std::to_string(m) + ": " + p1 + " is " + us(late[m]) + " us late in the median");
  }
  for (int p = 0; p < kNumPins; p++)
    for (size_t i = 0; i < same[p]; i++) {
      const PinEdge &x = a[p][i], &y = b[p][i];
      if (!x.timed) continue;
      timed++;
      const int64_t d = std::llabs(x.rel_ns - y.rel_ns - late[static_cast<size_t>(x.move)]);
      worst[static_cast<size_t>(x.move)] = std::max(worst[static_cast<size_t>(x.move)], d);
      over += d > within_ns;
      if (d > max_ns)
        report("pin " + std::to_string(kPins[p].number) + " edge " + std::to_string(i + 1) + " (move " +
               std::to_string(x.move) + "): at " + us(x.rel_ns) + " us vs " + us(y.rel_ns) +
               " us into the move, " + us(late[static_cast<size_t>(x.move)]) + " us late in the median");
    }
  if (over * 1000 > timed * permille)
    report(std::to_string(over) + " of " + std::to_string(timed) + " timed edges are more than " +
           us(within_ns) + " us off: more than " + std::to_string(permille) + " per mille");
  std::cout << "per move: median lateness of " << p1 << " / largest difference after it (us):";
  for (size_t m = 1; m < diff.size(); m++) std::cout << ' ' << us(late[m]) << '/' << us(worst[m]);
  std::cout << "\ncompare: " << ma << " moves, " << edges << " edges in the same order, " << timed
            << " timed: " << over << " more than " << us(within_ns) << " us off (allowed " << permille
            << " per mille), none over " << us(max_ns) << " us allowed: " << (bad ? "DIFFERENT" : "same")
            << "\n";
  return bad ? 1 : 0;
}

}  // namespace

int main(int argc, char **argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (args.empty() || args[0] == "-h" || args[0] == "--help") {
    std::cerr << kUsage;
    return args.empty() ? 2 : 0;
  }
  const std::string mode = args[0];
  if (args.size() < 2) usage_error("missing TRACE");
  const std::string path = args[1];

  if (mode == "edges") {
    if (args.size() != 2) usage_error("edges takes just TRACE");
    Trace tr = read_trace(path);
    std::string buf;
    for_each_change(tr, [&](const Change &c) {
      if (c.initial) return;
      buf += us(c.t_ns) + " " + std::to_string(kPins[c.pin].number) + " " + std::to_string(c.level) + "\n";
      if (buf.size() > 65536) {
        std::cout << buf;
        buf.clear();
      }
    });
    std::cout << buf;
  } else if (mode == "summary") {
    bool json = false;
    for (size_t i = 2; i < args.size(); i++) {
      if (args[i] == "--json")
        json = true;
      else
        usage_error("unknown option " + args[i]);
    }
    Trace tr = read_trace(path);
    Summary s = summarize(tr);
    if (json)
      print_summary_json(path, tr, s);
    else
      print_summary_text(path, tr, s);
  } else if (mode == "vcd") {
    if (args.size() != 3) usage_error("vcd takes TRACE OUT.vcd");
    Trace tr = read_trace(path);
    write_vcd(path, args[2], tr);
  } else if (mode == "svg") {
    if (args.size() != 3 && !(args.size() == 5 && args[3] == "--bin-ms"))
      usage_error("svg takes TRACE OUT.svg [--bin-ms N]");
    double bin_ms = -1;
    if (args.size() == 5) {
      char *end;
      bin_ms = std::strtod(args[4].c_str(), &end);
      if (*end || end == args[4].c_str() || !(bin_ms >= 0) || std::isinf(bin_ms))
        usage_error("--bin-ms needs a number >= 0 (0: per-step rate)");
    }
    Trace tr = read_trace(path);
    write_svg(path, args[2], tr, bin_ms);
  } else if (mode == "compare") {
    if (args.size() < 3 || args.size() % 2 == 0)
      usage_error("compare takes TRACE1 TRACE2 [--within-ns N] [--max-ns N] [--late-ns N] [--permille N]");
    // within, max and late (default: within), permille
    long long opt[4] = {1000, -1, -1, 0};
    const char *const names[4] = {"--within-ns", "--max-ns", "--late-ns", "--permille"};
    for (size_t i = 3; i < args.size(); i += 2) {
      char *end;
      const long long v = std::strtoll(args[i + 1].c_str(), &end, 10);
      if (*end || end == args[i + 1].c_str() || v < 0) usage_error(args[i] + " needs a number >= 0");
      int k = 0;
      while (k < 4 && args[i] != names[k]) k++;
      if (k == 4) usage_error("unknown option " + args[i]);
      opt[k] = v;
    }
    std::cout.flush();
    return compare(path, args[2], opt[0], opt[1] < 0 ? opt[0] : opt[1], opt[2] < 0 ? opt[0] : opt[2],
                   static_cast<long>(opt[3]));
  } else if (mode == "moves") {
    if (args.size() != 2) usage_error("moves takes just TRACE");
    print_moves(read_trace(path));
  } else {
    usage_error("unknown mode '" + mode + "'");
  }
  std::cout.flush();
  if (!std::cout) fail("error writing standard output");
  return 0;
}
