// SPDX-License-Identifier: GPL-2.0
// x4ctl gcode: the program is planned twice: once whole, into a counter,
// so that a bad line or a soft limit stops it before the first step; then
// into the path queue while it runs.
#include "gcode_cmd.hpp"

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <utility>

#include "commands.hpp"
#include "json.hpp"
#include "machine_io.hpp"
#include "path_stream.hpp"
#include "planner.hpp"
#include "run_display.hpp"
#include "show.hpp"
#include "sim.hpp"
#include "toolpath_svg.hpp"

namespace x4ctl {

namespace {

// Plans the whole program into out; a refused line is a usage error.
m::plan_summary plan(const m::machine &mc, const program &p, const g::pose &start, m::planner_output &out,
                     const g::coordinate_state &coords, g::coordinate_state *coords_after = nullptr) {
  std::istringstream in(p.text);
  try {
    return m::plan_program(mc, in, p.name, out, start, coords, coords_after);
  } catch (const g::error &e) {
    throw usage_error(p.prefix() + e.what());
  }
}

// The program's text alone, before the port is opened.
void check_text(const m::machine &mc, const program &p) {
  std::istringstream in(p.text);
  try {
    m::check_program(mc, in, p.name);
  } catch (const g::error &e) {
    throw usage_error(p.prefix() + e.what());
  }
}

// The check pass: counts what the run will need.
struct counter : m::planner_output {
  long pauses = 0;                // M0, M1, M6: an operator at a terminal
  toolpath_plot *plot = nullptr;  // --check --svg: the planned path
  void segment(const x4step::segment &, const m::segment_info &i) override {
    if (plot) plot->planned(i);
  }
  void pause(bool, int) override { pauses++; }
  // Once per command: the check pass sees every line once.
  void warning(const g::error &w) override { std::cerr << w.what() << "\n"; }
};

void print_summary(const m::machine &mc, const config &c, const program &p, const m::plan_summary &s,
                   long pauses) {
  if (c.json) {
    // Extents as [min, max] per axis: work and machine coordinates.
    auto extents_of = [&](const g::pose &lo, const g::pose &hi) {
      std::string extents = "{";
      for (size_t a = 0; a < g::n_axes; a++) {
        if (!mc.axes[a] || !s.moved) continue;
        char buf[80];
        std::snprintf(buf, sizeof buf, "\"%c\":[%.10g,%.10g]", axis_letters[a], lo[a], hi[a]);
        extents += (extents.size() > 1 ? "," : "") + std::string(buf);
      }
      return extents + "}";
    };
    std::cout << json_document()
                     .add("file", p.name)
                     .add("machine", machine_path(c))
                     .add("units", units_name(mc))
                     .add("lines", s.lines)
                     .add("segments", s.segments)
                     .add("length", s.length)
                     .add("seconds", s.seconds)
                     .add("pauses", pauses)
                     .raw("extents", extents_of(s.work_min, s.work_max))
                     .raw("machine_extents", extents_of(s.min, s.max))
                     .str()
              << "\n";
    return;
  }
  std::cout << p.name << ": OK: " << s.lines << " lines, " << s.segments << " segments, " << number(s.length)
            << " " << units_name(mc) << " along the path, about " << clock_text(s.seconds)
            << " at the top speeds (ramps not counted)";
  if (pauses) std::cout << ", " << pauses << " pauses for the operator";
  std::cout << "\n";
  if (!s.moved) return;
  auto extents = [&](const g::pose &lo, const g::pose &hi) {
    for (size_t a = 0; a < g::n_axes; a++)
      if (mc.axes[a]) std::cout << " " << axis_letters[a] << " " << number(lo[a]) << ".." << number(hi[a]);
  };
  std::cout << "extents (" << units_name(mc) << ", work coordinates):";
  extents(s.work_min, s.work_max);
  std::cout << "; machine:";
  extents(s.min, s.max);
  std::cout << "\n";
}

struct run_aborted {};

// The run pass: segments into the queue; dwells, pauses and outputs with the path at rest.
class runner : public m::planner_output {
 public:
  runner(const m::machine &mc, x4step::controller &ctl, path_stream &ps, progress_meter &meter, bool json,
         bool no_pause)
      : mc_(mc), ctl_(ctl), ps_(ps), meter_(meter), json_(json), no_pause_(no_pause) {}

