// SPDX-License-Identifier: GPL-2.0
// Engine benchmark: a 4-axis 20 kHz move with 50 ms ramps.
//   engine_bench            edge-time error against the reference, state size
//   engine_bench --per-step under callgrind: one stats dump per leader step
//   engine_bench --limit-hit under callgrind: the event at which a shared
//                limit stops four independent moves (the worst event)
// Run under `valgrind --tool=callgrind --toggle-collect=x4_engine_*` so that
// only the engine's own instructions are counted.
#include <valgrind/callgrind.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "engine_ref.h"

// Four axes' own moves toward E+ limits that share input 1; the input
// becomes active after 400 events: the event that sees it ends all four.
static int limit_hit() {
  x4_engine e;
  x4_engine_init(&e);
  x4_switches sw{};
  for (int i = 0; i < X4_AXES; i++) sw.plus[i] = 1;
  const x4_profile prof = {0, 0, 10000, 100000, 100000};
  const int32_t target[X4_AXES] = {100000, 90000, 80000, 70000};
  int ret = x4_switch_set(&e, &sw);
  for (int i = 0; i < X4_AXES; i++) ret |= x4_engine_set_profile(&e, i + 1, &prof);
  x4_switch_sense(&e, 0);
  ret |= x4_engine_goto(&e, 0x0f, target, false, 0);
  if (ret) return 1;
  for (int n = 0; n < 400; n++) x4_engine_fire(&e, x4_engine_due(&e));
  x4_switch_sense(&e, 1);
  while (e.cur->phase != X4_RISE) x4_engine_fire(&e, x4_engine_due(&e));
  CALLGRIND_ZERO_STATS;
  x4_engine_fire(&e, x4_engine_due(&e));
  CALLGRIND_DUMP_STATS_AT("limit hit");
  for (int i = 0; i < X4_AXES; i++)
    if (e.ch[i].phase != X4_IDLE && e.ch[i].phase != X4_END) return 1;
  return 0;
}

int main(int argc, char **argv) {
  if (argc > 1 && !std::strcmp(argv[1], "--limit-hit")) return limit_hit();
  const bool per_step = argc > 1 && !std::strcmp(argv[1], "--per-step");
  const x4_move move = {{20000, 15000, -10000, 5000}, 20000, 50};
  const uint64_t start = 0;
  x4_engine e;
  x4_engine_init(&e);

  int ret = x4_engine_load(&e, &move);
  ret |= x4_engine_start(&e, start);
  if (ret) return 1;

  const uint64_t origin = start + X4_DIR_SETUP_NS;
  double max_err = 0, sum_err = 0, prev_ideal = 0;
  uint64_t edges = 0, n = 0;
  bool high = false;
  while (x4_engine_busy(&e)) {
    if (per_step && !high) CALLGRIND_ZERO_STATS;  // a leader step: rise + fall
    const x4_event ev{x4_engine_due(&e), 0, 0};
    x4_engine_fire(&e, ev.t_ns);
    const uint8_t data = e.data;
    const bool clk = data & X4_CLK_BIT(0);
    if (clk == high) continue;  // start or end event
    high = clk;
    // Rising edge at the ideal step time; falling edge half way to the next.
    const double ideal_rise = x4test::ref_step_time(20000, 20000, 50, n) * 1e9;
    double ideal = ideal_rise;
    if (!clk) {
      const double next = n + 1 < 20000
                              ? x4test::ref_step_time(20000, 20000, 50, n + 1) * 1e9
                              : 2 * prev_ideal - x4test::ref_step_time(20000, 20000, 50, n - 1) * 1e9;
      ideal = (prev_ideal + next) / 2;
      if (per_step) CALLGRIND_DUMP_STATS_AT("step");
      n++;
    } else {
      prev_ideal = ideal_rise;
    }
    const double err = std::fabs(double(ev.t_ns - origin) - ideal);
    max_err = err > max_err ? err : max_err;
    sum_err += err;
    edges++;
  }
  if (!per_step) {
    std::printf("leader steps: %llu (axes %lld %lld %lld %lld)\n", (unsigned long long)n,
                (long long)e.steps[0], (long long)e.steps[1], (long long)e.steps[2], (long long)e.steps[3]);
    std::printf("edge-time error vs double reference: max %.1f ns, mean %.2f ns over %llu edges\n", max_err,
                sum_err / edges, (unsigned long long)edges);
    std::printf("engine state: %zu bytes (struct x4_engine)\n", sizeof(struct x4_engine));
  }
  return e.steps[0] == 20000 && e.steps[3] == 5000 ? 0 : 1;
}
