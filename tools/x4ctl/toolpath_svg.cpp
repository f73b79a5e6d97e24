// SPDX-License-Identifier: GPL-2.0
// x4ctl gcode --svg (toolpath_svg.hpp).
#include "toolpath_svg.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "cli.hpp"

namespace x4ctl {

namespace g = x4step::gcode;

namespace {

constexpr double view_px = 480, margin_px = 40;

std::string xml_text(const std::string &s) {
  std::string o;
  for (char ch : s) {
    if (ch == '<')
      o += "&lt;";
    else if (ch == '>')
      o += "&gt;";
    else if (ch == '&')
      o += "&amp;";
    else
      o += ch;
  }
  return o;
}

// One view: horizontal axis h, vertical axis v (up), both polylines.
void view(std::ostream &o, const char *id, const char *name, size_t h, size_t v, double x0,
          const std::vector<g::pose> &planned, const std::vector<g::pose> &done, const std::string &units) {
  double lo_h = 0, hi_h = 0, lo_v = 0, hi_v = 0;
  bool any = false;
  for (const auto *pts : {&planned, &done})
    for (const g::pose &p : *pts) {
      lo_h = any ? std::min(lo_h, p[h]) : p[h], hi_h = any ? std::max(hi_h, p[h]) : p[h];
      lo_v = any ? std::min(lo_v, p[v]) : p[v], hi_v = any ? std::max(hi_v, p[v]) : p[v];
      any = true;
    }
  const double span = std::max({hi_h - lo_h, hi_v - lo_v, 1e-6});
  const double k = view_px / span;  // px per unit, the same both ways
  // Machine (h, v) to the panel: h right, v up, centred.
  const double tx = x0 + margin_px + (view_px - (hi_h - lo_h) * k) / 2 - lo_h * k;
  const double ty = margin_px + view_px - (view_px - (hi_v - lo_v) * k) / 2 + lo_v * k;
  const char *const letters = "XYZABC";
  o << "<g id=\"" << id << "\">\n"
    << "<rect x=\"" << x0 + margin_px << "\" y=\"" << margin_px << "\" width=\"" << view_px << "\" height=\""
    << view_px << "\" fill=\"none\" stroke=\"#ccc\"/>\n"
    << "<text x=\"" << x0 + margin_px << "\" y=\"" << margin_px - 22 << "\">" << name << " (" << letters[h]
    << " right, " << letters[v] << " up, " << units << ")</text>\n"
    << "<text x=\"" << x0 + margin_px << "\" y=\"" << margin_px + view_px + 18 << "\" font-size=\"11\">"
    << letters[h] << " " << lo_h + 0.0 << ".." << hi_h + 0.0 << ", " << letters[v] << " " << lo_v + 0.0
    << ".." << hi_v + 0.0 << "</text>\n"
    << "<g transform=\"translate(" << tx << " " << ty << ") scale(" << k << " " << -k << ")\">\n";
  auto line = [&](const std::vector<g::pose> &pts, const char *cls, const char *colour, double width) {
    o << "<polyline class=\"" << cls << "\" fill=\"none\" stroke=\"" << colour << "\" stroke-width=\""
      << width << "\" vector-effect=\"non-scaling-stroke\" points=\"";
    for (const g::pose &p : pts) o << p[h] + 0.0 << "," << p[v] + 0.0 << " ";  // + 0.0: no "-0"
    o << "\"/>\n";
  };
  line(planned, "planned", "#1f77b4", 2.5);
  line(done, "done", "#d62728", 1);
  o << "</g>\n</g>\n";
}

}  // namespace

void toolpath_plot::write(const std::string &path, const std::string &units, const std::string &title) const {
  std::ostringstream o;
  o.precision(10);
  const double w = 2 * (view_px + 2 * margin_px), h = view_px + 2 * margin_px + 40;
  o << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
    << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << w << "\" height=\"" << h << "\" viewBox=\"0 0 "
    << w << " " << h << "\" font-family=\"sans-serif\" font-size=\"13\">\n"
    << "<title>" << xml_text(title) << "</title>\n"
    << "<text x=\"" << margin_px << "\" y=\"" << h - 10 << "\" font-size=\"12\">" << xml_text(title)
    << ": planned (blue) and done by the motors (red)</text>\n";
  view(o, "top", "top view", g::X, g::Y, 0, planned_, done_, units);
  view(o, "side", "side view", g::X, g::Z, view_px + 2 * margin_px, planned_, done_, units);
  o << "</svg>\n";
  std::ofstream f(path);
  if (!(f << o.str()) || !f.flush())
    throw failure("--svg " + path + ": cannot write: " + std::strerror(errno), errno ? errno : EIO);
}

}  // namespace x4ctl
