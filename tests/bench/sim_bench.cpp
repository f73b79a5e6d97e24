// SPDX-License-Identifier: GPL-2.0
// Simulated port benchmark (issue 19): a 4-axis 20 kHz move of 10 s
// (200000/150000/100000/50000 steps, no ramp) in virtual time, through the
// C++ API on "sim", without and with a VCD file of every pin change, each
// three times in turn (the best of each counts). Prints simulated steps
// per second of host CPU, the ratio to real time, and the VCD writer's
// cost per pin edge (the difference of the two, over the edges written).
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <string>

#include "x4step.hpp"

namespace {

constexpr long kSteps[4] = {200000, 150000, 100000, 50000};
constexpr double kMoveSeconds = 10.0;  // 200000 leader steps at 20 kHz

double cpu_seconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}

// One run; the CPU seconds from the open to the end of the close.
double run(const std::string &vcd) {
  if (vcd.empty())
    unsetenv("X4STEP_SIM_VCD");
  else
    setenv("X4STEP_SIM_VCD", vcd.c_str(), 1);
  const double t0 = cpu_seconds();
  {
    x4step::controller c("sim");
    c.load({{kSteps[0], kSteps[1], kSteps[2], kSteps[3]}, 20000, std::chrono::milliseconds(0)});
    c.start();
    c.wait();
    if (c.steps(x4step::axis(4)) != kSteps[3]) {
      std::fprintf(stderr, "sim_bench: the move made %lld steps on axis 4, not %ld\n",
                   c.steps(x4step::axis(4)), kSteps[3]);
      std::exit(1);
    }
  }
  return cpu_seconds() - t0;
}

long vcd_edges(const std::string &path) {
  std::ifstream in(path);
  long n = 0;
  for (std::string l; std::getline(in, l);) n += l.size() == 2 && (l[0] == '0' || l[0] == '1');
  return n;
}

}  // namespace

int main() {
  setenv("X4STEP_SIM_TIME", "virtual", 1);
  char dir[] = "/tmp/sim_bench.XXXXXX";
  if (!mkdtemp(dir)) {
    std::perror("sim_bench: mkdtemp");
    return 1;
  }
  const std::string vcd = std::string(dir) + "/run.vcd";
  double plain = 1e9, with_vcd = 1e9;
  for (int i = 0; i < 3; i++) {
    plain = std::min(plain, run(""));
    with_vcd = std::min(with_vcd, run(vcd));
  }
  const long edges = vcd_edges(vcd);
  unlink(vcd.c_str());
  rmdir(dir);
  long steps = 0;
  for (long s : kSteps) steps += s;
  std::printf(
      "simulated: %ld steps (4 axes, 20 kHz, %.0f s of motion) in %.1f ms of CPU: %.2f M steps/s, %.0fx real "
      "time\n",
      steps, kMoveSeconds, plain * 1e3, steps / plain / 1e6, kMoveSeconds / plain);
  std::printf("with VCD: %.1f ms of CPU, %ld pin edges written: %.1f ns per edge for the VCD writer\n",
              with_vcd * 1e3, edges, (with_vcd - plain) * 1e9 / edges);
  return 0;
}
