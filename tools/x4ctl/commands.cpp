// SPDX-License-Identifier: GPL-2.0
// x4ctl: the subcommands.
#include "commands.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <optional>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "cli.hpp"
#include "gcode_cmd.hpp"
#include "holder.hpp"
#include "json.hpp"
#include "lang.hpp"
#include "operate.hpp"
#include "panel.hpp"
#include "path.hpp"
#include "position.hpp"
#include "sim.hpp"
#include "term.hpp"

namespace x4ctl {
namespace {

// For checking a script: says nothing, has no keys.
class null_console : public console {
 public:
  std::ostream &out() override { return null_; }
  bool live() const override { return false; }
  bool has_keyboard() const override { return false; }
  key read_key(milliseconds) override { return key::none; }

 private:
  std::ostream null_{nullptr};
};

// The message of any exception, the X4Step ones in the library's words.
std::string what_of(const std::exception &e) {
  if (const auto *x = dynamic_cast<const x4step::error *>(&e);
      x && x->code().category() == x4step::category())
    return x->code().message();
  return e.what();
}

// The errno behind an exception, 0 if none is known.
int errno_of(const std::exception &e) {
  if (const auto *f = dynamic_cast<const failure *>(&e)) return f->err();
  if (const auto *x = dynamic_cast<const std::system_error *>(&e);
      x &&
      (x->code().category() == std::system_category() || x->code().category() == std::generic_category()))
    return x->code().value();
  return 0;
}

// The errno behind a refused open that the library reports as "port not
// found": the node missing, not ours to open, or (a controller) busy.
int open_errno(const std::string &dev, bool write) {
  if (::access(dev.c_str(), F_OK)) return errno;
  if (::access(dev.c_str(), write ? R_OK | W_OK : R_OK)) return errno;
  return write ? EBUSY : ENODEV;
}

// The library's own text when it knows more (who holds a busy port, how to
// get access), else its general one.
failure open_failure(const std::string &dev, const x4step::error &e, bool write) {
  // A simulated port: its name or a setting of the environment, which the
  // library names with what to fix; no node to ask about.
  if (is_sim_device(dev)) return failure(sim_error_text(e), EINVAL);
  const int err = open_errno(dev, write);
  if (e.what() != e.code().message()) return failure(e.what(), err);
  return failure(dev + ": " + e.code().message(), err);
}

}  // namespace

x4step::controller open_controller(const std::string &dev) {
  try {
    x4step::controller c(dev);
    wire_machine_switches(c);
    return c;
  } catch (const x4step::error &e) {
    if (e.code() != x4step::errc::lpt_not_found) throw;
    if (is_sim_device(dev)) throw open_failure(dev, e, true);
    if (const auto h = find_controller(dev))
      throw failure(dev + ": port busy: PID " + std::to_string(h->pid) + " (" + h->name + ") controls it" +
                        (h->is_x4ctl() ? "; 'x4ctl brake' ends its move" : ""),
                    EBUSY);
    failure f = open_failure(dev, e, true);
    if (const auto u = f.err() == EBUSY ? parport_user(dev) : std::nullopt)
      throw failure(std::string(f.what()) + "; PID " + std::to_string(u->pid) + " (" + u->name + ") uses it",
                    EBUSY);
    throw f;
  }
}

namespace {

x4step::monitor open_monitor(const std::string &dev) {
  try {
    return x4step::monitor(dev);
  } catch (const x4step::error &e) {
    if (e.code() != x4step::errc::lpt_not_found) throw;
    throw open_failure(dev, e, false);
  }
}

std::string describe_move(const x4step::move &m) {
  return steps_text(steps_of(m)) + " at " + std::to_string(m.freq_hz) + " Hz, ramp " +
         std::to_string(m.ramp.count()) + " ms";
}

deadline deadline_of(const config &c, const port &p) { return deadline_in(p, c.time); }

// brake, stop, halt, monitor and watch act on another program's moves:
// a simulated port has none (it lives in this x4ctl alone).
void refuse_sim(const std::string &dev, const char *command) {
  if (is_sim_device(dev)) throw failure(sim_elsewhere_text(dev, command), ENODEV);
}

// A one-shot setting on a simulated port: say that it ends with x4ctl.
void note_sim_setting(const std::string &dev) {
  if (is_sim_device(dev)) std::cerr << "x4ctl: " << sim_forgets_text(dev) << "\n";
}

// "move 3 of 3 not started", "moves 2 to 3 not started" (from: an index).
std::string not_started(size_t from, size_t n) {
  return (from + 1 == n ? "move " : "moves " + std::to_string(from + 1) + " to ") + std::to_string(n) +
         " not started";
}

// move, and the moves of --then: each preloaded while the one before it
// runs, and started the moment that one ends.
int cmd_move(const config &c) {
  controller_port p(open_controller(device_of(c)));
  std_console con(c.wait);
  std::vector<x4step::move> moves{c.move};
  moves.insert(moves.end(), c.then.begin(), c.then.end());
  const size_t n = moves.size();
  auto nth = [&](size_t i) { return "move " + std::to_string(i + 1) + " of " + std::to_string(n); };
  auto header = [&](size_t i) {
    return (n == 1 ? std::string("move") : nth(i)) + ": " + describe_move(moves[i]);
  };
  if (!c.wait) {
    for (size_t i = 0; i < n; i++) std::cout << header(i) << "\n";
    std::cout << std::flush;
    start_moves(p, moves);
    hold_in_background(p, [&](console &bg) { follow_moves(p, bg, moves); });
    return 0;  // the background process, after the moves
  }
  std::cout << header(0) << "\n" << std::flush;
  start_moves(p, moves);
  const std::vector<outcome> done = follow_moves(p, con, moves, [&](size_t i, const outcome &o) {
    if (!o.completed) return;  // the failure below says it
    std::cout << describe(o, steps_of(moves[i])) << "\n";
    if (i + 1 < n && o.late_halt.empty()) std::cout << header(i + 1) << "\n";
    std::cout << std::flush;
  });
  const size_t i = done.size() - 1;
  const outcome &last = done.back();
  if (!last.completed) {
    const std::string why = describe(last, steps_of(moves[i]));
    if (n == 1) throw failure(why);
    throw failure(nth(i) + ": " + why + (i + 1 < n ? "; " + not_started(i + 1, n) : ""));
  }
  if (i + 1 < n)  // a brake request that came as the move ended
    throw failure("halted (" + last.late_halt + ") at the end of " + nth(i) + ": " + not_started(i + 1, n));
  return 0;
}

int cmd_jog(const config &c) {
  controller_port p(open_controller(device_of(c)));
  std_console con(c.wait);
  if (c.wait) check_endless_ends(p, con, c.time.has_value(), "jog", std::make_pair(c.axis, c.dir));
  std::cout << "jog: axis " << c.axis.number() << (c.dir == x4step::direction::positive ? " +" : " -")
            << " at " << c.move.freq_hz << " Hz, ramp " << c.move.ramp.count() << " ms"
            << (c.time ? ", for " + std::to_string(c.time->count()) + " ms" : "") << "\n"
            << std::flush;
  if (!c.wait) {
    start_endless(p, c.axis, c.dir, c.move.freq_hz, c.move.ramp);
    const deadline until = deadline_of(c, p);
    hold_in_background(p, [&](console &bg) { follow(p, bg, std::nullopt, until); });
    return 0;
  }
  const outcome o = run_endless(p, con, c.axis, c.dir, c.move.freq_hz, c.move.ramp, deadline_of(c, p));
  std::cout << describe(o, std::nullopt) << "\n";
  return 0;
}

// brake, stop and halt: the moves belong to the process that holds the
// port; when that is an x4ctl, ask it to brake or stop the axes.
void ask_holder(const std::string &dev, bool stop, x4step::axis_set axes) {
  const auto h = find_controller(dev);
  if (!h) throw failure(dev + ": a move runs, but its program is not visible here (another user's?)");
  if (!h->is_x4ctl())
    throw failure(dev + " is controlled by PID " + std::to_string(h->pid) + " (" + h->name +
                  "), not by x4ctl: brake it there, or press ESC on the console keyboard");
  if (!send_request(h->pid, stop, axes))
    throw failure("cannot signal PID " + std::to_string(h->pid) + ": " + std::strerror(errno));
}

// brake and stop: the module's emergency halt, allowed to any reader of
// the port, whoever controls it. An x4ctl that holds the port is asked
// first, so that it reports the halt and starts none of its --then moves;
// the emergency halt follows at once, whether it heard or not (a stopped
// or hung holder). A module without the emergency halt: the request only.
int cmd_halt(const config &c, bool stop) {
  const std::string dev = device_of(c);
  refuse_sim(dev, stop ? "stop" : "brake");
  const x4step::monitor mon = open_monitor(dev);
  if (!mon.get_status().active) throw failure(message(x4step::errc::not_active));  // any move
  const auto h = find_controller(dev);
  const bool asked = h && h->is_x4ctl() && send_request(h->pid, stop, all_axes);
  try {
    mon.emergency_halt(stop ? x4step::halt_mode::stop : x4step::halt_mode::brake);
  } catch (const x4step::error &e) {
    if (e.code() == x4step::errc::not_active && !asked) throw failure(message(x4step::errc::not_active));
    if (e.code() == std::errc::not_supported && !asked) ask_holder(dev, stop, all_axes);
    if (e.code() != x4step::errc::not_active && e.code() != std::errc::not_supported) throw;
  }
  // A brake takes at most the longest ramp, 1 s.
  if (!mon.wait(milliseconds(5000))) throw failure("the move still runs 5 s later");
  std::cout << (stop ? "stopped: " : "braked: ") << steps_text(mon.get_status().steps) << "\n";
  return 0;
}

int cmd_halt_axes(const config &c) {
  const std::string dev = device_of(c);
  refuse_sim(dev, "halt");
  const x4step::monitor mon = open_monitor(dev);
  const x4step::axes_status a = mon.get_axes();
  bool running = false;
  std::string named;
  for (x4step::axis ax : c.axes) {
    running |= a[ax].running;
    named += (named.empty() ? "" : ", ") + std::to_string(ax.number());
  }
  if (!running)
    throw failure((named.size() == 1 ? "axis " + named + " is" : "axes " + named + " are") + " not moving");
  ask_holder(dev, c.halt_stop, c.axes);
  // An axis' own ramp may be long: wait for it, until Ctrl-C.
  while (!mon.wait_axes(c.axes, tick))
    if (quit_requested()) throw failure("gave up waiting: the axes still move");
  std::cout << (c.halt_stop ? "stopped: " : "braked: ") << positions_text(mon.get_axes(), c.axes) << "\n";
  return 0;
}

int cmd_status(const config &c) {
  const std::string dev = device_of(c);
  const x4step::monitor mon = open_monitor(dev);
  const x4step::status s = mon.get_status();
  const x4step::axes_status a = mon.get_axes();
  std::cout << (c.json ? status_json(s, a, dev) + "\n" : status_text(s, a, dev));
  if (is_sim_device(dev) && !c.json)
    std::cerr << "x4ctl: note: " << dev
              << " is a simulated port of this x4ctl alone: a fresh one, not that of another x4ctl --sim\n";
  return 0;
}

// The inputs as `x4ctl in` shows them. The module reads the port only
// while it has claimed it: through another program's controller when there
// is one, else x4ctl takes the port (kept until it ends), unless read_only.
class input_reader {
 public:
  input_reader(std::string dev, bool read_only)
      : dev_(std::move(dev)), read_only_(read_only), mon_(open_monitor(dev_)) {}

