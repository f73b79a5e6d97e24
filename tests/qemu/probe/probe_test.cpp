// SPDX-License-Identifier: GPL-2.0
// In-guest test of probing (issue 31, G38.2..G38.5) on the test-only
// virtual port tests/qemu/fixtures/x4vport: a probe switch on the machine
// at Z = 1000 (input 3), and probing segments of x4step::path through the
// module. The observer is the port's write trace: the status entry that
// the switch makes follows the data write of the step that reached it, so
// the Z steps written before that entry are the step at which the input
// changed; the module's latch (X4STEP_GET_PROBE) must be that step, at
// every feed, toward and away. Also: the path stops there (braking) and is
// flushed; a start with the probe tripped writes no step; a probing
// segment that ends without a trip lets the path go on; without a probe
// input the module refuses the segment (EINVAL).
//
// Prints PASS/FAIL per check and figures as `info:` lines.
#include <linux/x4step.h>

#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "check.hpp"
#include "vport.hpp"
#include "x4step.hpp"
#include "x4step_path.hpp"

using namespace std::chrono_literals;

namespace {

using guest::Check;
using guest::F;
using guest::kV;
using guest::Put;
using guest::Slurp;
using x4step::axis;
using x4step::probe_mode;

constexpr long long kAt = 1000;  // the probe: Z at 1000 and above
constexpr unsigned kInput = 3;   // X4GetIn bit 2 (pin 12)

long long MachineZ() {
  std::istringstream in(Slurp(kV + "positions"));
  long long p[4] = {0, 0, 0, 0};
  for (auto &v : p) in >> v;
  return p[2];
}

// What the trace since the last clear shows: Z's signed steps written
// before the first status change, and in all; data writes with a clock
// edge.
struct Seen {
  long long before = 0, total = 0;
  bool changed = false;
  long clock_writes = 0;
};

Seen Trace() {
  Seen s;
  std::istringstream in(Slurp(kV + "trace"));
  unsigned long long t;
  char reg;
  std::string val;
  unsigned prev = 0;
  while (in >> t >> reg >> val) {
    const unsigned v = std::strtoul(val.c_str(), nullptr, 16);
    if (reg == 's') {
      s.changed = true;  // only the probe switch changes the status here
      continue;
    }
    if (reg != 'd') continue;
    if ((v & ~prev) & 0xaa) s.clock_writes++;
    if ((v & ~prev) & 0x20) {  // Z's clock rose: a step in its direction pin's sense
      const int step = (v & 0x10) ? 1 : -1;
      s.total += step;
      if (!s.changed) s.before += step;
    }
    prev = v;
  }
  return s;
}

x4step::segment Seg(long z, long x, std::uint32_t feed, probe_mode m = probe_mode::none) {
  return x4step::segment{}
      .steps(axis(3), z)
      .steps(axis(1), x)
      .length(static_cast<std::uint32_t>(std::labs(z)))
      .top_speed(feed)
      .accel(100000)
      .tag(static_cast<std::uint64_t>(feed))
      .probe(m);
}

// One probing segment from where Z stands, observed from the trace.
void Probe(x4step::controller &c, x4step::path &path, long z, std::uint32_t feed, probe_mode m) {
  const char *dir = m == probe_mode::toward ? "toward" : "away";
  const long coord0 = c.get_axes()[axis(3)].position;
  const long long mach0 = MachineZ();
  Put(kV + "clear", "1\n");
  path.append(Seg(z, z / 4, feed, m));
  Check(path.wait(60s), F("%s at %u steps/s: the path stands", dir, feed));
  const x4step::probe_latch l = path.probe();
  const Seen s = Trace();
  const long long expect_machine = m == probe_mode::toward ? kAt : kAt - 1;
  Check(l.tripped && s.changed,
        F("%s at %u steps/s: tripped (the switch changed: %d)", dir, feed, s.changed));
  Check(l.steps[2] - coord0 == s.before,
        F("%s at %u steps/s: latch %ld is the step the input changed at (%+lld steps written before it)", dir,
          feed, l.steps[2], s.before));
  Check(mach0 + s.before == expect_machine,
        F("%s at %u steps/s: the machine changed the input at Z = %lld", dir, feed, mach0 + s.before));
  const long long past = std::llabs(s.total - s.before);
  std::printf("info: %s at %u steps/s: %lld steps braking past the change\n", dir, feed, past);
  Check(past <= static_cast<long long>(feed) * feed / (2 * 100000) + 2,
        F("%s at %u steps/s: stopped within the brake (%lld steps)", dir, feed, past));
  Check(std::labs(s.total) < std::labs(z),
        F("%s at %u steps/s: stopped before the segment's end", dir, feed));
  const x4step::path_status st = path.status();
  Check(st.state == x4step::path_state::idle && st.queued == 0, F("%s: the queue is flushed", dir));
  bool refused = false;
  try {
    path.append(Seg(10, 0, 1000));
  } catch (const x4step::error &e) {
    refused = e.code() == x4step::make_error_code(x4step::errc::not_active);
  }
  Check(refused, F("%s: append refused (not_active) until clear()", dir));
  path.clear();
}

void TestProbe(x4step::controller &c) {
  std::printf("== probing\n");
  Put(kV + "positions", "0 0 0 0\n");
  Check(Put(kV + "switches", "clear;add 3 2 above 1000 0 no\n"), "x4vport: a probe on Z at 1000, input 3");
  x4step::path path(c);
  bool refused = false;
  try {
    path.append(Seg(100, 0, 1000, probe_mode::toward));
  } catch (const x4step::error &e) {
    refused = e.code() == x4step::make_error_code(x4step::errc::param_fail);
  }
  Check(refused, "no probe input: a probing segment is refused (EINVAL)");
  path.configure(x4step::path_config{}.probe_input(kInput, false));
  Check(path.config().probe_input() == kInput, "the probe input reads back");
  for (const std::uint32_t feed : {300u, 4000u, 30000u}) {
    // From 2000 below the probe: an 8000-step segment reaches it at its
    // top speed, or 20000 steps/s (2000 steps into its ramp), and stops
    // well before its end.
    const long long z = MachineZ();
    if (z != kAt - 2000) {
      path.append(Seg(static_cast<long>(kAt - 2000 - z), 0, 20000));
      path.wait(60s);
    }
    Probe(c, path, 8000, feed, probe_mode::toward);
    Probe(c, path, -8000, feed, probe_mode::away);
  }
  // On the probe, a toward segment: no step written, the latch where Z stands.
  path.append(Seg(static_cast<long>(kAt + 200 - MachineZ()), 0, 20000));
  path.wait(60s);
  const long coord = c.get_axes()[axis(3)].position;
  Put(kV + "clear", "1\n");
  path.append(Seg(500, 0, 5000, probe_mode::toward));
  path.wait(60s);
  const x4step::probe_latch l = path.probe();
  const Seen s = Trace();
  Check(l.tripped && l.steps[2] == coord && s.clock_writes == 0,
        F("tripped at the start: latch %ld at %ld, %ld clock writes", l.steps[2], coord, s.clock_writes));
  path.clear();
  // Away from the switch 100 steps: it stays active, no trip, the path goes on.
  Put(kV + "clear", "1\n");
  path.append({Seg(100, 0, 2000, probe_mode::away), Seg(-50, 0, 2000)});
  Check(path.wait(60s), "no trip: the path stands at its end");
  const x4step::probe_latch n = path.probe();
  const x4step::path_status st = path.status();
  Check(!n.tripped && n.tag == 2000 && Trace().total == 50,
        F("no trip: latch not tripped, tag %llu, Z %+lld (both segments ran)",
          static_cast<unsigned long long>(n.tag), Trace().total));
  Check(st.state == x4step::path_state::idle && st.queued == 0, "no trip: the path ran to its end");
  Put(kV + "switches", "clear\n");
}

}  // namespace

int main() {
  setvbuf(stdout, nullptr, _IOLBF, 0);
  const int port = guest::VportNumber();
  if (port < 0) return guest::Finish("probe_test");
  try {
    x4step::controller c("/dev/x4step" + std::to_string(port));
    TestProbe(c);
  } catch (const std::exception &e) {
    Check(false, std::string("unexpected exception: ") + e.what());
  }
  return guest::Finish("probe_test");
}
