// SPDX-License-Identifier: GPL-2.0
// x4ctl gcode --svg: the planned toolpath and what the motors did, in work
// coordinates and the machine's units: a top view (X Y, true scale) and
// under it a side view (X Z, Z on its own scale when the part is flat),
// gridlines at round steps, a legend, the largest deviation of the motors
// from the plan.
#ifndef X4CTL_TOOLPATH_SVG_HPP
#define X4CTL_TOOLPATH_SVG_HPP

#include <cstdint>
#include <string>
#include <vector>

#include "gcode.hpp"
#include "planner.hpp"

namespace x4ctl {

/// The smallest of 1, 2, 5 times a power of 10 that is at least x.
double round_up_125(double x);
/// The grid step for a span: 1, 2 or 5 times a power of 10, so that the
/// span holds about `lines` steps.
double grid_step(double span, int lines);

class toolpath_plot {
 public:
  /// Where the path starts (the motors before its first segment), machine units.
  void start(const x4step::gcode::pose &p) { start_ = p; }
  /// A planned segment (in the program's order): its end, rapid or not, line.
  void planned(const x4step::machine::segment_info &i) { planned_.push_back({i.end, i.rapid, i.line}); }
  /// Where the motors stood at a status read while segment `running` ran
  /// (0-based: the number of segments done then), machine units.
  void done(const x4step::gcode::pose &p, std::uint64_t running);
  /// How many planned segments the motors completed; the rest is drawn as
  /// planned, not done. Only after done().
  void completed(std::uint64_t n) { completed_ = n; }
  /// Where work zero is in machine coordinates (the work offset in force);
  /// the plot is in work coordinates. Default 0: work = machine coordinates.
  void work_origin(const x4step::gcode::pose &o) { origin_ = o; }

  /// The largest distance (X Y Z) of a position of the motors from the
  /// planned segments around the one that ran, and that segment's line.
  struct deviation {
    double distance = 0;
    int line = 0;
  };
  deviation largest_deviation() const;

  /// Writes the SVG; throws failure if the file cannot be written. The
  /// paths' points are work coordinates (each view's data group maps them
  /// with its transform), so the file can be read back as data.
  void write(const std::string &path, const std::string &units, const std::string &title) const;

 private:
  struct step {
    x4step::gcode::pose end;
    bool rapid;
    int line;
  };
  struct sample {
    x4step::gcode::pose at;
    std::uint64_t running;
  };
  x4step::gcode::pose start_{}, origin_{};
  std::vector<step> planned_;
  std::vector<sample> done_;
  std::uint64_t completed_ = 0;
};

}  // namespace x4ctl

#endif  // X4CTL_TOOLPATH_SVG_HPP
