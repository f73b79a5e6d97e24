// SPDX-License-Identifier: GPL-2.0
// x4ctl gcode --svg: the planned toolpath next to what the motors did, top
// view (X Y) and side view (X Z), in the machine's units.
#ifndef X4CTL_TOOLPATH_SVG_HPP
#define X4CTL_TOOLPATH_SVG_HPP

#include <string>
#include <vector>

#include "gcode.hpp"

namespace x4ctl {

class toolpath_plot {
 public:
  /// A point of the planned path (a segment's end), machine units.
  void planned(const x4step::gcode::pose &p) { add(planned_, p); }
  /// Where the motors stood at a status read, machine units.
  void done(const x4step::gcode::pose &p) { add(done_, p); }
  bool has_done() const noexcept { return !done_.empty(); }

  /// Writes the SVG; throws failure if the file cannot be written. The
  /// polylines' points are machine units (the views' transforms map
  /// them), so the file can be read back as data.
  void write(const std::string &path, const std::string &units, const std::string &title) const;

 private:
  static void add(std::vector<x4step::gcode::pose> &v, const x4step::gcode::pose &p) {
    if (v.empty() || v.back() != p) v.push_back(p);
  }
  std::vector<x4step::gcode::pose> planned_, done_;
};

}  // namespace x4ctl

#endif  // X4CTL_TOOLPATH_SVG_HPP
