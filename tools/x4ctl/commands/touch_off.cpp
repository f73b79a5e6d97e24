// SPDX-License-Identifier: GPL-2.0
// x4ctl touch-off: where the machine stands becomes the given work
// coordinates: the active system's offset in the parameter file.
#include <cmath>
#include <cstdlib>
#include <iostream>

#include "commands.hpp"
#include "machine_io.hpp"
#include "options.hpp"
#include "subcommand.hpp"
#include "values.hpp"

namespace x4ctl {
namespace {

const char *const system_names[] = {"G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3"};

// LETTER=VALUE (or LETTERVALUE), each axis once.
void operands(parse_state &s, const std::vector<std::string> &ops) {
  need_operands(ops, 1, 6, s.prefix);
  for (const std::string &o : ops) {
    const size_t at = o.size() > 1 && o[1] == '=' ? 2 : 1;
    char *end = nullptr;
    const double v = o.size() > at ? std::strtod(o.c_str() + at, &end) : 0;
    if (!is_axis_letter(o[0]) || !end || *end || !std::isfinite(v))
      throw usage_error(s.prefix + "'" + o +
                        "': give LETTER=VALUE, the work coordinate where the axis stands, e.g. Z=0");
    for (const auto &w : s.c.work)
      if (w.first == upper(o[0]))
        throw usage_error(s.prefix + "'" + o + "': axis " + w.first + " given twice");
    s.c.work.emplace_back(upper(o[0]), v);
  }
}

int run(const config &c) {
  const m::machine mc = load_machine(c, "touch-off");
  const std::string file = machine_path(c);
  if (mc.parameter_file.empty())
    throw usage_error("touch-off: " + file +
                      " has no parameter file to keep work offsets in: add [RS274NGC] PARAMETER_FILE = "
                      "x4step.var (beside the machine file)");
  for (const auto &w : c.work)
    if (!mc.axes[size_t(std::string(axis_letters).find(w.first))])
      throw usage_error(std::string("touch-off: the machine has no ") + w.first +
                        " axis ([TRAJ] COORDINATES)");
  controller_port p(open_controller(machine_device(c, mc)));
  const x4step::axes_status st = p.get_axes();
  const g::pose at = pose_of(mc, st);
  for (const auto &w : c.work) {
    const m::axis &ax = *mc.axes[size_t(std::string(axis_letters).find(w.first))];
    if (st[motor_of(ax)].running)
      throw failure(std::string("touch-off: ") + w.first + " is moving: wait until it stands");
  }
  g::coordinate_state now;
  try {
    // As G10 L20 in the active system: offset = machine - G92 - value.
    now = m::parameter_file(mc.parameter_file).update([&](g::coordinate_state &s) {
      const size_t sys = size_t(c.work_system >= 0 ? c.work_system : s.system);
      for (const auto &w : c.work) {
        const size_t a = std::string(axis_letters).find(w.first);
        s.g5x[sys][a] = at[a] - s.g92[a] - w.second;
      }
    });
  } catch (const m::parameter_error &e) {
    throw failure(std::string("touch-off: ") + e.what());
  }
  const size_t sys = size_t(c.work_system >= 0 ? c.work_system : now.system);
  for (const auto &w : c.work) {
    const size_t a = std::string(axis_letters).find(w.first);
    const bool synced = st[motor_of(*mc.axes[a])].synced;
    std::cout << "touch-off: " << system_names[sys] << " " << w.first << " " << number(now.g5x[sys][a])
              << ": " << w.first << " stands at work " << number(at[a] - now.g5x[sys][a] - now.g92[a])
              << ", machine " << number(at[a]) << " (" << (a < 3 ? units_name(mc) : "deg") << ")"
              << (synced ? "" : "; not homed: the offset holds only until the port loses the position")
              << "\n";
  }
  std::cout << "touch-off: kept in " << mc.parameter_file << "\n";
  return 0;
}

}  // namespace

const subcommand &touch_off_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "touch-off";
    c.usage = {"[OPTIONS] LETTER=VALUE..."};
    c.synopsis = "LETTER=VALUE...";
    c.summary = "where the axes stand becomes work coordinates (Z=0)";
    c.prose =
        "Touch off: where each named axis stands now becomes that coordinate of the\n"
        "active work system (G54 after any program) or of --system: its offset is\n"
        "set as 'G10 L20' sets it (machine position - G92 offset - VALUE) and kept in\n"
        "the machine file's parameter file ([RS274NGC] PARAMETER_FILE, LinuxCNC's\n"
        ".var numbering), which gcode, mdi and the panel read. Jog the tool onto the\n"
        "stock's top, then 'touch-off Z=0'; onto a corner, 'touch-off X=0 Y=0'.\n"
        "Nothing moves.\n";
    c.options = {
        machine_option(machine_file_help),
        {"system", 0, "G54..G59.3",
         "the work system to set (default: the active one,\n"
         "G54 after any program: M2 selects it)",
         [](parse_state &s, const option_value &o) {
           for (size_t i = 0; i < sizeof system_names / sizeof *system_names; i++)
             if (o.value == system_names[i] || o.value == std::string("g") + (system_names[i] + 1))
               s.c.work_system = int(i);
           if (s.c.work_system < 0)
             throw usage_error(s.prefix + "--system " + o.value +
                               ": use G54, G55, G56, G57, G58, G59, G59.1, G59.2 or G59.3");
         }},
    };
    c.epilogue =
        "Exit status: 0 done; 1 the port refused or the parameter file cannot be\n"
        "written; 2 bad usage, a bad machine file or none named.\n"
        "Example: x4ctl touch-off --machine machines/smc1500-mill.ini Z=0\n";
    c.operands = operands;
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
