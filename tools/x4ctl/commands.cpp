// SPDX-License-Identifier: GPL-2.0
// x4ctl: what the commands share (opening the port, halting moves, settings
// of an open port), and the program's entry point.
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
#include "subcommand.hpp"
#include "term.hpp"

namespace x4ctl {

// The message of any exception, the X4Step ones in the library's words.
std::string what_of(const std::exception &e) {
  if (const auto *x = dynamic_cast<const x4step::error *>(&e);
      x && x->code().category() == x4step::category())
    return x->code().message();
  return e.what();
}

namespace {

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

x4step::monitor open_monitor(const std::string &dev) {
  try {
    return x4step::monitor(dev);
  } catch (const x4step::error &e) {
    if (e.code() != x4step::errc::lpt_not_found) throw;
    throw open_failure(dev, e, false);
  }
}

deadline deadline_of(const config &c, const port &p) { return deadline_in(p, c.time); }

void refuse_sim(const std::string &dev, const char *command) {
  if (is_sim_device(dev)) throw failure(sim_elsewhere_text(dev, command), ENODEV);
}

void note_sim_setting(const std::string &dev) {
  if (is_sim_device(dev)) std::cerr << "x4ctl: " << sim_forgets_text(dev) << "\n";
}

void ask_holder(const std::string &dev, bool stop, x4step::axis_set axes) {
  const auto h = find_controller(dev);
  if (!h) throw failure(dev + ": a move runs, but its program is not visible here (another user's?)");
  if (!h->is_x4ctl())
    throw failure(dev + " is controlled by PID " + std::to_string(h->pid) + " (" + h->name +
                  "), not by x4ctl: brake it there, or press ESC on the console keyboard");
  if (!send_request(h->pid, stop, axes))
    throw failure("cannot signal PID " + std::to_string(h->pid) + ": " + std::strerror(errno));
}

// The module's emergency halt, allowed to any reader of the port, whoever
// controls it. An x4ctl that holds the port is asked first, so that it
// reports the halt and starts none of its --then moves; the emergency halt
// follows at once, whether it heard or not (a stopped or hung holder). A
// module without the emergency halt: the request only.
int halt_moves(const config &c, bool stop) {
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

int with_port(const config &c, void (*command)(port &, const config &, std::ostream &), bool changes) {
  controller_port p(open_controller(device_of(c)));
  command(p, c, std::cout);
  if (changes) note_sim_setting(device_of(c));
  return 0;
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
    std::cout << help_text(*c.cmd);
    return 0;
  }
  const std::string prefix = std::string("x4ctl: ") + (c.cmd->name.empty() ? "" : c.cmd->name + ": ");
  install_signal_handlers();
  try {
    return c.cmd->run(c);
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
