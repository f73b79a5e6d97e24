// SPDX-License-Identifier: GPL-2.0
// G-code interpreter throughput (issue 20, goal >= 200 000 lines/s): a
// 100 000-line file made of a real CAM program's body repeated (by
// default LinuxCNC's plasmatest.ngc, the EMC-Plasma post processor's
// output, from scripts/get-rs274.sh's cache), run from the file through
// the interpreter into a sink that counts; then the interpreter and the
// planner (lib/machine) into an output that counts segments, on a mill
// with room for the whole program; the best of 5 runs each. tests/bench/
// run.sh runs it also on arc-heavy CAM output (tests/gcode/cam/
// fusion360-linuxcnc.ngc: adaptive clearing's arcs, drilling cycles).
// Usage: gcode_bench [CAM.ngc] [LINES] [KEEP]
// KEEP: also write the program and the machine as KEEP.ngc and KEEP.ini
// (tests/bench/run.sh times `x4ctl gcode --check` on them).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "gcode.hpp"
#include "planner.hpp"

namespace g = x4step::gcode;

namespace {

struct counter : g::sink {
  long moves = 0, arcs = 0;
  double sum = 0;
  void straight_traverse(const g::straight &s) override { ++moves, sum += s.end[0]; }
  void straight_feed(const g::straight &s) override { ++moves, sum += s.end[0]; }
  void arc_feed(const g::arc &a) override { ++arcs, sum += a.centre_first; }
};

struct segment_counter : x4step::machine::planner_output {
  long segments = 0;
  void segment(const x4step::segment &, const x4step::machine::segment_info &) override { ++segments; }
};

// A mill in mm with room for any of LinuxCNC's examples.
const char *const bench_machine =
    "[X4STEP]\nARC_TOLERANCE = 0.01\nJUNCTION_DEVIATION = 0.02\n"
    "[TRAJ]\nCOORDINATES = XYZ\nLINEAR_UNITS = mm\n"
    "[AXIS_X]\nMIN_LIMIT = -10000\nMAX_LIMIT = 10000\nMAX_VELOCITY = 100\nMAX_ACCELERATION = 1000\n"
    "[AXIS_Y]\nMIN_LIMIT = -10000\nMAX_LIMIT = 10000\nMAX_VELOCITY = 100\nMAX_ACCELERATION = 1000\n"
    "[AXIS_Z]\nMIN_LIMIT = -10000\nMAX_LIMIT = 10000\nMAX_VELOCITY = 50\nMAX_ACCELERATION = 500\n"
    "[JOINT_0]\nMOTOR = 1\nSCALE = 100\n[JOINT_1]\nMOTOR = 2\nSCALE = 100\n[JOINT_2]\nMOTOR = 3\nSCALE = "
    "100\n";

bool is_end(const std::string &l) {
  std::string u;
  for (char c : l)
    if (c != ' ' && c != '\t' && c != '\r') u += char(std::toupper(static_cast<unsigned char>(c)));
  auto p = u.find('M');
  while (p != std::string::npos) {
    std::string n;
    for (size_t i = p + 1; i < u.size() && std::isdigit(static_cast<unsigned char>(u[i])); ++i) n += u[i];
    if (!n.empty() && (std::atoi(n.c_str()) == 2 || std::atoi(n.c_str()) == 30)) return true;
    p = u.find('M', p + 1);
  }
  return u == "%";
}

}  // namespace

int main(int argc, char **argv) {
  std::string src =
      argc > 1 ? argv[1] : "/var/cache/x4step/linuxcnc/root/usr/share/linuxcnc/ncfiles/plasmatest.ngc";
  long want = argc > 2 ? std::atol(argv[2]) : 100000;
  std::ifstream in(src);
  if (!in) {
    std::fprintf(stderr, "gcode_bench: cannot open %s (scripts/get-rs274.sh fetches LinuxCNC's examples)\n",
                 src.c_str());
    return 1;
  }
  std::vector<std::string> body;
  for (std::string l; std::getline(in, l);)
    if (!is_end(l)) body.push_back(l);
  char tmpl[] = "/tmp/gcode_bench.XXXXXX";
  int fd = mkstemp(tmpl);
  if (fd < 0) return 1;
  std::string path = tmpl;
  {
    std::ofstream out(path);
    long n = 0;
    while (n < want - 1)
      for (const auto &l : body) {
        if (n >= want - 1) break;
        out << l << '\n';
        ++n;
      }
    out << "M2\n";
  }
  double best = 1e30;
  counter c;
  for (int run = 0; run < 5; ++run) {
    c = counter{};
    auto t0 = std::chrono::steady_clock::now();
    try {
      g::interpreter interp(c);
      interp.run_file(path);
    } catch (const g::error &e) {
      std::fprintf(stderr, "%s\n", e.what());
      std::remove(path.c_str());
      return 1;
    }
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (s < best) best = s;
  }
  std::printf("gcode: %ld lines of %s (%zu-line body repeated): %ld straight moves, %ld arcs\n", want,
              src.substr(src.rfind('/') + 1).c_str(), body.size(), c.moves, c.arcs);
  std::printf("gcode: %.0f lines/s, best of 5 runs (%.1f ms; goal >= 200000 lines/s)\n", double(want) / best,
              best * 1e3);

  std::istringstream machine_text(bench_machine);
  const x4step::machine::machine mill = x4step::machine::read(machine_text, "bench.ini");
  double best_planned = 1e30;
  segment_counter segs;
  for (int run = 0; run < 5; ++run) {
    segs = segment_counter{};
    auto t0 = std::chrono::steady_clock::now();
    try {
      std::ifstream f(path);
      x4step::machine::plan_program(mill, f, path, segs);
    } catch (const g::error &e) {
      std::fprintf(stderr, "%s\n", e.what());
      std::remove(path.c_str());
      return 1;
    }
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (s < best_planned) best_planned = s;
  }
  std::printf(
      "gcode + planner: %.0f lines/s, %ld segments (arcs in 0.01 mm chords), best of 5 runs (%.1f ms;"
      " goal >= 200000 lines/s)\n",
      double(want) / best_planned, segs.segments, best_planned * 1e3);
  if (argc > 3) {
    std::ofstream(std::string(argv[3]) + ".ini") << bench_machine;
    std::ifstream from(path);
    std::ofstream(std::string(argv[3]) + ".ngc") << from.rdbuf();
  }
  std::remove(path.c_str());
  return 0;
}
