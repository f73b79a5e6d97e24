// SPDX-License-Identifier: GPL-2.0
// The parameter file (lib/machine/params.hpp): LinuxCNC's numbering and
// format, the interpreter starting from and giving back its state, atomic
// replacement, and two writers that never lose each other's change.
#include "params.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "machine.hpp"
#include "planner.hpp"

namespace m = x4step::machine;
namespace g = x4step::gcode;

namespace {

// A fresh directory for one test, removed with it.
class params_dir : public ::testing::Test {
 protected:
  void SetUp() override {
    char t[] = "/tmp/x4params.XXXXXX";
    ASSERT_NE(::mkdtemp(t), nullptr);
    dir_ = t;
  }
  void TearDown() override { std::system(("rm -rf " + dir_).c_str()); }
  std::string path(const std::string &name) const { return dir_ + "/" + name; }
  std::string dir_;
};

std::string slurp(const std::string &p) {
  std::ifstream f(p);
  std::ostringstream o;
  o << f.rdbuf();
  return o.str();
}

// A sink that keeps where the moves end.
struct ends : g::sink {
  std::vector<g::pose> at;
  void straight_traverse(const g::straight &s) override { at.push_back(s.end); }
  void straight_feed(const g::straight &s) override { at.push_back(s.end); }
};

g::coordinate_state run(const std::string &text, const g::coordinate_state &start, ends &out,
                        g::units u = g::units::mm) {
  g::options o;
  o.machine_units = o.initial_units = u;
  o.coordinates = start;
  g::interpreter in(out, o);
  std::istringstream s(text);
  in.run(s, "t.ngc");
  return in.coordinates();
}

}  // namespace

TEST(params, linuxcnc_numbers) {
  g::coordinate_state c;
  c.g28 = {1, 2, 3, 4, 0, 0};
  c.g30 = {5, 0, 0, 0, 0, 0};
  c.g92 = {0, 0, -1.5, 0, 0, 0};
  c.g5x[0] = {10, 20, 30, 0, 0, 0};  // G54
  c.g5x[1] = {0, -7, 0, 0, 0, 0};    // G55
  c.g5x[8] = {0, 0, 0, 90, 0, 0};    // G59.3
  c.system = 1;
  m::parameters p;
  m::set_coordinates(p, c);
  EXPECT_EQ(p.at(5161), 1);
  EXPECT_EQ(p.at(5163), 3);
  EXPECT_EQ(p.at(5164), 4);
  EXPECT_EQ(p.at(5181), 5);
  EXPECT_EQ(p.at(5210), 1);
  EXPECT_EQ(p.at(5213), -1.5);
  EXPECT_EQ(p.at(5220), 2);  // G55
  EXPECT_EQ(p.at(5221), 10);
  EXPECT_EQ(p.at(5223), 30);
  EXPECT_EQ(p.at(5242), -7);
  EXPECT_EQ(p.at(5384), 90);
  // LinuxCNC needs U V W of every group: 0 where x4step has none.
  for (int n : {5167, 5169, 5187, 5189, 5217, 5219, 5227, 5229, 5387, 5389}) EXPECT_EQ(p.at(n), 0) << n;
  EXPECT_EQ(p.size(), 9u + 9u + 1u + 9u + 1u + 9u * 9u);
  EXPECT_EQ(m::coordinates_of(p), c);
  const std::string text = m::format_parameters(p);
  EXPECT_NE(text.find("5161\t1.000000\n5162\t2.000000\n"), std::string::npos) << text;
  EXPECT_NE(text.find("5220\t2.000000\n5221\t10.000000\n"), std::string::npos) << text;
  EXPECT_EQ(m::parse_parameters(text, "x.var"), p);
  // G92 values LinuxCNC keeps while 5210 is 0 (G92.2) do not apply.
  p[5210] = 0;
  EXPECT_EQ(m::coordinates_of(p).g92[g::Z], 0);
}

TEST(params, refuses_bad_lines) {
  EXPECT_EQ(m::parse_parameters("\n5221 1.5\n\n", "x.var").at(5221), 1.5);
  EXPECT_EQ(m::parse_parameters("  5221\t +2.5 \r\n", "x.var").at(5221), 2.5);
  for (const char *bad : {"5221\n", "5221 abc\n", "x 1\n", "5221=1\n", "-5 1\n", "5221 1.5 junk\n",
                          "5222 2,5\n", "4294967297 1\n", "5603 1\n", "5220 2\n", "5221 nan\n"}) {
    try {
      m::parse_parameters(std::string("5220 1\n") + bad, "x.var");
      ADD_FAILURE() << bad;
    } catch (const m::parameter_error &e) {
      EXPECT_EQ(std::string(e.what()).rfind("x.var:2: ", 0), 0u) << e.what();
    }
  }
}

