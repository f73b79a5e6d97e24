// SPDX-License-Identifier: GPL-2.0
// x4ctl gcode --svg (toolpath_svg.hpp).
#include "toolpath_svg.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "cli.hpp"
#include "machine_io.hpp"

namespace x4ctl {

namespace {

using g::pose;

// Pixels: the top view fits top_w x top_h, the side view is side_min..side_max high.
constexpr double left_px = 70, top_px = 60, top_w = 640, top_h = 440, gap_px = 64;
constexpr double side_min = 90, side_max = 240, legend_w = 330;

// Colours: planned cuts blue (a pale band under a run's positions), rapids
// grey and dashed, the motors' positions dark, planned but not done orange.
constexpr const char *cut_colour = "#1f77b4", *band_colour = "#b9d4ea", *rapid_colour = "#8c8c8c",
                     *done_colour = "#0b2545", *not_done_colour = "#f07f0c", *grid_colour = "#e4e4e4";
constexpr const char *rapid_dash = "6 4", *done_rapid_dash = "3 3";

std::string xml_text(const std::string &s) {
  std::string o;
  for (char ch : s) {
    if (ch == '<')
      o += "&lt;";
    else if (ch == '>')
      o += "&gt;";
    else if (ch == '&')
      o += "&amp;";
    else if (ch == '"')
      o += "&quot;";
    else
      o += ch;
  }
  return o;
}

// A coordinate in a path: up to 10 significant digits, never "-0".
std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.10g", v + 0.0);
  return b;
}

// A label on a grid of this step: as many decimals as the step has.
std::string label(double v, double step) {
  const int decimals = std::max(0, int(std::ceil(-std::log10(step) - 1e-9)));
  char b[32];
  std::snprintf(b, sizeof b, "%.*f", decimals, std::fabs(v) < step * 1e-6 ? 0.0 : v);
  return b;
}

// An axis of a view: the range framed on whole grid steps.
struct range {
  double lo = 0, hi = 0;
  bool any = false;
  void add(double v) {
    lo = any ? std::min(lo, v) : v;
    hi = any ? std::max(hi, v) : v;
    any = true;
  }
  double span() const { return hi - lo; }
};

struct frame {
  double lo, hi, step;
};

// On whole steps, with a margin of pad either side: the path clear of the frame.
frame frame_on(const range &r, double step, double pad) {
  double lo = std::floor((r.lo - pad) / step + 1e-9) * step,
         hi = std::ceil((r.hi + pad) / step - 1e-9) * step;
  if (hi - lo < step * 0.5) lo -= step, hi += step;  // a flat axis: a step either side
  return {lo, hi, step};
}

// A view: horizontal axis h, vertical v, their frames, px per unit, where.
struct view {
  const char *id, *name;
  size_t h, v;
  frame fh, fv;
  double kh, kv;
  double x0, y0;  // the frame's top left corner, px
  double width() const { return (fh.hi - fh.lo) * kh; }
  double height() const { return (fv.hi - fv.lo) * kv; }
  double px(double a) const { return x0 + (a - fh.lo) * kh; }
  double py(double b) const { return y0 + (fv.hi - b) * kv; }
};

// The segments i with rapid == want (all when only_from is set: from it
// on), as one path's d: "M x,y L x,y ...", a new M where a run breaks.
std::string path_d(const view &w, const std::vector<pose> &pts, const std::vector<bool> &rapid, bool want,
                   size_t from, size_t to) {
  std::string d;
  bool open = false;
  for (size_t i = from; i < to; i++) {
    if (rapid[i] != want) {
      open = false;
      continue;
    }
    if (!open) d += "M" + num(pts[i][w.h]) + "," + num(pts[i][w.v]) + " ";
    d += "L" + num(pts[i + 1][w.h]) + "," + num(pts[i + 1][w.v]) + " ";
    open = true;
  }
  return d;
}

void path_element(std::ostream &o, const char *cls, const std::string &d, const char *colour, double width,
                  const char *dash) {
  if (d.empty()) return;
  o << "<path class=\"" << cls << "\" fill=\"none\" stroke=\"" << colour << "\" stroke-width=\"" << width
    << "\" stroke-linejoin=\"round\" stroke-linecap=\"round\"";
  if (dash) o << " stroke-dasharray=\"" << dash << "\"";
  o << " vector-effect=\"non-scaling-stroke\" d=\"" << d << "\"/>\n";
}

double distance_to_segment(const pose &p, const pose &a, const pose &b) {
  double dot = 0, len2 = 0;
  for (size_t k : {g::X, g::Y, g::Z}) {
    dot += (p[k] - a[k]) * (b[k] - a[k]);
    len2 += (b[k] - a[k]) * (b[k] - a[k]);
  }
  const double t = len2 > 0 ? std::clamp(dot / len2, 0.0, 1.0) : 0;
  double d2 = 0;
  for (size_t k : {g::X, g::Y, g::Z}) {
    const double d = p[k] - a[k] - t * (b[k] - a[k]);
    d2 += d * d;
  }
  return std::sqrt(d2);
}

}  // namespace

