// SPDX-License-Identifier: GPL-2.0
// x4ctl gcode and mdi: the run's progress and end (run_display.hpp).
#include "run_display.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>
#include <utility>

namespace x4ctl {

std::string clock_text(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  std::ostringstream o;
  if (s >= 3600)
    o << s / 3600 << ":" << std::setw(2) << std::setfill('0') << (s / 60) % 60;
  else
    o << s / 60;
  o << ":" << std::setw(2) << std::setfill('0') << s % 60;
  return o.str();
}

std::string fit_line(const std::vector<std::vector<std::string>> &fields, const std::vector<size_t> &shrink,
                     size_t width, const std::string &sep) {
  std::vector<size_t> form(fields.size(), 0);
  auto join = [&] {
    std::string line;
    for (size_t f = 0; f < fields.size(); f++) {
      if (form[f] >= fields[f].size() || fields[f][form[f]].empty()) continue;
      line += (line.empty() ? "" : sep) + fields[f][form[f]];
    }
    return line;
  };
  std::string line = join();
  for (size_t i = 0; i < shrink.size() && line.size() > width; i++) {
    if (shrink[i] < fields.size()) form[shrink[i]]++;
    line = join();
  }
  if (line.size() > width) line.resize(width);
  return line;
}

progress_meter::progress_meter(const m::machine &mc, x4step::controller &ctl, const m::plan_summary &total,
                               std::string command, bool keys, unsigned override_percent,
                               const g::pose &start)
    : mc_(mc),
      ctl_(ctl),
      command_(std::move(command)),
      units_(units_name(mc)),
      ppu_(m::path_units_per_unit(mc.units)),
      total_(total),
      keys_(keys),
      start_override_(std::max(1u, override_percent)),
      last_end_(start),
      start_(ctl.now()) {}

void progress_meter::queued(const m::segment_info &i) {
  mark k;
  k.seg_length = i.length;
  k.seg_seconds = i.speed > 0 ? i.length / i.speed : 0;
  queued_len_ += k.seg_length;
  queued_secs_ += k.seg_seconds;
  k.length = queued_len_;
  k.seconds = queued_secs_;
  k.from = last_end_;
  k.to = i.end;
  last_end_ = i.end;
  pending_.push_back(k);
}

void progress_meter::dwelled(double seconds) { dwelled_ += seconds; }

double progress_meter::elapsed() const { return std::chrono::duration<double>(ctl_.now() - start_).count(); }

double progress_meter::estimated() const { return total_.seconds * 100 / start_override_; }

void progress_meter::measure(const x4step::path_status &s, std::uint64_t done) {
  while (taken_ < done && !pending_.empty()) {
    done_ = pending_.front();
    pending_.pop_front();
    taken_++;
  }
  now_len_ = done_.length;
  now_secs_ = done_.seconds;
  // Within the running segment: the motors' place along its chord (a long
  // move shows its progress, not only its end).
  // (An aborted path stands within it too.)
  (void)s;
  if (pending_.empty()) return;
  const mark &r = pending_.front();
  const g::pose at = pose_of(mc_, ctl_.get_axes());
  double dot = 0, len2 = 0;
  for (size_t a = 0; a < g::n_axes; a++) {
    const double d = r.to[a] - r.from[a];
    dot += (at[a] - r.from[a]) * d;
    len2 += d * d;
  }
  const double t = len2 > 0 ? std::clamp(dot / len2, 0.0, 1.0) : 0;
  now_len_ += t * r.seg_length;
  now_secs_ += t * r.seg_seconds;
}

std::string progress_meter::record(const x4step::path_status &s, std::uint64_t done, bool json,
                                   size_t width) {
  measure(s, done);
  const double percent = total_.length > 0 ? std::min(100.0, 100 * now_len_ / total_.length) : 100;
  const double feed = double(s.speed) / ppu_ * 60;
  const double elapsed = this->elapsed();
  const double remaining =
      std::max(0.0, total_.seconds - now_secs_ - dwelled_) * 100 / std::max(1u, s.override_percent);
  std::ostringstream state;
  state << s.state;
  if (json)
    return json_document()
        .add("state", state.str())
        .add("line", s.tag)
        .add("percent", percent)
        .add("feed", feed)
        .add("units", units_)
        .add("override", s.override_percent)
        .add("elapsed", elapsed)
        .add("remaining", remaining)
        .str();
  char pct[32];
  std::snprintf(pct, sizeof pct, "%.1f%%", percent);
  const std::string status = state.str() + " " + pct;
  const std::string line = s.tag ? std::to_string(s.tag) : "";
  const std::string f = "F" + std::to_string(std::lround(feed));
  const std::string ovr = std::to_string(s.override_percent) + "%";
  std::vector<std::string> keys;
  if (keys_) {
    if (s.state == x4step::path_state::running)
      keys = {"space hold, ESC abort, +/- feed", "spc hold ESC abort +-", "spc/ESC/+-", ""};
    else if (s.state == x4step::path_state::idle)
      keys = {"ESC abort", "ESC", ""};
    else
      keys = {"space resume, ESC abort, +/- feed", "spc resume ESC abort +-", "spc/ESC/+-", ""};
  }
  // What goes first when the line is too wide: the feed's units, the
  // command, the long key names, the elapsed time, then the least needed
  // figures; the state, percent and remaining time go last.
  enum { status_f, line_f, feed_f, override_f, elapsed_f, left_f, keys_f };
  const std::vector<std::vector<std::string>> fields = {
      {(command_.empty() ? "" : command_ + ": ") + status, status},
      line.empty() ? std::vector<std::string>{} : std::vector<std::string>{"line " + line, "L" + line, ""},
      {f + " " + units_ + "/min", f, ""},
      // The override when it is not 100 %.
      s.override_percent == 100 ? std::vector<std::string>{}
                                : std::vector<std::string>{"override " + ovr, "ovr " + ovr, ""},
      {clock_text(elapsed) + " elapsed", clock_text(elapsed), ""},
      {clock_text(remaining) + " left", ""},
      keys,
  };
  const std::vector<size_t> shrink = {feed_f, status_f, keys_f, elapsed_f,  override_f, elapsed_f, feed_f,
                                      line_f, keys_f,   line_f, override_f, keys_f,     left_f};
  return fit_line(fields, shrink, width);
}

std::string progress_meter::end_line(bool aborted, const std::string &where) const {
  std::ostringstream o;
  if (!command_.empty()) o << command_ << ": ";
  if (aborted) {
    char pct[32];
    std::snprintf(pct, sizeof pct, "%.1f%%",
                  total_.length > 0 ? std::min(100.0, 100 * now_len_ / total_.length) : 100.0);
    o << "aborted at " << pct << " after " << clock_text(elapsed());
  } else {
    o << "done in " << clock_text(elapsed());
  }
  o << ", estimated " << clock_text(estimated()) << ", at" << where << " (" << units_ << ")";
  return o.str();
}

std::string progress_meter::end_json(bool aborted, const json_object &position) const {
  return json_document()
      .add("result", aborted ? "aborted" : "done")
      .add("position", position)
      .add("units", units_)
      .add("elapsed", elapsed())
      .add("estimated", estimated())
      .str();
}

}  // namespace x4ctl