TEST_F(params_dir, missing_file_is_zero_and_write_keeps_other_numbers) {
  const m::parameter_file f(path("m.var"));
  EXPECT_EQ(f.read(), g::coordinate_state{});
  // Nothing changed: no file made.
  f.update([](g::coordinate_state &) {});
  struct stat st;
  EXPECT_NE(::stat(path("m.var").c_str(), &st), 0);
  std::ofstream(path("m.var")) << "31\t7.000000\n5227\t3.000000\n5221\t1.000000\n";
  EXPECT_EQ(f.read().g5x[0][g::X], 1);
  f.update([](g::coordinate_state &c) { c.g5x[0][g::Z] = -12.25; });
  const std::string text = slurp(path("m.var"));
  EXPECT_NE(text.find("31\t7.000000\n"), std::string::npos) << text;    // a user parameter
  EXPECT_NE(text.find("5227\t3.000000\n"), std::string::npos) << text;  // G54 U
  EXPECT_NE(text.find("5221\t1.000000\n5222\t0.000000\n5223\t-12.250000\n"), std::string::npos) << text;
  EXPECT_EQ(f.read().g5x[0][g::Z], -12.25);
}

TEST_F(params_dir, replaced_atomically_by_rename) {
  const m::parameter_file f(path("m.var"));
  f.update([](g::coordinate_state &c) { c.g5x[0][g::X] = 1; });
  struct stat a, b;
  ASSERT_EQ(::stat(path("m.var").c_str(), &a), 0);
  f.update([](g::coordinate_state &c) { c.g5x[0][g::X] = 2; });
  ASSERT_EQ(::stat(path("m.var").c_str(), &b), 0);
  EXPECT_NE(a.st_ino, b.st_ino);  // a new file, not the old one rewritten
  EXPECT_EQ(std::system(("test $(ls -A " + dir_ + " | wc -l) -eq 2").c_str()), 0)
      << "only m.var and m.var.lock: no temporary file left";
  // A reader never sees a file half written, while a writer rewrites it:
  // it reads for as long as the writer runs.
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    try {
      for (int i = 0; i < 150; i++) f.update([i](g::coordinate_state &c) { c.g5x[0][g::X] = i + 3; });
    } catch (...) {
      ::_exit(1);
    }
    ::_exit(0);
  }
  int reads = 0, status = 0;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    const m::parameters p = f.read_all();
    EXPECT_EQ(p.size(), 110u) << "a file half written";
    reads++;
  }
  EXPECT_EQ(status, 0);
  EXPECT_GT(reads, 0);
  EXPECT_EQ(f.read().g5x[0][g::X], 152);
}

TEST_F(params_dir, two_writers_lose_nothing) {
  const m::parameter_file f(path("m.var"));
  constexpr int each = 100;
  pid_t pids[2];
  for (int w = 0; w < 2; w++) {
    pids[w] = ::fork();
    ASSERT_GE(pids[w], 0);
    if (pids[w] == 0) {
      try {
        for (int i = 0; i < each; i++)
          f.update([w](g::coordinate_state &c) { c.g5x[size_t(w)][g::X] += 1, c.g28[g::Y] += 1; });
      } catch (...) {
        ::_exit(1);  // not the rest of the test suite in the child
      }
      ::_exit(0);
    }
  }
  for (pid_t p : pids) {
    int status = 0;
    ::waitpid(p, &status, 0);
    EXPECT_EQ(status, 0);
  }
  const g::coordinate_state c = f.read();
  EXPECT_EQ(c.g5x[0][g::X], each);
  EXPECT_EQ(c.g5x[1][g::X], each);
  EXPECT_EQ(c.g28[g::Y], 2 * each);
}

TEST(params, apply_changes_keeps_others) {
  g::coordinate_state before, after, file;
  after.g5x[0][g::Z] = 5;  // this command: G54 Z
  file.g5x[0][g::X] = 7;   // another one meanwhile: G54 X
  m::apply_changes(file, before, after);
  EXPECT_EQ(file.g5x[0][g::X], 7);
  EXPECT_EQ(file.g5x[0][g::Z], 5);
  EXPECT_EQ(file.system, 0);
}

// The interpreter starts from a state and gives it back, in machine units.
TEST(params, interpreter_state) {
  g::coordinate_state s;
  s.g5x[0][g::Z] = -20;  // G54: work Z0 at machine Z -20
  s.g5x[1][g::X] = 100;
  ends e;
  g::coordinate_state after =
      run("G0 Z5\nG55 G0 X1\nG10 L2 P3 Y4\nG54 G0 Z0\nG28.1\nG92 X0\nG30.1\nM2\n", s, e);
  ASSERT_GE(e.at.size(), 3u);
  EXPECT_DOUBLE_EQ(e.at[0][g::Z], -15);
  EXPECT_DOUBLE_EQ(e.at[1][g::X], 101);
  EXPECT_DOUBLE_EQ(after.g5x[2][g::Y], 4);
  EXPECT_DOUBLE_EQ(after.g28[g::Z], -20);
  EXPECT_DOUBLE_EQ(after.g28[g::X], 101);
  EXPECT_DOUBLE_EQ(after.g92[g::X], 101);  // X was 101 in G54: G92 X0 makes it 0
  EXPECT_DOUBLE_EQ(after.g30[g::X], 101);
  EXPECT_EQ(after.system, 0);  // M2 goes back to G54, as LinuxCNC
  EXPECT_DOUBLE_EQ(after.g5x[0][g::Z], -20);
  // G10 L20: where the tool is becomes that work coordinate.
  ends e2;
  after = run("G0 Z-3\nG10 L20 P1 Z0\nM2\n", g::coordinate_state{}, e2);
  EXPECT_DOUBLE_EQ(after.g5x[0][g::Z], -3);
  // An inch machine keeps inches; the interpreter works in mm inside.
  g::coordinate_state in;
  in.g5x[0][g::X] = 1;  // inch
  ends e3;
  after = run("G21 G0 X25.4\nM2\n", in, e3, g::units::inch);
  EXPECT_DOUBLE_EQ(e3.at[0][g::X], 2);
  EXPECT_DOUBLE_EQ(after.g5x[0][g::X], 1);
  EXPECT_EQ(after.system, 0);
}

