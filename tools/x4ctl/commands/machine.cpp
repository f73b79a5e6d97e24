// SPDX-License-Identifier: GPL-2.0
// x4ctl machine: check a machine file, or make one of a LinuxCNC StepConf
// configuration (lib/machine/stepconf.hpp). Touches no port.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "machine_io.hpp"
#include "stepconf.hpp"
#include "subcommand.hpp"

namespace x4ctl {
namespace {

std::string directory_of(const std::string &path) {
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}

bool exists(const std::string &path) {
  struct stat st;
  return stat(path.c_str(), &st) == 0;
}

// "good: XYZ in mm, motors 1 2 3, homes X Z".
std::string summary(const m::machine &mc) {
  std::string letters, motors, homes;
  for (size_t a = 0; a < g::n_axes; a++)
    if (mc.axes[a]) {
      letters += axis_letters[a];
      motors += " " + std::to_string(mc.axes[a]->motor + 1);
      if (mc.axes[a]->home.enabled) homes += std::string(" ") + axis_letters[a];
    }
  return "good: " + letters + " in " + units_name(mc) + ", motors" + motors +
         (homes.empty() ? ", no homing" : ", homes" + homes);
}

// One file checked: its mistakes, else a summary, then its warnings. True if good.
bool check_one(std::istream &in, const std::string &name, std::ostream &out) {
  try {
    const m::machine mc = m::read(in, name);
    out << name << ": " << summary(mc) << "\n";
    for (const std::string &w : mc.warnings) out << w << "\n";
    return true;
  } catch (const m::error &e) {
    for (const std::string &l : e.lines()) out << l << "\n";
    const size_t n = e.problems().size();
    out << name << ": refused: " << n << (n == 1 ? " mistake" : " mistakes") << "\n";
    return false;
  }
}

int run_check(const config &c) {
  bool good = true;
  for (const std::string &f : c.files) {
    std::ifstream in(f);
    if (!in) {
      std::cout << f << ": cannot read the machine file\n";
      good = false;
      continue;
    }
    good = check_one(in, f, std::cout) && good;
  }
  return good ? 0 : 1;
}

int run_import(const config &c) {
  const std::string &ini_path = c.files[0];
  std::ifstream ini(ini_path);
  if (!ini) throw usage_error("machine: cannot read " + ini_path);
  std::string ini_text((std::istreambuf_iterator<char>(ini)), std::istreambuf_iterator<char>());
  // The HAL file: given, else the INI's first [HAL] HALFILE beside it.
  std::string hal_path = c.files.size() > 1 ? c.files[1] : "";
  std::string tool_table;
  {
    std::istringstream lines(ini_text);
    std::string section;
    for (std::string l; std::getline(lines, l);) {
      const size_t a = l.find_first_not_of(" \t");
      if (a == std::string::npos) continue;
      if (l[a] == '[') section = l.substr(a, l.find(']') + 1 - a);
      const size_t eq = l.find('=');
      if (eq == std::string::npos) continue;
      std::string key = l.substr(a, eq - a), value = l.substr(eq + 1);
      key.erase(key.find_last_not_of(" \t") + 1);
      value.erase(0, value.find_first_not_of(" \t"));
      value.erase(value.find_last_not_of(" \t\r") + 1);
      const std::string file = value.empty() || value[0] == '/' ? value : directory_of(ini_path) + value;
      if (section == "[HAL]" && key == "HALFILE" && c.files.size() == 1 && hal_path.empty() && exists(file))
        hal_path = file;
      if (section == "[EMCIO]" && key == "TOOL_TABLE" && tool_table.empty() && exists(file)) {
        char *real = realpath(file.c_str(), nullptr);
        tool_table = real ? real : file;
        std::free(real);
      }
    }
  }
  std::unique_ptr<std::ifstream> hal;
  if (!hal_path.empty()) {
    hal = std::make_unique<std::ifstream>(hal_path);
    if (!*hal) throw usage_error("machine: cannot read " + hal_path);
  }
  std::istringstream ini_in(ini_text);
  const m::imported r = m::import_stepconf(ini_in, ini_path, hal.get(), hal_path, tool_table);

  const std::string out_name = c.output.empty() ? "(standard output)" : c.output;
  if (!c.output.empty()) {
    // O_EXCL: never over a file (or through a link) that is there, even
    // one made since the program started.
    const int fd = ::open(c.output.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno == EEXIST)
      throw usage_error("machine: " + c.output + " exists: remove it or name another");
    if (fd < 0) throw failure("cannot write " + c.output + ": " + std::strerror(errno), errno);
    bool written = true;
    for (size_t done = 0; written && done < r.text.size();) {
      const ssize_t n = ::write(fd, r.text.data() + done, r.text.size() - done);
      if (n < 0 && errno == EINTR) continue;
      written = n > 0;
      if (written) done += size_t(n);
    }
    if (::close(fd) < 0 || !written)
      throw failure("cannot write " + c.output + ": " + std::strerror(errno), errno);
  } else {
    std::cout << r.text << std::flush;
  }
  // The report: on standard output with -o, else on standard error.
  std::ostream &rep = c.output.empty() ? std::cerr : std::cout;
  rep << "import: " << ini_path << (hal ? " and " + hal_path : " (no HAL file)") << " into " << out_name
      << "\n";
  if (c.files.size() == 1 && hal) rep << "import: the HAL file is the INI's [HAL] HALFILE\n";
  for (const std::string &n : r.notes) rep << "changed: " << n << "\n";
  for (const std::string &n : r.not_carried) rep << "not carried: " << n << "\n";
  // The file made, as `machine check` reads it.
  std::istringstream made(r.text);
  const bool good = check_one(made, c.output.empty() ? "import" : c.output, rep);
  return good ? 0 : 1;
}

void operands(parse_state &s, const std::vector<std::string> &ops) {
  if (ops.empty() || (ops[0] != "check" && ops[0] != "import"))
    throw usage_error(s.prefix + (ops.empty() ? "give check or import"
                                              : "no action '" + ops[0] + "': use check or import"));
  s.c.machine_action = ops[0];
  s.c.files.assign(ops.begin() + 1, ops.end());
  if (ops[0] == "check" && s.c.files.empty()) throw usage_error(s.prefix + "check: give the machine file(s)");
  if (ops[0] == "import") need_operands(s.c.files, 1, 2, s.prefix + "import: ");
  if (ops[0] == "check" && !s.c.output.empty()) throw usage_error(s.prefix + "--output is import's");
}

int run(const config &c) { return c.machine_action == "check" ? run_check(c) : run_import(c); }

}  // namespace

const subcommand &machine_subcommand() {
  static const subcommand c = [] {
    subcommand c;
    c.name = "machine";
    c.usage = {"check FILE...", "import [OPTIONS] INI [HAL]"};
    c.synopsis = "check|import FILE...";
    c.summary = "check a machine file, or make one of a LinuxCNC StepConf\nconfiguration";
    c.prose =
        "check: read each machine file as gcode, mdi, home, jog and panel read it,\n"
        "and list every mistake in it, a line each (FILE:LINE:COLUMN: [SECTION] KEY:\n"
        "what to fix, with 'did you mean KEY?' for a misspelt key), or 'good' and\n"
        "what the machine is; then LinuxCNC's sections and keys that x4step accepts\n"
        "but does not use. The keys: machines/README.md.\n"
        "import: make a machine file of a LinuxCNC configuration as StepConf writes\n"
        "it: its INI file and its HAL file (default: the INI's [HAL] HALFILE beside\n"
        "it). Carried: units, axes, SCALE, velocities, accelerations, soft limits,\n"
        "homing with the home switches' inputs, spindle and coolant outputs on pins\n"
        "1 and 14, the tool table. Listed as not carried: the pin map (x4step's\n"
        "pins are fixed: joint n is motor n+1), limit switches and step timing (the\n"
        "port's settings, with the x4ctl command that makes them), and every other\n"
        "key. The file made is then checked as 'check' does.\n";
    c.options = {
        {"output", 'o', "FILE",
         "import: write the machine file to FILE (not if it\n"
         "exists) and the report to standard output; default:\n"
         "the file to standard output, the report to standard error",
         [](parse_state &s, const option_value &o) {
           if (o.value.empty()) throw usage_error(s.prefix + "--output needs a file");
           s.c.output = o.value;
         }},
    };
    c.epilogue =
        "Exit status: 0 every file is good (import: the file made is); 1 a file was\n"
        "refused (import: the file is written, fix what the check lists); 2 bad\n"
        "usage, or the INI or HAL file cannot be read.\n"
        "Examples: x4ctl machine check machines/smc1500-mill.ini\n"
        "          x4ctl machine import -o router.ini linuxcnc/configs/router/router.ini\n";
    c.operands = operands;
    c.run = run;
    return c;
  }();
  return c;
}

}  // namespace x4ctl
