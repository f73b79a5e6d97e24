// SPDX-License-Identifier: GPL-2.0
// Path benchmark (issue 18): a circle of 5000 chords of 4 steps (0.05 mm
// at 80 steps/mm), streamed through a 256-segment queue at 10000 steps/s.
//   path_bench             fidelity: speeds and accelerations from the
//                          edges against the limits, speed at the chord
//                          junctions against the commanded speed
//   path_bench --chord N   chords of N steps instead of 4
//   path_bench --per-push  under callgrind --collect-atstart=no: one stats
//                          dump per appended segment (the planner's cost)
//   path_bench --unbounded every backward pass run through at each push
//                          (the planner before issue 28 bounded it)
//   path_bench --worst D   the planner's worst case instead of the circle:
//                          short segments streamed through a queue of D,
//                          shorter than their stop distance (every push
//                          raises every entry); with --per-push as above
//   path_bench --junctions junction and ramp fidelity: a path of 62
//                          segments against a double-precision reference
//                          of its plan; exits 1 if a bound is exceeded
//   path_bench --reference the circle (--chord N) against that reference,
//                          queued whole; figures only
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

// ---- junction and ramp fidelity (issue 18): a multi-segment path against
// a double-precision reference of its plan --------------------------------

// An irregular polygon of chords on an ellipse: chords of unequal lengths,
// some split into collinear pieces (junctions without a corner), top
// speeds and accelerations that change from segment to segment, corner
// limits by junction deviation (as x4step::junction_speed()), and two
// corners that stop. No chord reverses its leader axis (a reversing axis
// waits for its direction setup: not part of the plan).
std::vector<x4_segment> polygon() {
  constexpr int kCorners = 48;
  constexpr double kRx = 3000, kRy = 1900, kDeviation = 0.05 * kUnit;
  const uint32_t speeds[] = {6000, 9000, 12000, 4000, 15000};  // steps/s
  const uint32_t accels[] = {150000, 300000, 80000};           // steps/s^2
  std::vector<long> x, y;
  for (int k = 0; k <= kCorners; k++) {
    const double th = k == kCorners ? 2 * M_PI : 2 * M_PI * (k + 0.35 * std::sin(3.0 * k)) / kCorners;
    const long vx = std::lround(kRx * std::cos(th)), vy = std::lround(kRy * std::sin(th));
    if (k % 7 == 3 && !x.empty()) {  // collinear pieces of 1/6, 1/2 and 1/3 of the chord
      const long px = x.back(), py = y.back();
      for (double f : {1.0 / 6, 2.0 / 3}) {
        x.push_back(px + std::lround((vx - px) * f));
        y.push_back(py + std::lround((vy - py) * f));
      }
    }
    x.push_back(vx);
    y.push_back(vy);
  }
  std::vector<x4_segment> out;
  double pdx = 0, pdy = 0;
  for (size_t k = 1; k < x.size(); k++) {
    const long dx = x[k] - x[k - 1], dy = y[k] - y[k - 1];
    if (!dx && !dy) continue;
    const size_t m = out.size();
    x4_segment s{};
    s.steps[0] = int32_t(dx);
    s.steps[1] = int32_t(dy);
    const double len = std::hypot(dx, dy);
    s.length = uint32_t(std::lround(len * kUnit));
    s.v_max = speeds[m % 5] * kUnit;
    s.accel = accels[m % 3] * kUnit;
    s.tag = m;
    // Junction deviation (lib/path.cpp's junction_speed()), the corner
    // from the last segment's direction.
    double ve = 0;
    if (m) {
      const double cos_theta = -(pdx * dx + pdy * dy) / (std::hypot(pdx, pdy) * len);
      const double sin_half = std::sqrt(0.5 * (1 - cos_theta));
      ve = cos_theta < -0.999999 ? 4e9 : std::sqrt(s.accel * kDeviation * sin_half / (1 - sin_half));
    }
    s.v_entry = uint32_t(std::min(ve, 2147483647.0));
    if (m == 20 || m == 41) s.v_entry = 0;  // stops
    pdx = double(dx);
    pdy = double(dy);
    out.push_back(s);
  }
  return out;
}