// The planner's extents in work coordinates, from the offsets in force.
TEST(params, work_extents) {
  std::istringstream good(
      "[X4STEP]\nARC_TOLERANCE = 0.01\nJUNCTION_DEVIATION = 0.02\n[TRAJ]\nCOORDINATES = XZ\nLINEAR_UNITS = "
      "mm\n"
      "[AXIS_X]\nMIN_LIMIT = -10\nMAX_LIMIT = 100\nMAX_VELOCITY = 20\nMAX_ACCELERATION = 200\n"
      "[AXIS_Z]\nMIN_LIMIT = -50\nMAX_LIMIT = 0\nMAX_VELOCITY = 10\nMAX_ACCELERATION = 100\n"
      "[JOINT_0]\nMOTOR = 1\nSCALE = 800\n[JOINT_1]\nMOTOR = 3\nSCALE = -400\n"
      "[RS274NGC]\nPARAMETER_FILE = m.var\n");
  const m::machine mc = m::read(good, "/some/dir/m.ini");
  EXPECT_EQ(mc.parameter_file, "/some/dir/m.var");
  struct none : m::planner_output {
    void segment(const x4step::segment &, const m::segment_info &) override {}
  } out;
  g::coordinate_state s;
  s.g5x[0][g::Z] = -30;
  g::coordinate_state after;
  std::istringstream prog("G0 Z2\nG1 X10 Z-1 F100\nG0 Z2\nM2\n");
  const m::plan_summary sum = m::plan_program(mc, prog, "p.ngc", out, g::pose{0, 0, -30}, s, &after);
  EXPECT_DOUBLE_EQ(sum.min[g::Z], -31);
  EXPECT_DOUBLE_EQ(sum.max[g::Z], -28);
  EXPECT_DOUBLE_EQ(sum.work_min[g::Z], -1);
  EXPECT_DOUBLE_EQ(sum.work_max[g::Z], 2);
  EXPECT_EQ(after, s);
}

// The machine file's keys for it: [RS274NGC] PARAMETER_FILE and [TRAJ] NO_FORCE_HOMING.
TEST(params, machine_file_keys) {
  const std::string base =
      "[X4STEP]\nARC_TOLERANCE = 0.01\nJUNCTION_DEVIATION = 0.02\n[TRAJ]\nCOORDINATES = X\nLINEAR_UNITS = "
      "mm\n"
      "[AXIS_X]\nMIN_LIMIT = -10\nMAX_LIMIT = 100\nMAX_VELOCITY = 20\nMAX_ACCELERATION = 200\n"
      "[JOINT_0]\nMOTOR = 1\nSCALE = 800\n";
  auto read = [](const std::string &text) {
    std::istringstream in(text);
    return m::read(in, "d/m.ini");
  };
  auto refused = [&](const std::string &text) {
    try {
      read(text);
    } catch (const m::error &e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  m::machine mc = read(base);
  EXPECT_EQ(mc.parameter_file, "");
  EXPECT_FALSE(mc.no_force_homing);
  mc = read(base + "[RS274NGC]\nPARAMETER_FILE = /var/lib/x4step/mill.var\n");
  EXPECT_EQ(mc.parameter_file, "/var/lib/x4step/mill.var");
  auto with_traj = [&](const std::string &line) {
    std::string t = base;
    return t.insert(t.find("[AXIS_X]"), line);
  };
  mc = read(with_traj("NO_FORCE_HOMING = 1\n"));
  EXPECT_TRUE(mc.no_force_homing);
  EXPECT_FALSE(read(with_traj("NO_FORCE_HOMING = 0\n")).no_force_homing);
  EXPECT_EQ(
      refused(base + "[RS274NGC]\nPARAMETER_FILE =\n"),
      "d/m.ini:16:17: [RS274NGC] PARAMETER_FILE: empty: give the parameter file's name (e.g. x4step.var)");
  // LinuxCNC's other [RS274NGC] keys are accepted with a warning (machines/README.md).
  EXPECT_EQ(refused(base + "[RS274NGC]\nSUBROUTINE_PATH = x\n"), "accepted");
  EXPECT_EQ(refused(with_traj("NO_FORCE_HOMING = 2\n")),
            "d/m.ini:7:19: [TRAJ] NO_FORCE_HOMING: '2': use a whole number 0..1");
}
