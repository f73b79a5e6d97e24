// SPDX-License-Identifier: GPL-2.0
// Prints the interpreter's canonical motions, one per line, for the oracle
// comparison with LinuxCNC's rs274 (tests/gcode/oracle.py):
//   TRAVERSE x y z a b c | FEED x y z a b c | ARC x y z a b c plane c1 c2 turns
//   | DWELL seconds
// in mm (degrees for A B C), %.9f. Usage: gcode_dump [-t tool.tbl] [-i] FILE
// (-i: the tool table is in inches). Exit 1 with file:line:column: what.
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
  void arc_feed(const g::arc &a) override {
    std::printf("ARC");
    for (double v : a.end) std::printf(" %.9f", v);
    std::printf(" %d %.9f %.9f %d\n", int(a.in), a.centre_first, a.centre_second, a.turns);
  }
  void dwell(double seconds) override { std::printf("DWELL %.9f\n", seconds); }
  void tool_length_offset(const g::pose &) override {}

 private:
  static void put(const char *what, const g::pose &p) {
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