int leader_of(const x4_segment &g) {
  int lead = 0;
  for (int i = 1; i < X4_AXES; i++)
    if (std::abs(g.steps[i]) > std::abs(g.steps[lead])) lead = i;
  return lead;
}

// The plan in double, from the segment records and the planner's rules
// (x4_path.c): each segment runs with its leader's whole steps/s^2 (what
// the timer runs, and what the plan uses); its entry is the highest its
// corner, its top speed and the stop of everything after it allow
// (backward from the last, which stops); the timer enters it at what the
// segment before could reach of that, and runs a trapezoid: up from its
// entry, cruise at its top speed, down to the next one's entry. Speeds in
// path units/s; `whole`: every leader speed rounded down to whole steps/s
// (docs/motion.md: leader speeds are whole steps/s), else exact.
struct RefSegment {
  double t0;          // s, when it starts (at its step 0, the last one before)
  double u;           // path units per leader step
  double a;           // path units/s^2
  double v0, vp, ve;  // entry, peak (cruise or the ramps' meeting), exit
  double len;
  // The time at path position x (0..len) from the start of the segment.
  double at(double x) const {
    const double xa = (vp * vp - v0 * v0) / (2 * a), xd = (vp * vp - ve * ve) / (2 * a);
    const double ta = (vp - v0) / a;
    if (x <= xa) return (std::sqrt(v0 * v0 + 2 * a * x) - v0) / a;
    if (x <= len - xd) return ta + (x - xa) / vp;
    const double tc = (len - xd - xa) / vp;
    return ta + tc + (vp - std::sqrt(std::max(0.0, ve * ve + 2 * a * (len - x)))) / a;
  }
  double duration() const { return at(len); }
};

std::vector<RefSegment> reference(const std::vector<x4_segment> &segs, double t_start, bool whole) {
  const size_t n = segs.size();
  std::vector<double> u(n), a(n), top(n), entry(n + 1, 0);
  for (size_t k = 0; k < n; k++) {
    const double steps = std::abs(segs[k].steps[leader_of(segs[k])]);
    u[k] = segs[k].length / steps;
    a[k] = std::floor(segs[k].accel / u[k]) * u[k];  // whole leader steps/s^2
    top[k] = segs[k].v_max;
    if (whole) top[k] = std::floor(top[k] / u[k]) * u[k];
  }
  for (size_t k = n; k-- > 0;)
    entry[k] = std::min({double(segs[k].v_entry), double(segs[k].v_max),
                         std::sqrt(entry[k + 1] * entry[k + 1] + 2 * a[k] * segs[k].length)});
  std::vector<RefSegment> out;
  double t = t_start, v_in = 0;
  for (size_t k = 0; k < n; k++) {
    const double len = segs[k].length;
    double ve = std::min({entry[k + 1], top[k], std::sqrt(v_in * v_in + 2 * a[k] * len)});
    if (whole) ve = std::floor(ve / u[k]) * u[k];
    const double vp = std::min(top[k], std::sqrt((v_in * v_in + ve * ve) / 2 + a[k] * len));
    RefSegment r{t, u[k], a[k], v_in, vp, ve, len};
    out.push_back(r);
    t += r.duration();
    v_in = ve;
    if (whole && k + 1 < n) v_in = std::floor(v_in / u[k + 1]) * u[k + 1];
  }
  return out;
}

struct Edge {
  double t;  // s
  size_t seg;
  uint32_t j;  // leader step of the segment, 1..n
};

