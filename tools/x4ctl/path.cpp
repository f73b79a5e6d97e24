// SPDX-License-Identifier: GPL-2.0
// x4ctl path: read a path of straight segments in steps, check all of it,
// then stream it to the module's path queue and show the progress.
#include "path.hpp"

#include <poll.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>

#include "commands.hpp"
#include "json.hpp"
#include "path_stream.hpp"
#include "show.hpp"
#include "term.hpp"

namespace x4ctl {

namespace {

constexpr long steps_max = 16777216;
constexpr double units_max = 2147483647;

// A token of a line and its column (1-based).
struct token {
  std::string text;
  int column;
};

std::vector<token> tokens_of(const std::string &line) {
  std::vector<token> out;
  size_t i = 0;
  while (i < line.size() && line[i] != '#') {
    if (std::isspace(static_cast<unsigned char>(line[i]))) {
      i++;
      continue;
    }
    const size_t start = i;
    while (i < line.size() && line[i] != '#' && !std::isspace(static_cast<unsigned char>(line[i]))) i++;
    out.push_back({line.substr(start, i - start), static_cast<int>(start) + 1});
  }
  return out;
}

// A whole decimal number in [min, max], or nothing.
bool number_in(const std::string &text, long min, long max, long &out) {
  char *end = nullptr;
  errno = 0;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end || errno || v < min || v > max) return false;
  out = v;
  return true;
}

class line_reader {
 public:
  line_reader(const std::string &name, int number) : where_(name + ":" + std::to_string(number) + ":") {}
  [[noreturn]] void fail(const token &t, const std::string &what) const {
    throw usage_error(where_ + std::to_string(t.column) + ": " + what);
  }

 private:
  std::string where_;
};

}  // namespace

std::vector<x4step::segment> read_path(std::istream &in, const std::string &name, const path_defaults &d) {
  std::vector<x4step::segment> out;
  std::array<double, x4step::axes> prev{};  // the last segment's direction
  std::string text;
  for (int n = 1; std::getline(in, text); n++) {
    const std::vector<token> toks = tokens_of(text);
    if (toks.empty()) continue;
    const line_reader r(name, n);
    std::array<long, x4step::axes> steps{};
    size_t i = 0;
    for (; i < toks.size() && toks[i].text.find('=') == std::string::npos; i++) {
      if (i == x4step::axes)
        r.fail(toks[i], "more than 4 axes: a line is up to 4 step counts, then key=value");
      if (!number_in(toks[i].text, -steps_max, steps_max, steps[i]))
        r.fail(toks[i], "'" + toks[i].text + "' is no step count: use a whole number within +-16777216");
    }
    unsigned speed = d.speed, accel = d.accel;
    long corner = -1;
    for (; i < toks.size(); i++) {
      const token &t = toks[i];
      const size_t eq = t.text.find('=');
      if (eq == std::string::npos) r.fail(t, "'" + t.text + "': step counts come first, then key=value");
      const std::string key = t.text.substr(0, eq), value = t.text.substr(eq + 1);
      long v = 0;
      if (key == "speed") {
        if (!number_in(value, 1, x4step::vel_max, v))
          r.fail(t, "speed '" + value + "': use 1..100000 steps/s");
        speed = static_cast<unsigned>(v);
      } else if (key == "accel") {
        if (!number_in(value, 1, x4step::acc_max, v))
          r.fail(t, "accel '" + value + "': use 1..1000000 steps/s^2");
        accel = static_cast<unsigned>(v);
      } else if (key == "corner") {
        if (!number_in(value, 0, x4step::vel_max, v))
          r.fail(t, "corner '" + value + "': use 0..100000 steps/s");
        corner = v;
      } else {
        r.fail(t, "unknown key '" + key + "': use speed=, accel= or corner=");
      }
    }
    std::array<double, x4step::axes> dir{};
    double len2 = 0;
    for (int a = 0; a < x4step::axes; a++) {
      dir[a] = static_cast<double>(steps[a]);
      len2 += dir[a] * dir[a];
    }
    if (len2 == 0) r.fail(toks[0], "no steps: give at least one axis a non-zero count");
    const double units = std::round(std::sqrt(len2) * path_units_per_step);
    if (units > units_max)
      r.fail(toks[0], "segment too long: split it (at most 2147483 steps along the path)");
    if (speed > 1800.0 * accel)
      r.fail(toks[0], "speed / accel above 1800 s: accelerate faster or move slower");
    const double a_units = double(accel) * path_units_per_step;
    std::uint32_t entry = 0;
    if (corner >= 0)
      entry = static_cast<std::uint32_t>(corner * path_units_per_step);
    else if (!out.empty())
      entry = x4step::junction_speed(prev, dir, a_units, d.deviation * path_units_per_step);
    x4step::segment s;
    for (x4step::axis a : x4step::axis_set::all()) s.steps(a, steps[a.index()]);
    out.push_back(s.length(static_cast<std::uint32_t>(units))
                      .top_speed(speed * path_units_per_step)
                      .accel(static_cast<std::uint32_t>(std::min(a_units, units_max)))
                      .entry_speed(std::min<std::uint32_t>(entry, speed * path_units_per_step))
                      .tag(static_cast<std::uint64_t>(n)));
    prev = dir;
  }
  return out;
}