  void segment(const x4step::segment &s, const m::segment_info &i) override {
    if (plot) plot->planned(i);
    meter_.queued(i);
    if (!ps_.push(s)) throw run_aborted{};
  }
  void dwell(double seconds) override {
    rest();
    if (!ps_.wait_for(std::chrono::milliseconds(std::lround(seconds * 1000)))) throw run_aborted{};
    meter_.dwelled(seconds);
  }
  void pause(bool optional, int tool) override {
    rest();
    const std::string what = tool >= 0  ? "M6: change to tool " + std::to_string(tool)
                             : optional ? "M1"
                                        : "M0";
    if (no_pause_) {
      say(what + ": not waited for (--no-pause)");
      return;
    }
    say(tool >= 0 ? what + ", then press space (ESC aborts)" : what + ": paused; space goes on, ESC aborts");
    if (!ps_.wait_for_operator()) throw run_aborted{};
  }
  // G38.x: from rest, to where the probe input trips (or the move's end).
  m::probe_result probe(const x4step::segment &s, const m::segment_info &i, g::probe_kind k) override {
    rest();
    if (plot) plot->planned(i);
    meter_.queued(i);
    x4step::segment p = s;
    p.probe(k == g::probe_kind::toward_or_error || k == g::probe_kind::toward ? x4step::probe_mode::toward
                                                                              : x4step::probe_mode::away);
    const std::optional<x4step::probe_latch> l = ps_.probe(p);
    if (!l) throw run_aborted{};
    m::probe_result r;
    r.ran = true;
    r.tripped = l->tripped;
    const x4step::axes_status at = ctl_.get_axes();
    for (x4step::axis a : x4step::axis_set::all()) {
      r.stop[size_t(a.index())] = at[a].position;
      r.trip[size_t(a.index())] = l->tripped ? l->steps[size_t(a.index())] : at[a].position;
    }
    if (l->tripped) say("probe: tripped at" + where_text(r.trip));
    return r;
  }
  void spindle(bool on) override { set(mc_.spindle, on); }
  void coolant(bool mist, bool flood) override {
    set(mc_.mist, mist);
    set(mc_.flood, flood);
  }
  void message(std::string_view text) override { say("MSG: " + std::string(text)); }
  // (MSG,...) and (DEBUG,...) when the path reaches their line, not when
  // it is planned (up to a queue's length earlier).
  void message_at(std::string_view text, const m::message_info &i) override { messages_.add(text, i); }
  void show_due_messages() { messages_.due(ps_.done(), show_message()); }
  // A run that went to its end shows what is left; an aborted one drops it.
  void end_messages(bool aborted) {
    if (aborted)
      messages_.clear();
    else
      messages_.due(UINT64_MAX, show_message());
  }

  /// Switches off every output the program switched on.
  void outputs_off() {
    for (m::pin p : {mc_.spindle, mc_.mist, mc_.flood}) set_pin(p, false);
  }

 private:
  void rest() {
    if (!ps_.drain()) throw run_aborted{};
    show_due_messages();
  }
  m::message_queue::show_fn show_message() {
    return [this](const std::string &text, const m::message_info &i) {
      say((i.debug ? "DEBUG: " : "MSG: ") + text);
    };
  }
  void set(m::pin p, bool on) {
    if (p == m::pin::none) return;
    rest();
    set_pin(p, on);
  }
  void set_pin(m::pin p, bool on) {
    if (p != m::pin::none) ctl_.set_output(p == m::pin::pin1 ? x4step::signal::one : x4step::signal::two, on);
  }
  // " X1 Z-2.5 (mm)": motor steps in the machine's units.
  std::string where_text(const std::array<long, x4step::axes> &steps) const {
    const g::pose p = pose_of(mc_, steps);
    std::string t;
    for (size_t a = 0; a < g::n_axes; a++)
      if (mc_.axes[a]) t += " " + std::string(1, axis_letters[a]) + number(p[a]);
    return t + " (" + units_name(mc_) + ")";
  }
  // With JSON the time too, on the progress records' clock.
  void say(const std::string &text) {
    ps_.say(json_ ? json_document().add("message", text).add("elapsed", meter_.elapsed()).str() : text);
  }

  const m::machine &mc_;
  x4step::controller &ctl_;
  path_stream &ps_;
  progress_meter &meter_;
  bool json_;
  bool no_pause_;
  m::message_queue messages_;