double round_up_125(double x) {
  if (!(x > 0)) return 1;
  const double mag = std::pow(10.0, std::floor(std::log10(x)));
  const double r = x / mag;
  return (r <= 1 + 1e-9 ? 1 : r <= 2 + 1e-9 ? 2 : r <= 5 + 1e-9 ? 5 : 10) * mag;
}

// From three quarters of span / lines up: about lines steps, rather more than fewer.
double grid_step(double span, int lines) { return span > 0 ? round_up_125(0.75 * span / lines) : 1; }

void toolpath_plot::done(const pose &p, std::uint64_t running) {
  if (done_.empty() || done_.back().at != p) done_.push_back({p, running});
}

toolpath_plot::deviation toolpath_plot::largest_deviation() const {
  deviation worst;
  const size_t n = planned_.size();
  if (n == 0) return worst;
  auto from = [&](size_t i) -> const pose & { return i == 0 ? start_ : planned_[i - 1].end; };
  for (const sample &s : done_) {
    // The segment that ran at the status read, and those around it: the
    // position is read just after the status.
    const size_t r = size_t(std::min<std::uint64_t>(s.running, n - 1));
    double best = INFINITY;
    int line = 0;
    for (size_t i = r >= 2 ? r - 2 : 0; i <= std::min(n - 1, r + 2); i++) {
      const double d = distance_to_segment(s.at, from(i), planned_[i].end);
      if (d < best) best = d, line = planned_[i].line;
    }
    if (best > worst.distance) worst = {best, line};
  }
  return worst;
}