namespace {

std::vector<x4step::segment> read_path_file(const config &c) {
  const std::string name = c.file == "-" ? "stdin" : c.file;
  if (c.file == "-") return read_path(std::cin, name, c.path);
  std::ifstream f(c.file);
  if (!f) throw failure("cannot read " + c.file + ": " + std::strerror(errno), errno);
  return read_path(f, name, c.path);
}

std::string state_name(x4step::path_state s) {
  std::ostringstream o;
  o << s;  // idle, running, holding, held
  return o.str();
}

// One progress record: text (redrawn on a terminal) or a JSON line.
std::string progress(const x4step::path_status &s, std::uint64_t done, size_t total, bool json) {
  const double speed = double(s.speed) / path_units_per_step;
  if (json)
    return json_document()
        .add("state", state_name(s.state))
        .add("line", s.tag)
        .add("done", done)
        .add("total", total)
        .add("speed", speed)
        .add("queued", s.queued)
        .add("override", s.override_percent)
        .add("starved", s.starved)
        .str();
  std::ostringstream o;
  o << "path: " << state_name(s.state) << ", segment " << done << "/" << total;
  if (s.tag) o << ", line " << s.tag;
  o << ", " << static_cast<long>(speed + 0.5) << " steps/s, queue " << s.queued << "/" << s.depth;
  if (s.starved) o << ", starved " << s.starved;
  return o.str();
}

}  // namespace

int cmd_path(const config &c) {
  const std::vector<x4step::segment> segs = read_path_file(c);
  double steps = 0;
  for (const auto &s : segs) steps += double(s.length()) / path_units_per_step;
  if (c.check) {
    std::cout << (c.file == "-" ? "stdin" : c.file) << ": " << segs.size() << " segments, "
              << static_cast<long>(steps + 0.5) << " steps along the path: OK\n";
    return 0;
  }
  x4step::controller ctl = open_controller(device_of(c));
  // What the port's step timing allows, for every line before the first step.
  const int fmax = max_freq_hz(ctl.get_step_timing(), ctl.get_config().mode(), x4step::vel_max);
  for (const auto &s : segs) {
    long leader = 0;
    for (x4step::axis a : x4step::axis_set::all()) leader = std::max(leader, std::labs(s.steps(a)));
    const double rate = double(s.top_speed()) * double(leader) / s.length();
    if (rate > fmax)
      throw failure((c.file == "-" ? std::string("stdin") : c.file) + ":" + std::to_string(s.tag()) +
                    ": its leader axis would step at " + std::to_string(long(rate)) +
                    " steps/s; the port's step timing allows " + std::to_string(fmax) + ": lower its speed");
  }
  path_stream ps(ctl, c.override_percent, c.json, false,
                 [&](const x4step::path_status &s, std::uint64_t done, bool json, size_t) {
                   return progress(s, done, segs.size(), json);
                 });
  for (const auto &s : segs)
    if (!ps.push(s)) break;
  ps.drain();
  ps.finish();
  const x4step::axes_status a = ctl.get_axes();
  if (!c.json) {
    std::cout << "path: " << (ps.aborted() ? "aborted" : "done") << ", " << ps.done() << " of " << segs.size()
              << " segments, at";
    for (x4step::axis ax : x4step::axis_set::all()) std::cout << " " << a[ax].position;
    std::cout << "\n";
  }
  return ps.aborted() ? 1 : 0;
}

}  // namespace x4ctl