// Runs the whole path (queued before it starts, so that the plan is the
// full queue's) and compares its leader edges with reference(). Prints
// the figures; `bounded`: returns 1 if one is out of its bound.
int fidelity(const std::vector<x4_segment> &segs, const char *what, bool bounded) {
  std::vector<x4_path_slot> q(8192);
  x4_engine e;
  x4_engine_init(&e);
  if (segs.size() > q.size() || x4_path_set_queue(&e, q.data(), uint32_t(q.size()))) return 1;
  // The whole path queued before it starts: the plan is the full queue's.
  for (const x4_segment &g : segs) {
    const int ret = x4_path_check(&e, &g);
    if (ret) {
      std::printf("segment %llu refused: %d\n", (unsigned long long)g.tag, ret);
      return 1;
    }
    x4_path_push(&e, &g);
  }
  const uint64_t start = 1000;
  x4_path_kick(&e, start);

  std::vector<Edge> edges;
  size_t cur = 0;
  uint32_t j = 0;
  uint8_t data = e.data;
  while (x4_engine_busy(&e)) {
    const uint64_t due = x4_engine_due(&e);
    x4_engine_fire(&e, due);
    const uint8_t rose = e.data & ~data & X4_CLK_MASK;
    data = e.data;
    if (cur < segs.size() && rose & X4_CLK_BIT(leader_of(segs[cur]))) {
      edges.push_back({due * 1e-9, cur, ++j});
      if (j == uint32_t(std::abs(segs[cur].steps[leader_of(segs[cur])]))) {
        cur++;
        j = 0;
      }
    }
  }
  if (cur != segs.size()) {
    std::printf("the path ended after %zu of %zu segments\n", cur, segs.size());
    return 1;
  }

  const double t0 = (start + X4_DIR_SETUP_NS) * 1e-9;
  const std::vector<RefSegment> whole = reference(segs, t0, true), exact = reference(segs, t0, false);
  // Edge times against the plan; the same from each segment's start as
  // the engine ran it (its step 0), which leaves out what came before.
  double err = 0, err_exact = 0, err_local = 0, seg_t0 = t0, last_err = 0;
  for (size_t k = 0; k < edges.size(); k++) {
    const Edge &g = edges[k];
    const RefSegment &w = whole[g.seg], &x = exact[g.seg];
    if (g.j == 1 && k) seg_t0 = edges[k - 1].t;
    last_err = (g.t - w.t0 - w.at(g.j * w.u)) * 1e9;
    err = std::max(err, std::fabs(last_err));
    err_exact = std::max(err_exact, std::fabs(g.t - x.t0 - x.at(g.j * x.u)) * 1e9);
    err_local = std::max(err_local, std::fabs(g.t - seg_t0 - w.at(g.j * w.u)) * 1e9);
  }
  // Speeds and accelerations from consecutive leader intervals (the
  // interval before step j of a segment lies in that segment). Allowance:
  // the one-step quantisation (leader speeds are whole steps/s: a step/s
  // of the faster leader's, in path units/s), and 1 ns of rounding of
  // each edge time.
  double speed = 0, acc = 0;
  for (size_t k = 2; k < edges.size(); k++) {
    const Edge &a = edges[k - 2], &b = edges[k - 1], &c = edges[k];
    const double dt1 = b.t - a.t, dt2 = c.t - b.t;
    const double v1 = whole[b.seg].u / dt1, v2 = whole[c.seg].u / dt2;
    const double ns = std::max(v1, v2) * 2e-9 / std::min(dt1, dt2);
    speed = std::max(speed, (v2 - v2 * 1e-9 / dt2) / segs[c.seg].v_max);
    const double allowance = std::max(whole[b.seg].u, whole[c.seg].u) + ns;
    const double limit = std::max(segs[b.seg].accel, segs[c.seg].accel);
    acc = std::max(acc, (std::fabs(v2 - v1) - allowance) / ((dt1 + dt2) / 2) / limit);
  }
  std::printf("path: %s: %zu segments, %zu leader steps, %.3f s\n", what, segs.size(), edges.size(),
              edges.back().t - t0);
  std::printf(
      "edge times vs the plan in double (whole leader steps/s): max error %.1f ns (bound 50); "
      "at the end %+.1f ns, %+.2f ns per segment; within a segment %.1f ns\n",
      err, last_err, last_err / double(segs.size()), err_local);
  std::printf("edge times vs the plan at exact speeds (no whole steps/s): max error %.1f us\n",
              err_exact * 1e-3);
  std::printf("speed: at most %.6f of the segment's v_max (bound 1, less 1 ns of edge rounding)\n", speed);
  std::printf("acceleration: at most %.3f of the limit beyond 1 step/s and 2 ns of rounding (bound 1)\n",
              std::max(0.0, acc));
  const bool ok = err <= 50 && speed <= 1 && acc <= 1;
  if (!ok)
    std::printf("%s\n", bounded ? "FAILED: a bound is exceeded" : "(a bound is exceeded: not enforced here)");
  return ok || !bounded ? 0 : 1;
}

}  // namespace

