// SPDX-License-Identifier: GPL-2.0
// Path benchmark (issue 18): a circle of 5000 chords of 4 steps (0.05 mm
// at 80 steps/mm), streamed through a 256-segment queue at 10000 steps/s.
//   path_bench             fidelity: speeds and accelerations from the
//                          edges against the limits, speed at the chord
//                          junctions against the commanded speed
//   path_bench --chord N   chords of N steps instead of 4
//   path_bench --per-push  under callgrind: one stats dump per appended
//                          segment (the planner's cost)
// Run under `valgrind --tool=callgrind --toggle-collect=x4_engine_fire`
// for the engine's cost per leader step in path mode.
#include <valgrind/callgrind.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "engine_ref.h"

namespace {

constexpr int kChords = 5000;
double chord_steps = 4;              // the radius: 2 pi r / 5000 chords
constexpr uint32_t kUnit = 1000;     // path units per step
constexpr uint32_t kSpeed = 10000;   // steps/s along the path
constexpr uint32_t kAccel = 200000;  // steps/s^2

std::vector<x4_segment> circle() {
  std::vector<x4_segment> out;
  const double radius = chord_steps * kChords / (2 * M_PI);
  long px = std::lround(radius), py = 0;
  for (int k = 1; k <= kChords; k++) {
    const long x = std::lround(radius * std::cos(2 * M_PI * k / kChords));
    const long y = std::lround(radius * std::sin(2 * M_PI * k / kChords));
    x4_segment s{};
    s.steps[0] = int32_t(x - px);
    s.steps[1] = int32_t(y - py);
    s.length = uint32_t(std::lround(std::hypot(x - px, y - py) * kUnit));
    s.v_max = kSpeed * kUnit;
    s.accel = kAccel * kUnit;
    s.v_entry = s.v_max;  // 0.07 degree corners: far above the feed
    px = x;
    py = y;
    if (s.steps[0] || s.steps[1]) out.push_back(s);
  }
  return out;
}

}  // namespace

int main(int argc, char **argv) {
  bool per_push = false;
  for (int i = 1; i < argc; i++) {
    if (!std::strcmp(argv[i], "--per-push"))
      per_push = true;
    else if (!std::strcmp(argv[i], "--chord") && i + 1 < argc)
      chord_steps = std::atof(argv[++i]);
    else
      return 2;
  }
  const std::vector<x4_segment> segs = circle();
  std::vector<x4_path_slot> q(256);
  x4_engine e;
  x4_engine_init(&e);
  if (x4_path_set_queue(&e, q.data(), uint32_t(q.size()))) return 1;

  // Leader step times and path positions, from the clock edges.
  std::vector<double> t, s;
  std::vector<size_t> seg_of;
  size_t next = 0, cur = 0;
  uint32_t done_in_seg = 0;
  uint8_t data = 0;
  uint64_t starved_events = 0;
  double base = 0;
  uint64_t now = 0;
  while (next < segs.size() || x4_engine_busy(&e)) {
    while (next < segs.size() && x4_path_room(&e)) {
      if (x4_path_check(&e, &segs[next])) return 1;
      if (per_push) CALLGRIND_ZERO_STATS;
      x4_path_push(&e, &segs[next]);
      if (per_push) CALLGRIND_DUMP_STATS_AT("push");
      x4_path_kick(&e, now);
      next++;
    }
    if (!x4_engine_busy(&e)) {
      starved_events++;
      continue;
    }
    const uint64_t due = x4_engine_due(&e);
    x4_engine_fire(&e, due);
    now = due;
    const uint8_t rose = e.data & ~data & X4_CLK_MASK;
    data = e.data;
    if (!rose) continue;
    const x4_segment &g = segs[cur];
    const int lead = std::abs(g.steps[0]) >= std::abs(g.steps[1]) ? 0 : 1;
    if (!(rose & X4_CLK_BIT(lead))) continue;
    const uint32_t n = uint32_t(std::abs(g.steps[lead]));
    done_in_seg++;
    t.push_back(due * 1e-9);
    s.push_back(base + double(g.length) / kUnit * done_in_seg / n);
    seg_of.push_back(cur);
    if (done_in_seg == n) {
      base += double(g.length) / kUnit;
      cur++;
      done_in_seg = 0;
    }
  }
  if (per_push) return 0;

  double worst_acc = 0, fastest = 0, junction_min = 1e9, junction_max = 0;
  for (size_t k = 2; k < t.size(); k++) {
    const double v1 = (s[k - 1] - s[k - 2]) / (t[k - 1] - t[k - 2]),
                 v2 = (s[k] - s[k - 1]) / (t[k] - t[k - 1]);
    // One step/s of quantisation, and 1 ns of rounding per edge.
    const double slack = 2 + std::max(v1, v2) * 2e-9 / std::min(t[k] - t[k - 1], t[k - 1] - t[k - 2]);
    const double r = (std::fabs(v2 - v1) - slack) / ((t[k] - t[k - 2]) / 2) / kAccel;
    worst_acc = std::max(worst_acc, r);
    fastest = std::max(fastest, v2);
    // Junctions in the middle of the circle (cruising): the interval that crosses one.
    if (seg_of[k] != seg_of[k - 1] && seg_of[k] > 100 && seg_of[k] + 100 < segs.size()) {
      junction_min = std::min(junction_min, v2 / kSpeed);
      junction_max = std::max(junction_max, v2 / kSpeed);
    }
  }
  std::printf(
      "path: %zu chords, %zu leader steps, %.3f s; segments completed %llu, queue starved %llu times\n",
      segs.size(), t.size(), t.back() - t.front(), (unsigned long long)e.path.done,
      (unsigned long long)starved_events);
  std::printf(
      "fidelity: fastest %.1f steps/s (limit %u); largest acceleration %.3f of the limit (beyond 2 steps/s "
      "of quantisation)\n",
      fastest, kSpeed, std::max(0.0, worst_acc));
  std::printf("junctions while cruising: path speed %.4f .. %.4f of the commanded\n", junction_min,
              junction_max);
  int32_t x = int32_t(e.pos_base[0] + uint32_t(e.steps[0])),
          y = int32_t(e.pos_base[1] + uint32_t(e.steps[1]));
  std::printf("end: %d %d (the start: 0 0)\n", x, y);
  return x == 0 && y == 0 && t.size() > 0 ? 0 : 1;
}