void toolpath_plot::write(const std::string &path, const std::string &units, const std::string &title) const {
  const bool run = !done_.empty();
  // Work coordinates: the start and the segments' ends, then the positions.
  std::vector<pose> pts;
  std::vector<bool> rapid;
  auto work = [&](pose p) {
    for (size_t a = 0; a < g::n_axes; a++) p[a] -= origin_[a];
    return p;
  };
  pts.push_back(work(start_));
  for (const step &s : planned_) {
    pts.push_back(work(s.end));
    rapid.push_back(s.rapid);
  }
  std::vector<pose> motors;
  std::vector<bool> motors_rapid;  // the segment running at that position was a rapid
  for (const sample &s : done_) {
    motors.push_back(work(s.at));
    motors_rapid.push_back(!planned_.empty() &&
                           planned_[std::min<size_t>(s.running, planned_.size() - 1)].rapid);
  }

  // Framed on the program (its segments' ends, not where the machine
  // stood before it) and on work zero.
  range rx, ry, rz;
  for (size_t i = 1; i < pts.size(); i++) rx.add(pts[i][g::X]), ry.add(pts[i][g::Y]), rz.add(pts[i][g::Z]);
  rx.add(0), ry.add(0), rz.add(0);
  const double span = std::max({rx.span(), ry.span(), 1e-3}), step = grid_step(span, 8);
  view top{
      "top", "top view", g::X,    g::Y,  frame_on(rx, step, 0.02 * span), frame_on(ry, step, 0.02 * span),
      0,     0,          left_px, top_px};
  const double k = std::min(top_w / (top.fh.hi - top.fh.lo), top_h / (top.fv.hi - top.fv.lo));
  top.kh = top.kv = k;
  // The side view under it: X as above, Z at true scale unless that is
  // too flat or too high to read.
  const double zspan = std::max(rz.span(), step * 1e-3);
  const frame fz = frame_on(rz, grid_step(zspan, 4), 0.02 * zspan);
  // Z's own scale: a round multiple (or fraction) of X's.
  const double true_h = (fz.hi - fz.lo) * k;
  double z_ratio = 1;
  if (true_h < side_min)
    z_ratio = round_up_125(side_min / true_h);
  else if (true_h > side_max)
    z_ratio = 1 / round_up_125(true_h / side_max);
  view side{"side", "side view", g::X,        g::Z,    top.fh,
            fz,     k,           k * z_ratio, left_px, top_px + top.height() + gap_px};
  const bool z_true = std::fabs(z_ratio - 1) < 1e-9;

  const double legend_x = left_px + top.width() + 50;
  const double w = legend_x + legend_w, h = std::max(side.y0 + side.height() + 50, top_px + 360);
  std::ostringstream o;
  o << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << num(w) << "\" height=\"" << num(h)
    << "\" viewBox=\"0 0 " << num(w) << " " << num(h) << "\" font-family=\"sans-serif\" font-size=\"12\">\n"
    << "<title>" << xml_text(title) << "</title>\n"
    << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<text x=\"" << left_px << "\" y=\"24\" font-size=\"15\" font-weight=\"bold\">" << xml_text(title)
    << "</text>\n";

  const char *const letters = "XYZABC";
  auto draw_view = [&](const view &v) {
    o << "<g id=\"" << v.id << "\">\n"
      << "<text x=\"" << num(v.x0) << "\" y=\"" << num(v.y0 - 8) << "\" font-weight=\"bold\">" << v.name
      << ": " << letters[v.h] << " right, " << letters[v.v] << " up (" << xml_text(units);
    if (v.id == std::string("side"))
      o << (z_true ? ", true scale" : ", Z scale " + number(z_ratio) + " times X's");
    o << ")</text>\n";
    // Gridlines at every step, labelled.
    o << "<g class=\"grid\" stroke=\"" << grid_colour << "\" stroke-width=\"1\">\n";
    for (const bool horiz : {true, false}) {
      const frame &f = horiz ? v.fh : v.fv;
      const long n = std::lround((f.hi - f.lo) / f.step);
      for (long i = 0; i <= n; i++) {
        const double a = f.lo + double(i) * f.step;
        if (horiz)
          o << "<line x1=\"" << num(v.px(a)) << "\" y1=\"" << num(v.y0) << "\" x2=\"" << num(v.px(a))
            << "\" y2=\"" << num(v.y0 + v.height()) << "\"/>\n";
        else
          o << "<line x1=\"" << num(v.x0) << "\" y1=\"" << num(v.py(a)) << "\" x2=\"" << num(v.x0 + v.width())
            << "\" y2=\"" << num(v.py(a)) << "\"/>\n";
      }
    }
    o << "</g>\n<g class=\"labels\" font-size=\"11\" fill=\"#444\">\n";
    for (const bool horiz : {true, false}) {
      const frame &f = horiz ? v.fh : v.fv;
      const long n = std::lround((f.hi - f.lo) / f.step);
      // Every label unless they would crowd: then every other one.
      const double gap = f.step * (horiz ? v.kh : v.kv);
      const long every = gap < (horiz ? 44 : 16) ? 2 : 1;
      for (long i = 0; i <= n; i++) {
        const double a = f.lo + double(i) * f.step;
        if (i % every && i != n) continue;
        o << "<text class=\"label\" data-axis=\"" << letters[horiz ? v.h : v.v] << "\" data-value=\""
          << label(a, f.step) << "\"";
        if (horiz)
          o << " x=\"" << num(v.px(a)) << "\" y=\"" << num(v.y0 + v.height() + 15)
            << "\" text-anchor=\"middle\">";
        else
          o << " x=\"" << num(v.x0 - 6) << "\" y=\"" << num(v.py(a) + 4) << "\" text-anchor=\"end\">";
        o << label(a, f.step) << "</text>\n";
      }
    }
    o << "</g>\n<rect class=\"frame\" x=\"" << num(v.x0) << "\" y=\"" << num(v.y0) << "\" width=\""
      << num(v.width()) << "\" height=\"" << num(v.height()) << "\" fill=\"none\" stroke=\"#999\"/>\n";
    // The data, clipped a little outside the frame (the machine's start
    // may lie beyond it).
    o << "<clipPath id=\"" << v.id << "-clip\"><rect x=\"" << num(v.x0 - 8) << "\" y=\"" << num(v.y0 - 8)
      << "\" width=\"" << num(v.width() + 16) << "\" height=\"" << num(v.height() + 16)
      << "\"/></clipPath>\n<g clip-path=\"url(#" << v.id << "-clip)\">\n<g class=\"data\" transform=\"matrix("
      << num(v.kh) << " 0 0 " << num(-v.kv) << " " << num(v.x0 - v.fh.lo * v.kh) << " "
      << num(v.y0 + v.fv.hi * v.kv) << ")\">\n";
    const size_t n = planned_.size();
    path_element(o, "rapid", path_d(v, pts, rapid, true, 0, n), rapid_colour, 1.2, rapid_dash);
    path_element(o, "cut", path_d(v, pts, rapid, false, 0, n), run ? band_colour : cut_colour, run ? 6 : 1.6,
                 nullptr);
    if (run) {
      // The motors' positions, dashed where a rapid ran.
      std::string d_cut, d_rapid;
      for (size_t i = 0; i + 1 < motors.size(); i++) {
        std::string &d = motors_rapid[i + 1] ? d_rapid : d_cut;
        const bool joined = i > 0 && motors_rapid[i] == motors_rapid[i + 1];
        if (!joined) d += "M" + num(motors[i][v.h]) + "," + num(motors[i][v.v]) + " ";
        d += "L" + num(motors[i + 1][v.h]) + "," + num(motors[i + 1][v.v]) + " ";
      }
      path_element(o, "done", d_cut, done_colour, 1.4, nullptr);
      path_element(o, "done-rapid", d_rapid, done_colour, 1.2, done_rapid_dash);
      // Planned, not done: from where the motors stopped on.
      if (completed_ < n) {
        std::vector<pose> rest(pts.begin() + long(completed_), pts.end());
        rest[0] = motors.back();
        std::vector<bool> rest_rapid(rapid.begin() + long(completed_), rapid.end());
        path_element(o, "not-done", path_d(v, rest, rest_rapid, false, 0, rest_rapid.size()), not_done_colour,
                     2.6, nullptr);
        path_element(o, "not-done-rapid", path_d(v, rest, rest_rapid, true, 0, rest_rapid.size()),
                     not_done_colour, 1.6, rapid_dash);
      }
    }
    o << "</g>\n</g>\n";
    // Work zero: a ring and cross at (0, 0), outside the scaled group (a
    // circle stays round).
    const double ox = v.px(0), oy = v.py(0);
    o << "<g class=\"origin\" data-x=\"" << num(ox) << "\" data-y=\"" << num(oy)
      << "\" stroke=\"#c0392b\" stroke-width=\"1.5\" fill=\"none\"><circle cx=\"" << num(ox) << "\" cy=\""
      << num(oy) << "\" r=\"5\"/><line x1=\"" << num(ox - 9) << "\" y1=\"" << num(oy) << "\" x2=\""
      << num(ox + 9) << "\" y2=\"" << num(oy) << "\"/><line x1=\"" << num(ox) << "\" y1=\"" << num(oy - 9)
      << "\" x2=\"" << num(ox) << "\" y2=\"" << num(oy + 9) << "\"/></g>\n</g>\n";
  };
  draw_view(top);
  draw_view(side);

  // The legend: a swatch per kind of line, then the figures.
  double y = top_px + 4;
  o << "<g id=\"legend\">\n<text x=\"" << num(legend_x) << "\" y=\"" << num(y) << "\" font-weight=\"bold\">"
    << (run ? "planned and done" : "planned") << "</text>\n";
  auto entry = [&](const char *cls, const char *colour, double width, const char *dash,
                   const std::string &text) {
    y += 22;
    o << "<g class=\"entry\" data-kind=\"" << cls << "\"><line class=\"swatch\" x1=\"" << num(legend_x)
      << "\" y1=\"" << num(y - 4) << "\" x2=\"" << num(legend_x + 36) << "\" y2=\"" << num(y - 4)
      << "\" stroke=\"" << colour << "\" stroke-width=\"" << width << "\" stroke-linecap=\"round\"";
    if (dash) o << " stroke-dasharray=\"" << dash << "\"";
    o << "/><text x=\"" << num(legend_x + 46) << "\" y=\"" << num(y) << "\">" << xml_text(text)
      << "</text></g>\n";
  };
  entry("cut", run ? band_colour : cut_colour, run ? 6 : 1.6, nullptr, "cut (G1 G2 G3), planned");
  entry("rapid", rapid_colour, 1.2, rapid_dash, "rapid (G0), planned");
  if (run) {
    entry("done", done_colour, 1.4, nullptr, "done: the motors' positions");
    entry("done-rapid", done_colour, 1.2, done_rapid_dash, "done, in a rapid");
    entry("not-done", not_done_colour, 2.6, nullptr,
          completed_ < planned_.size() ? "planned, not done" : "planned, not done (none)");
  }
  y += 22;
  o << "<g class=\"entry\" data-kind=\"origin\" stroke=\"#c0392b\" stroke-width=\"1.5\" "
       "fill=\"none\"><circle cx=\""
    << num(legend_x + 18) << "\" cy=\"" << num(y - 4) << "\" r=\"5\"/><line x1=\"" << num(legend_x + 9)
    << "\" y1=\"" << num(y - 4) << "\" x2=\"" << num(legend_x + 27) << "\" y2=\"" << num(y - 4)
    << "\"/><text x=\"" << num(legend_x + 46) << "\" y=\"" << num(y)
    << "\" stroke=\"none\" fill=\"black\">work zero</text></g>\n";
  auto note = [&](const std::string &text, const std::string &attrs = "") {
    y += 20;
    o << "<text x=\"" << num(legend_x) << "\" y=\"" << num(y) << "\"" << attrs << ">" << xml_text(text)
      << "</text>\n";
  };
  y += 12;
  bool offset = false;
  for (double a : origin_) offset |= a != 0;
  if (offset) {
    std::string at;
    for (size_t a : {g::X, g::Y, g::Z}) at += std::string(" ") + letters[a] + number(origin_[a]);
    note("work coordinates, " + units + "; work zero at machine" + at);
  } else {
    note("work coordinates, " + units + " (no work offset:");
    note("the same as machine coordinates)");
  }
  note("grid: " + label(step, step) + " " + units +
       (z_true ? "" : ", Z " + label(fz.step, fz.step) + " " + units));
  if (run) {
    const deviation d = largest_deviation();
    char v[32], text[32];
    std::snprintf(v, sizeof v, "%.6g", d.distance);
    std::snprintf(text, sizeof text, "%.4f", d.distance);
    note("largest deviation done vs planned:", " font-weight=\"bold\"");
    note(std::string(text) + " " + units + (d.line ? " (line " + std::to_string(d.line) + ")" : ""),
         " id=\"deviation\" data-value=\"" + std::string(v) + "\" font-weight=\"bold\"");
  }
  o << "</g>\n</svg>\n";
  std::ofstream f(path);
  if (!(f << o.str()) || !f.flush())
    throw failure("--svg " + path + ": cannot write: " + std::strerror(errno), errno ? errno : EIO);
}

}  // namespace x4ctl
