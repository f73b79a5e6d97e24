// SPDX-License-Identifier: GPL-2.0
#include "engine_ref.h"

#include <algorithm>
#include <cmath>

namespace x4test {

double ref_step_time(uint64_t steps, int freq_hz, int ramp_ms, uint64_t n) {
  const double f = freq_hz;
  const double r = ramp_ms / 1000.0;
  const double x = static_cast<double>(n);
  if (ramp_ms == 0) return x / f;
  const double a = f / r;       // steps/s^2
  const double na = f * r / 2;  // steps of one full ramp
  const double p = X4_PLATEAU_STEPS;
  if (steps == 0) {  // endless: accelerate, then cruise
    return x <= na ? std::sqrt(2 * x / a) : x / f + r / 2;
  }
  const double d = static_cast<double>(steps - 1);
  if (d >= 2 * na + p) {
    const double t_end = d / f + r;
    if (x <= na) return std::sqrt(2 * x / a);
    if (x <= d - na) return x / f + r / 2;
    return t_end - std::sqrt(2 * (d - x) / a);
  }
  if (d >= p + 2) {
    // Ramps of whole steps; an odd rest lengthens the plateau to p + 1.
    const double xa = std::floor((d - p) / 2);
    const double ta = std::sqrt(2 * xa / a);
    const double v = a * ta;
    const double t_end = 2 * ta + (d - 2 * xa) / v;
    if (x <= xa) return std::sqrt(2 * x / a);
    if (x <= d - xa) return ta + (x - xa) / v;
    return t_end - std::sqrt(2 * (d - x) / a);
  }
  const double v = std::min(f, std::sqrt(a));
  return x / v;
}

double ref_speed(uint64_t steps, int freq_hz, int ramp_ms, double x) {
  const double f = freq_hz;
  const double r = ramp_ms / 1000.0;
  if (ramp_ms == 0) return f;
  const double a = f / r;
  const double na = f * r / 2;
  const double p = X4_PLATEAU_STEPS;
  if (steps == 0) return x <= na ? std::sqrt(2 * a * x) : f;
  const double d = static_cast<double>(steps - 1);
  // The ramps' length: full, or the short move's floor((d - p) / 2) (its
  // plateau runs at the speed reached).
  const double xa = d >= 2 * na + p ? na : d >= p + 2 ? std::floor((d - p) / 2) : -1;
  if (xa < 0) return std::min(f, std::sqrt(a));
  if (x <= xa) return std::sqrt(2 * a * x);
  if (x <= d - xa) return std::sqrt(2 * a * xa);
  return std::sqrt(2 * a * (d - x));
}

x4_move Move(int32_t s1, int32_t s2, int32_t s3, int32_t s4, int freq, int ramp) {
  x4_move m{};
  m.steps[0] = s1;
  m.steps[1] = s2;
  m.steps[2] = s3;
  m.steps[3] = s4;
  m.freq_hz = freq;
  m.ramp_ms = ramp;
  return m;
}

x4_event fire(x4_engine &e, uint64_t now_ns) {
  const uint64_t due = x4_engine_due(&e);
  x4_engine_fire(&e, now_ns ? now_ns : due);
  return {due, e.data, e.ctl};
}

void record(x4_engine &e, Recording &rec, size_t max_events, const std::function<void()> &before_fire) {
  uint8_t data = e.data;
  bool moving = false;
  for (size_t i = 0; i < max_events && x4_engine_busy(&e); i++) {
    if (before_fire) before_fire();
    const x4_event ev = fire(e);
    rec.events.push_back(ev);
    const uint8_t changed = data ^ ev.data;
    for (int axis = 0; axis < X4_AXES; axis++) {
      if (changed & X4_CLK_BIT(axis)) {
        (ev.data & X4_CLK_BIT(axis) ? rec.rises : rec.falls)[axis].push_back(ev.t_ns);
      }
      if ((changed & X4_DIR_BIT(axis)) && moving) rec.dir_changes++;
    }
    moving = true;
    data = ev.data;
  }
}

}  // namespace x4test