// The planner's worst case (issue 28 item 6): D + 2048 segments of 4
// steps at 20000 steps/s and 1000 steps/s^2 (200 000 steps to stop)
// streamed through a queue of D: every push can raise every entry. The
// pass the pushes leave over goes on every 4 ms as in the module.
int worst(uint32_t depth, bool per_push, bool unbounded) {
  std::vector<x4_path_slot> q(depth);
  x4_engine e;
  x4_engine_init(&e);
  if (x4_path_set_queue(&e, q.data(), depth)) return 1;
  x4_segment s{};
  s.steps[0] = 4;
  s.length = 4;
  s.v_max = 20000;
  s.accel = 1000;
  s.v_entry = s.v_max;
  const size_t n = depth + 2048;
  size_t next = 0;
  uint64_t now = 1000, most = 0, work_at = 0;
  while (next < n || x4_engine_busy(&e)) {
    if (!unbounded && now >= work_at) {  // the module's work item, a jiffy at 250 Hz
      x4_path_plan(&e, X4_PATH_PLAN_WORK);
      if (e.path.state != X4_PATH_IDLE) x4_path_kick(&e, now);
      work_at = now + 4000000;
    }
    while (next < n && x4_path_room(&e)) {
      if (x4_path_check(&e, &s)) return 1;
      const uint64_t before = e.path.planned;
      if (per_push) {
        CALLGRIND_ZERO_STATS;
        CALLGRIND_TOGGLE_COLLECT;
      }
      x4_path_push(&e, &s);
      if (unbounded)
        while (x4_path_plan(&e, UINT32_MAX)) {
        }
      if (per_push) {
        CALLGRIND_TOGGLE_COLLECT;
        CALLGRIND_DUMP_STATS_AT("push");
      }
      most = std::max(most, e.path.planned - before);
      x4_path_kick(&e, now);
      next++;
    }
    if (!x4_engine_busy(&e)) continue;
    now = x4_engine_due(&e);
    x4_engine_fire(&e, now);
  }
  std::printf("worst case, depth %u: %zu segments of 4 steps, %.3f s; most entries a push planned: %llu\n",
              depth, n, (now - 1000) * 1e-9, (unsigned long long)most);
  return 0;
}

int main(int argc, char **argv) {
  bool per_push = false, reference_run = false, unbounded = false;
  uint32_t worst_depth = 0;
  for (int i = 1; i < argc; i++) {
    if (!std::strcmp(argv[i], "--junctions"))
      return fidelity(
          polygon(), "an irregular polygon (corners by junction deviation, 2 stops, collinear pieces)", true);
    else if (!std::strcmp(argv[i], "--reference"))
      reference_run = true;
    else if (!std::strcmp(argv[i], "--per-push"))
      per_push = true;
    else if (!std::strcmp(argv[i], "--unbounded"))
      unbounded = true;
    else if (!std::strcmp(argv[i], "--worst") && i + 1 < argc)
      worst_depth = uint32_t(std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--chord") && i + 1 < argc)
      chord_steps = std::atof(argv[++i]);
    else
      return 2;
  }
  if (worst_depth) return worst(worst_depth, per_push, unbounded);
  const std::vector<x4_segment> segs = circle();
  if (reference_run) return fidelity(segs, "the circle, queued whole", false);
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
      if (per_push) {
        CALLGRIND_ZERO_STATS;
        CALLGRIND_TOGGLE_COLLECT;
      }
      x4_path_push(&e, &segs[next]);
      if (unbounded)
        while (x4_path_plan(&e, UINT32_MAX)) {
        }
      if (per_push) {
        CALLGRIND_TOGGLE_COLLECT;
        CALLGRIND_DUMP_STATS_AT("push");
      }
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