  // A wait between two reads (paced as the wall clock: only Ctrl-C ends
  // the watch); a simulated port in virtual time passes it too.
  void pause(milliseconds d) {
    nap(d);
    if (ctl_ && !port_clock_runs(*ctl_)) port_pass(*ctl_, d);
  }

  x4step::status read() {
    if (ctl_) return ctl_->get_status();
    const x4step::status s = mon_.get_status();
    if (!s.inputs_stale || read_only_) return s;
    try {
      ctl_.emplace(dev_);
    } catch (const x4step::error &) {
      return s;  // another driver (or a controller that just opened) has it
    }
    return ctl_->get_status();
  }

 private:
  std::string dev_;
  bool read_only_;
  x4step::monitor mon_;
  std::optional<x4step::controller> ctl_;
};

int cmd_in(const config &c) {
  input_reader in(device_of(c), c.read_only);
  auto line = [&] {
    const x4step::status s = in.read();
    const auto now = std::chrono::steady_clock::now();
    if (c.json) return inputs_json(s, device_of(c), now);
    return inputs_text(s.inputs) + " (" + std::to_string(s.inputs) + ")" +
           (s.inputs_stale ? " " + stale_text(s, now) : "");
  };
  if (!c.watch) {
    std::cout << line() << "\n";
    return 0;
  }
  std_console con(false);
  std::string last;
  while (take_signal() == key::none) {  // until Ctrl-C
    const std::string now = line();
    if (con.live() && !c.json)
      draw_live(con, now);
    else if (now != last)
      std::cout << now << "\n" << std::flush;
    last = now;
    in.pause(milliseconds(100));
  }
  if (con.live()) std::cout << "\n";
  return 0;
}

int cmd_out(const config &c) {
  controller_port p(open_controller(device_of(c)));
  std_console con(false);
  p.set_output(c.signal, c.level);
  std::cout << "signal " << (c.signal == x4step::signal::one ? "1 (pin 1) " : "2 (pin 14) ")
            << (c.level ? "on" : "off") << "; holding the port "
            << (c.time ? "for " + std::to_string(c.time->count()) + " ms" : std::string("until Ctrl-C"))
            << "\n"
            << std::flush;
  // On the port's clock: a simulated port in virtual time holds the level
  // for --time of its own time at once; without --time, as the wall clock.
  const deadline until = deadline_of(c, p);
  for (auto now = p.now(); !(until && now >= *until); now = p.now()) {
    const milliseconds step =
        until ? std::min(std::chrono::ceil<milliseconds>(*until - now), milliseconds(50)) : milliseconds(50);
    if (pause(p, con, step, !until) != key::none) break;
  }
  std::cout << "released the port: the module drives the outputs low\n";
  return 0;
}

int cmd_keys(const config &c) {
  controller_port p(open_controller(device_of(c)));
  note_sim_setting(device_of(c));
  p.set_brake_codes(c.codes);
  std::string list;
  for (int k : c.codes) list += " " + std::to_string(k);
  std::cout << (c.codes.empty() ? "brake keys: ESC only\n" : "brake keys:" + list + " and ESC\n");
  return 0;
}

int cmd_sweep(const config &c) {
  controller_port p(open_controller(device_of(c)));
  std_console con(true);
  interpreter in(con, &p, true);
  // The A command of the test program, on the given axis.
  const std::string script = "S" + std::to_string(c.axis.number()) + "; D" +
                             std::to_string(c.move.steps[c.axis.index()]) + "; R" +
                             std::to_string(c.move.ramp.count()) + "; A" + std::to_string(c.sweep_from) +
                             "," + std::to_string(c.sweep_to) + "," + std::to_string(c.sweep_step);
  for (const command &cmd : parse_line(script)) in.execute(cmd);
  return 0;
}

int cmd_monitor(const config &c) {
  refuse_sim(device_of(c), "monitor");
  const x4step::monitor mon = open_monitor(device_of(c));
  std_console con(false);
  x4step::status s = mon.get_status();
  std::uint64_t seen = s.moves_ended;
  bool was_active = s.active;
  long ended = 0;
  const bool live = con.live() && !c.json;
  std::cout << (c.json     ? monitor_json(s.active ? "running" : "idle", s) + "\n"
                : s.active ? "move running\n"
                           : "idle, waiting for moves\n")
            << std::flush;
  while (take_signal() == key::none) {
    s = mon.get_status();
    if (s.active && !was_active)
      std::cout << (c.json ? monitor_json("started", s)
                           : std::string(live ? "\r\x1b[K" : "") + "move started")
                << "\n"
                << std::flush;
    if (s.moves_ended != seen) {
      if (live) draw_live(con, "");
      if (c.json)
        std::cout << monitor_json("ended", s) << "\n" << std::flush;
      else
        std::cout << "move ended: steps " << steps_text(s.steps)
                  << (s.last_brake_code ? ", braked by " + key_name(s.last_brake_code) : "") << "\n"
                  << std::flush;
      ended += static_cast<long>(s.moves_ended - seen);
      seen = s.moves_ended;
      if (c.moves && ended >= *c.moves) return 0;
    }
    if (s.active && live) draw_live(con, "steps " + steps_text(s.steps));
    was_active = s.active;
    if (s.active)
      mon.wait(tick);  // returns at the move's end
    else
      nap(milliseconds(20));
  }
  if (live) std::cout << "\n";
  return 0;
}

// The port's events, one line each, until Ctrl-C or --count of them.
int cmd_watch(const config &c) {
  refuse_sim(device_of(c), "watch");
  const x4step::monitor mon = open_monitor(device_of(c));
  std::uint64_t next = 0;  // the seq expected next; 0: any
  long seen = 0;
  while (take_signal() == key::none) {
    std::optional<x4step::event> e;
    try {
      e = mon.read_event(tick);
    } catch (const x4step::error &err) {
      if (err.code() != x4step::errc::lpt_not_found) throw;
      throw failure(device_of(c) + ": the port went away");
    }
    if (!e) continue;
    if (next && e->seq > next)
      std::cout << (c.json ? missed_json(e->seq - next) : missed_text(e->seq - next)) << "\n";
    next = e->seq + 1;
    std::cout << (c.json ? event_json(*e) : event_text(*e)) << "\n" << std::flush;
    if (c.count && ++seen >= *c.count) return 0;
    if (e->type == x4step::event_type::port_gone) throw failure(device_of(c) + ": the port went away");
  }
  return 0;
}

// The simulated ports: in this library, a fresh one in each program.
int list_sim(const config &c) {
  std::vector<port_entry> ports;
  for (int n = 0; n < 4; n++) {
    port_entry p;
    p.device = "sim:" + std::to_string(n);
    p.parport = n;
    p.simulated = true;
    try {
      p.abi = open_monitor(p.device).abi_version();
    } catch (const failure &e) {
      p.error = e.what();
      p.err = e.err();
    }
    ports.push_back(p);
  }
  std::cout << (c.json ? list_json(ports) + "\n" : list_text(ports));
  return 0;
}

// Every port: its module's version and who holds it.
int cmd_list(const config &c) {
  if (is_sim_device(device_of(c))) return list_sim(c);
  std::vector<port_entry> ports;
  for (const std::string &dev : x4step_devices()) {
    port_entry p;
    p.device = dev;
    p.parport = std::atoi(dev.c_str() + std::strlen("/dev/x4step"));
    p.claimant = parport_claimant(p.parport);
    try {
      const x4step::monitor mon = open_monitor(dev);
      p.abi = mon.abi_version();
      p.controlled = mon.get_status().controlled;
      if (p.controlled) p.controller = find_controller(dev);
    } catch (const failure &e) {
      p.error = e.what();
      p.err = e.err();
    }
    ports.push_back(p);
  }
  if (ports.empty())
    throw failure(
        "no /dev/x4stepN: load the module ('sudo modprobe x4step'; a parallel port and parport_pc needed)",
        ENOENT);
  std::cout << (c.json ? list_json(ports) + "\n" : list_text(ports));
  return 0;
}

// timing, mode, profile, limits, zero: settings of an open port.
int with_port(const config &c, void (*command)(port &, const config &, std::ostream &)) {
  controller_port p(open_controller(device_of(c)));
  command(p, c, std::cout);
  const bool changes = c.pulse || c.space || c.dir_setup || c.dir_hold || c.mode || c.v0 || c.ve || c.vm ||
                       c.a0 || c.ae || c.ref || c.plus || c.minus || c.nc || c.cmd == subcommand::zero;
  if (changes) note_sim_setting(device_of(c));
  return 0;
}

int cmd_goto(const config &c) {
  controller_port p(open_controller(device_of(c)));
  std_console con(!c.no_wait);
  const coordinates want = start_goto_command(p, c, std::cout);
  if (c.no_wait) {
    hold_in_background(p, [&](console &bg) { follow_axes(p, bg, c.axes); });
    return 0;  // the background process, after the moves
  }
  finish_goto_command(p, con, c, want, std::cout);
  return 0;
}

int cmd_home(const config &c) {
  controller_port p(open_controller(device_of(c)));
  std_console con(true);
  home_command(p, con, c, std::cout);
  return 0;
}

struct script_line {
  int number;
  command cmd;
};

// Reads and parses the whole script, so that a bad line is found before anything moves.
std::vector<script_line> read_script(const std::string &file, const std::string &name) {
  std::ifstream f;
  if (file != "-") {
    f.open(file);
    if (!f) throw failure("cannot read " + file + ": " + std::strerror(errno));
  }
  std::istream &in = file == "-" ? std::cin : f;
  std::vector<script_line> lines;
  std::string text;
  for (int n = 1; std::getline(in, text); n++) {
    try {
      for (auto &cmd : parse_line(text)) lines.push_back({n, std::move(cmd)});
    } catch (const usage_error &e) {
      throw usage_error("run: " + name + ":" + std::to_string(n) + ": " + e.what());
    }
  }
  return lines;
}

int cmd_run(const config &c) {
  const std::string name = c.file == "-" ? "stdin" : c.file;
  const auto lines = read_script(c.file, name);
  auto where = [&](const script_line &l) { return name + ":" + std::to_string(l.number) + ": "; };

  // First a dry run: every value and combination (ramp against frequency,
  // C without a terminal) is checked before the port is opened.
  null_console quiet;
  interpreter dry(quiet, nullptr, true);
  for (const auto &l : lines) {
    try {
      if (!dry.execute(l.cmd)) break;
    } catch (const usage_error &e) {
      throw usage_error("run: " + where(l) + e.what());
    }
  }
  if (c.check) {
    std::cout << name << ": " << lines.size() << " commands, no errors\n";
    return 0;
  }

  controller_port p(open_controller(device_of(c)));
  std_console con(false);
  interpreter in(con, &p, true);
  for (const auto &l : lines) {
    if (quit_requested()) throw failure(where(l) + "interrupted before " + l.cmd.text);
    if (c.echo) std::cout << in.prompt() << l.cmd.text << "\n" << std::flush;
    try {
      if (!in.execute(l.cmd)) break;
    } catch (const std::exception &e) {
      throw failure(where(l) + what_of(e));
    }
  }
  return 0;
}

int cmd_interactive(const config &c) {
  const std::string dev = device_of(c);
  controller_port p(open_controller(dev));
  std_console con(true);
  interpreter in(con, &p, false);
  const bool tty = ::isatty(STDIN_FILENO);
  std::cout << "x4ctl: X4Step test program on " << dev << "\n";
  if (tty) std::cout << language_help();  // as TEST.EXE does at its start
  for (;;) {
    std::cout << in.prompt() << std::flush;
    std::string line;
    if (!std::getline(std::cin, line)) break;  // end of input, or Ctrl-C
    if (!tty) std::cout << line << "\n";       // a readable transcript
    try {
      for (const command &cmd : parse_line(strip_keys(line)))
        if (!in.execute(cmd)) return 0;
    } catch (const std::exception &e) {
      // The rest of the line is dropped: nothing moves after an error.
      std::cout << std::flush;
      std::cerr << "error: " << what_of(e) << "\n";
    }
    if (quit_requested()) break;
  }
  std::cout << "\n";
  return 0;
}

int dispatch(const config &c) {
  switch (c.cmd) {
    case subcommand::interactive:
      return cmd_interactive(c);
    case subcommand::move:
      return cmd_move(c);
    case subcommand::jog:
      return c.machine_units() ? cmd_jog_machine(c) : cmd_jog(c);
    case subcommand::brake:
      return cmd_halt(c, false);
    case subcommand::stop:
      return cmd_halt(c, true);
    case subcommand::status:
      return cmd_status(c);
    case subcommand::in:
      return cmd_in(c);
    case subcommand::out:
      return cmd_out(c);
    case subcommand::keys:
      return cmd_keys(c);
    case subcommand::sweep:
      return cmd_sweep(c);
    case subcommand::monitor:
      return cmd_monitor(c);
    case subcommand::run:
      return cmd_run(c);
    case subcommand::timing:
      return with_port(c, timing_command);
    case subcommand::mode:
      return with_port(c, mode_command);
    case subcommand::profile:
      return with_port(c, profile_command);
    case subcommand::go_to:
      return cmd_goto(c);
    case subcommand::home:
      return c.machine_units() ? cmd_home_machine(c) : cmd_home(c);
    case subcommand::zero:
      return with_port(c, zero_command);
    case subcommand::limits:
      return with_port(c, limits_command);
    case subcommand::halt:
      return cmd_halt_axes(c);
    case subcommand::watch:
      return cmd_watch(c);
    case subcommand::list:
      return cmd_list(c);
    case subcommand::path:
      return cmd_path(c);
    case subcommand::gcode:
      return cmd_gcode(c);
    case subcommand::mdi:
      return cmd_mdi(c);
    case subcommand::panel:
      return cmd_panel(c);
    case subcommand::help:
      std::cout << help_text(c.topic);
      return 0;
  }
  return 2;
}

}  // namespace

void timing_command(port &p, const config &c, std::ostream &out) {
  x4step::step_timing t = p.get_step_timing();
  if (c.pulse || c.space || c.dir_setup || c.dir_hold) {
    if (c.pulse) t.pulse(*c.pulse);
    if (c.space) t.space(*c.space);
    if (c.dir_setup) t.dir_setup(*c.dir_setup);
    if (c.dir_hold) t.dir_hold(*c.dir_hold);
    p.set_step_timing(t);
    t = p.get_step_timing();  // what the port took
  }
  const x4step::output_mode m = p.get_config().mode();
  const std::string dev = device_of(c);
  out << (c.json ? timing_json(t, m, dev) + "\n" : timing_text(t, m, dev));
}

void mode_command(port &p, const config &c, std::ostream &out) {
  x4step::config k = p.get_config();
  if (c.mode) {
    k.mode(*c.mode);  // the inversions and key settings stay
    p.set_config(k);
    k = p.get_config();
  }
  out << (c.json ? mode_json(k.mode(), device_of(c)) : mode_text(k.mode())) << "\n";
}

int run_main(const std::vector<std::string> &args) {
  config c;
  try {
    c = parse_args(args);
  } catch (const usage_error &e) {
    if (std::find(args.begin(), args.end(), "--json") != args.end()) {
      std::cout << json_error(e.what(), EINVAL) << "\n";
      return 2;
    }
    std::cerr << "x4ctl: " << e.what() << "\n";
    // The first known subcommand's help, else x4ctl's.
    std::string sub;
    for (size_t i = 1; i < args.size() && sub.empty(); i++)
      if (find_command(args[i])) sub = args[i] + " ";
    std::cerr << "Try 'x4ctl " << sub << "--help'.\n";
    return 2;
  }
  if (c.version) {
    std::cout << version_text();
    return 0;
  }
  if (c.help) {
    std::cout << help_text(c.cmd);
    return 0;
  }
  const std::string prefix =
      std::string("x4ctl: ") + (c.cmd == subcommand::interactive ? "" : std::string(name_of(c.cmd)) + ": ");
  install_signal_handlers();
  try {
    return dispatch(c);
  } catch (const usage_error &e) {
    std::cout << std::flush;
    if (c.json)
      std::cout << json_error(e.what(), EINVAL) << "\n";
    else
      std::cerr << "x4ctl: " << e.what() << "\n";
    return 2;
  } catch (const std::exception &e) {
    std::cout << std::flush;
    if (c.json)
      std::cout << json_error(what_of(e), errno_of(e)) << "\n" << std::flush;
    else
      std::cerr << prefix << what_of(e) << "\n";
    return 1;
  }
}

}  // namespace x4ctl
