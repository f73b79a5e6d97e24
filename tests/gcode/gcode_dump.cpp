// SPDX-License-Identifier: GPL-2.0
// Prints the interpreter's canonical motions, one per line, for the oracle
// comparison with LinuxCNC's rs274 (tests/gcode/oracle.py):
//   TRAVERSE x y z a b c | FEED x y z a b c | ARC x y z a b c plane c1 c2 turns
//   | DWELL seconds | PROBE x y z a b c
// A probe (G38.2..G38.5) answers as rs274's stand-alone machine does
// (saicanon.cc): contact at the programmed end, then a stop 0.254 mm
// (0.01 inch) back along the move in X Y Z, where the program goes on.
// in mm (degrees for A B C), %.9f. Usage: gcode_dump [-t tool.tbl] [-i] FILE
// (-i: the tool table is in inches). Exit 1 with file:line:column: what.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>

#include "gcode.hpp"

namespace g = x4step::gcode;

namespace {

class printer : public g::sink {
 public:
  void straight_traverse(const g::straight &s) override { put("TRAVERSE", s.end); }
  void straight_feed(const g::straight &s) override { put("FEED", s.end); }
  g::probe_outcome straight_probe(const g::straight &s, g::probe_kind) override {
    const g::pose from = at_;
    put("PROBE", s.end);
    g::probe_outcome r{s.end, true, s.end};
    const double d = std::hypot(from[0] - s.end[0], from[1] - s.end[1], from[2] - s.end[2]);
    if (d != 0)
      for (int a = 0; a < 3; a++) r.stop[size_t(a)] += 0.254 * (from[size_t(a)] - s.end[size_t(a)]) / d;
    at_ = r.stop;
    return r;
  }
  void arc_feed(const g::arc &a) override {
    at_ = a.end;
    std::printf("ARC");
    for (double v : a.end) std::printf(" %.9f", v);
    std::printf(" %d %.9f %.9f %d\n", int(a.in), a.centre_first, a.centre_second, a.turns);
  }
  void dwell(double seconds) override { std::printf("DWELL %.9f\n", seconds); }
  void tool_length_offset(const g::pose &) override {}

 private:
  g::pose at_{};  // where the last motion ended

  void put(const char *what, const g::pose &p) {
    at_ = p;
    std::printf("%s", what);
    for (double v : p) std::printf(" %.9f", v);
    std::printf("\n");
  }
};

}  // namespace

int main(int argc, char **argv) {
  std::string table;
  bool table_inch = false;
  int i = 1;
  for (; i < argc && argv[i][0] == '-'; ++i) {
    if (!std::strcmp(argv[i], "-t") && i + 1 < argc)
      table = argv[++i];
    else if (!std::strcmp(argv[i], "-i"))
      table_inch = true;
    else
      break;
  }
  if (i + 1 != argc) {
    std::fprintf(stderr, "usage: gcode_dump [-t tool.tbl] [-i] FILE\n");
    return 2;
  }
  printer p;
  try {
    g::interpreter in(p);
    if (!table.empty())
      in.set_tool_table(g::read_tool_table(table, table_inch ? g::units::inch : g::units::mm, g::units::mm));
    in.run_file(argv[i]);
  } catch (const g::error &e) {
    std::fflush(stdout);
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