 public:
  toolpath_plot *plot = nullptr;  // --svg
};

// gcode and mdi: check, plan from where the machine stands, run.
int run_program(const config &c, const program &prog) {
  const m::machine mc = load_machine(c, prog.command());
  counter n;
  toolpath_plot plot;
  // A plot that cannot be written fails before anything moves.
  if (!c.svg.empty() && !std::ofstream(c.svg))
    throw failure("--svg " + c.svg + ": cannot write: " + std::strerror(errno), errno);
  if (c.check) {
    // The offsets the parameter file keeps.
    const g::coordinate_state coords = load_coordinates(mc, prog.command());
    if (!c.svg.empty()) n.plot = &plot;
    print_summary(mc, c, prog, plan(mc, prog, g::pose{}, n, coords), n.pauses);
    n.plot = nullptr;
    if (!c.svg.empty()) plot.write(c.svg, units_name(mc), prog.name + " (planned, as from machine zero)");
    return 0;
  }
  check_text(mc, prog);
  controller_port port(open_controller(machine_device(c, mc)));
  x4step::controller &ctl = port.controller();
  const program_check k = check_at_machine(c, mc, ctl, prog);
  const bool keyboard = ::isatty(STDIN_FILENO);
  if (k.pauses && !keyboard && !c.no_pause)
    throw usage_error(prog.prefix() + prog.name + ": " + std::to_string(k.pauses) +
                      " pauses for the operator (M0, M1, M6): run it from a terminal");
  // Only a program found good changes the port's settings.
  prepare_port(port, mc);
  // The summary first, as text or as the first JSON record (mdi's blocks
  // are on its command line: no summary in text).
  if (c.json || prog.is_file) print_summary(mc, c, prog, k.total, k.pauses);
  const run_result r =
      run_checked(c, mc, ctl, prog, k, prog.command(), keyboard, c.svg.empty() ? nullptr : &plot, nullptr);
  if (!c.svg.empty()) plot.write(c.svg, units_name(mc), prog.name);
  std::cout << (c.json ? r.end_json : r.end_line) << "\n";
  return r.aborted ? 1 : 0;
}

}  // namespace

program program::from_file(const std::string &file) {
  std::ifstream f(file, std::ios::binary);
  if (!f) throw failure("cannot read " + file + ": " + std::strerror(errno), errno);
  std::ostringstream text;
  text << f.rdbuf();
  if (f.bad()) throw failure("cannot read " + file + ": " + std::strerror(errno), errno);
  return {file, text.str(), true, ""};
}

program_check check_at_machine(const config &c, const m::machine &mc, x4step::controller &ctl,
                               const program &prog) {
  program_check k;
  // The offsets the parameter file keeps; what the program changes goes back once it ran.
  k.coords = load_coordinates(mc, prog.command());
  // Planned from where the machine stands.
  const x4step::axes_status at_start = ctl.get_axes();
  k.start = pose_of(mc, at_start);
  // (A simulated port without a machine, X4STEP_SIM_MACHINE, has no switches to home on.)
  const bool can_home = !is_sim_device(ctl.path()) || x4step::sim_machine_switches();
  const std::vector<size_t> unhomed =
      can_home ? unhomed_axes(mc, at_start, machine_axes_of(mc)) : std::vector<size_t>{};
  counter n;
  try {
    k.total = plan(mc, prog, k.start, n, k.coords);
  } catch (const usage_error &e) {
    // A soft limit means little while the machine does not know where it stands.
    if (unhomed.empty()) throw;
    throw usage_error(std::string(e.what()) + "; but " + unhomed_text(c, mc, unhomed));
  }
  k.pauses = n.pauses;
  // Homed first: an axis with a home switch that the program moves.
  std::vector<size_t> moved;
  for (size_t a = 0; a < g::n_axes; a++)
    if (mc.axes[a] && k.total.moved &&
        (steps_of(*mc.axes[a], k.total.min[a]) != steps_of(*mc.axes[a], k.start[a]) ||
         steps_of(*mc.axes[a], k.total.max[a]) != steps_of(*mc.axes[a], k.start[a])))
      moved.push_back(a);
  if (const std::vector<size_t> u = can_home ? unhomed_axes(mc, at_start, moved) : std::vector<size_t>{};
      !u.empty())
    throw failure((prog.is_file ? prog.name + ": " : "") + unhomed_text(c, mc, u) + "; nothing moved");
  return k;
}

std::string check_line(const m::machine &mc, const program_check &k) {
  const m::plan_summary &s = k.total;
  std::string line = std::to_string(s.lines) + " lines, about " + clock_text(s.seconds);
  if (k.pauses) line += ", " + std::to_string(k.pauses) + " pauses";
  if (!s.moved) return line + ", nothing moves";
  line += "; work " + units_name(mc) + ":";
  for (size_t a = 0; a < g::n_axes; a++)
    if (mc.axes[a])
      line += " " + std::string(1, axis_letters[a]) + number(s.work_min[a]) + ".." + number(s.work_max[a]);
  return line;
}

run_result run_checked(const config &c, const m::machine &mc, x4step::controller &ctl, const program &prog,
                       const program_check &k, const std::string &command, bool keyboard, toolpath_plot *plot,
                       const run_view *view) {
  progress_meter meter(mc, ctl, k.total, command, keyboard, c.override_percent, k.start);
  run_result res;
  // G38.x watch the machine file's probe input (set while no path runs).
  if (mc.probe_input)
    x4step::path(ctl).configure(x4step::path_config{}.probe_input(unsigned(mc.probe_input), mc.probe_nc));
  std::string failed;  // a line refused while running (a probe without contact)
  g::coordinate_state coords_after = k.coords;
  {
    path_stream::progress_fn progress = [&](const x4step::path_status &s, std::uint64_t done, bool json,
                                            size_t width) { return meter.record(s, done, json, width); };
    path_stream::view v;
    if (view) {
      v.keys = view->keys;
      v.show = [&](const x4step::path_status &s, std::uint64_t done) { view->show(s, done, meter); };
      v.say = view->say;
    }
    std::optional<path_stream> stream;
    if (view)
      stream.emplace(ctl, c.override_percent, v, progress);
    else
      stream.emplace(ctl, c.override_percent, c.json, keyboard, progress);
    path_stream &ps = *stream;
    runner r(mc, ctl, ps, meter, c.json && !view, c.no_pause);
    if (plot) {
      r.plot = plot;
      plot->start(k.start);
      plot->done(k.start, 0);
    }
    ps.on_poll([&] {
      r.show_due_messages();
      if (plot) plot->done(pose_of(mc, ctl.get_axes()), ps.done());
    });
    try {
      plan(mc, prog, k.start, r, k.coords, &coords_after);
      ps.drain();
    } catch (const run_aborted &) {
      ps.drain();
    } catch (const usage_error &e) {
      // What only the run can find (G38.2 without contact): it ends as an abort.
      failed = e.what();
      ps.drain();
    }
    r.outputs_off();
    res.aborted = ps.aborted() || !failed.empty();
    res.interrupted = ps.interrupted();
    r.end_messages(res.aborted);
    ps.finish();
    meter.ended(ps.status(), ps.done());
    const x4step::axes_status a = ctl.get_axes();
    for (x4step::axis ax : x4step::axis_set::all()) res.end[size_t(ax.index())] = a[ax].position;
    if (plot) {
      plot->done(pose_of(mc, a), ps.done());
      plot->completed(ps.done());
    }
  }
  // A program that ran to its end leaves its offsets (G10, G28.1, G92 ...) for the next command.
  if (!res.aborted) save_coordinates(mc, k.coords, coords_after, prog.command());
  std::ostringstream where;
  json_object pos;
  const g::pose end = pose_of(mc, res.end);
  for (size_t a = 0; a < g::n_axes; a++) {
    if (!mc.axes[a]) continue;
    const double v = end[a];
    where << " " << axis_letters[a] << number(v);
    pos.add(std::string(1, axis_letters[a]), v);
  }
  res.end_line = meter.end_line(res.aborted, where.str());
  res.end_json = meter.end_json(res.aborted, pos);
  if (!failed.empty()) throw usage_error(failed + "; " + res.end_line);
  return res;
}

int cmd_gcode(const config &c) { return run_program(c, program::from_file(c.file)); }

int cmd_mdi(const config &c) {
  // Line n of "mdi" is the n-th block; the M2 after them ends the program
  // (a block's own M2 ends it first).
  std::string text;
  for (const std::string &b : c.blocks) text += b + "\n";
  return run_program(c, program{"mdi", text + "M2\n", false, ""});
}

}  // namespace x4ctl
