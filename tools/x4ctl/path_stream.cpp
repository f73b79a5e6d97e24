// SPDX-License-Identifier: GPL-2.0
// x4ctl: streaming segments into the path queue, with keys and progress.
#include "path_stream.hpp"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <iostream>

namespace x4ctl {

namespace {

using steady = std::chrono::steady_clock;

bool at_rest(const x4step::path_status &s) { return s.state == x4step::path_state::idle && !s.queued; }

}  // namespace

path_stream::path_stream(x4step::controller &ctl, unsigned override_percent, bool json, bool keyboard,
                         progress_fn progress)
    : ctl_(ctl),
      path_(ctl),
      json_(json),
      live_(!json && ::isatty(STDOUT_FILENO)),
      own_(keyboard),
      con_(own_),
      progress_(std::move(progress)),
      override_(override_percent) {
  begin(json_ ? ctl_.now() : steady::now());
}

path_stream::path_stream(x4step::controller &ctl, unsigned override_percent, const view &v,
                         progress_fn progress)
    : ctl_(ctl),
      path_(ctl),
      json_(false),
      live_(false),
      own_(false),
      con_(v.keys ? *v.keys : own_),
      view_(v),
      progress_(std::move(progress)),
      override_(override_percent) {
  begin(steady::now());
}

// Both constructors: the override, the done count to start from, the
// progress due at once, the keys.
void path_stream::begin(steady::time_point now) {
  path_.set_override(override_);
  status_ = path_.status();
  base_ = status_.done;
  last_shown_ = now - std::chrono::seconds(1);
  con_.keys_on();
}

path_stream::~path_stream() {
  con_.keys_off();
  if (drawn_) std::cout << "\r\033[K" << std::flush;
}

void path_stream::take(key k) {
  try {
    switch (k) {
      case key::stop_request:  // x4ctl stop: at once
        ctl_.stop();
        aborted_ = true;
        break;
      case key::interrupt:
        interrupted_ = true;
        [[fallthrough]];
      case key::esc:
      case key::brake_request:
        if (!aborted_) path_.abort();  // hold along the path, then flush
        aborted_ = true;
        break;
      case key::space:
        if (aborted_) break;
        if (status_.state == x4step::path_state::running)
          path_.hold();
        else if (status_.state != x4step::path_state::idle)
          path_.resume();
        break;
      case key::plus:
      case key::minus:
        override_ = k == key::plus ? std::min(override_ + 10, 200u) : std::max(override_, 20u) - 10;
        path_.set_override(override_);
        break;
      default:
        break;
    }
  } catch (const x4step::error &e) {
    // The path ended (or was flushed) between the status read and the key:
    // nothing left to hold or resume.
    if (e.code() != x4step::make_error_code(x4step::errc::not_active)) throw;
  }
}

void path_stream::serve(int poll_ms) {
  take(con_.read_key(std::chrono::milliseconds(0)));
  status_ = path_.status();
  // At rest with segments missing: the kernel flushed them (a limit
  // switch, a stop from elsewhere), which is no end of the program.
  if (at_rest(status_) && done() < pushed_ && !probing_) aborted_ = true;
  if (on_poll_) on_poll_();
  show(false);
  if (poll_ms <= 0) return;
  // Room comes as segments end, the end when the path stops: the library's
  // wait, not a poll of fd(), as on a simulated port that wait is what runs
  // the clock in virtual time. A held or idle path has nothing to wait for
  // (its wait would return at once): sleep, for a key or a dwell.
  const bool moving =
      status_.state == x4step::path_state::running || status_.state == x4step::path_state::holding;
  if (moving && !aborted_)
    path_.wait(std::chrono::milliseconds(poll_ms));
  else
    ::poll(nullptr, 0, poll_ms);
}

bool path_stream::push(const x4step::segment &s) {
  while (!aborted_) {
    try {
      if (path_.try_append(&s, 1)) {
        pushed_++;
        serve(0);
        return !aborted_;
      }
    } catch (const x4step::error &e) {
      // Flushed under us: a brake key, a limit switch, an emergency stop.
      if (e.code() != x4step::make_error_code(x4step::errc::not_active)) throw;
      aborted_ = true;
      break;
    }
    serve(20);
  }
  return false;
}

std::size_t path_stream::push_some(const x4step::segment *s, std::size_t n) {
  const std::size_t queued = aborted_ ? 0 : path_.try_append(s, n);
  pushed_ += queued;
  serve(0);
  return queued;
}

bool path_stream::drain() {
  for (;;) {
    serve(20);
    if (at_rest(status_)) break;
  }
  return !aborted_;
}

std::optional<x4step::probe_latch> path_stream::probe(const x4step::segment &s) {
  if (!drain() || !push(s)) return std::nullopt;
  probing_ = true;
  while (!aborted_ && !at_rest(status_)) serve(20);
  probing_ = false;
  if (aborted_) return std::nullopt;
  const x4step::probe_latch l = path_.probe();
  if (l.tripped) {
    // The trip braked and flushed the path (its probing segment unfinished): a new one goes on.
    path_.clear();
    pushed_ = done();
  }
  return l;
}

bool path_stream::wait_for(std::chrono::milliseconds t) {
  const auto until = ctl_.now() + t;
  while (!aborted_ && ctl_.now() < until) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - ctl_.now()).count();
    const auto slice = std::chrono::milliseconds(std::clamp<long long>(left, 1, 20));
    serve(0);
    // The port's clock: a dwell in virtual time takes no time here.
    if (ctl_.clock_runs())
      ::poll(nullptr, 0, static_cast<int>(slice.count()));
    else
      ctl_.sleep_for(slice);
  }
  return !aborted_;
}

bool path_stream::wait_for_operator() {
  while (!aborted_) {
    const key k = con_.read_key(std::chrono::milliseconds(100));
    if (k == key::space) return true;
    if (k == key::esc || k == key::interrupt || k == key::brake_request || k == key::stop_request)
      aborted_ = true;
    if (k == key::interrupt) interrupted_ = true;
    if (view_.show) view_.show(status_, done());
  }
  return false;
}

void path_stream::show(bool now) {
  if (view_.show) {  // the view has its own pace
    view_.show(status_, done());
    return;
  }
  // JSON records every 200 ms of the port's clock (as many in virtual
  // time as in real time); a terminal's line 10 times a second.
  const auto t = json_ ? ctl_.now() : steady::now();
  if (!now && t - last_shown_ < std::chrono::milliseconds(json_ ? 200 : 100)) return;
  last_shown_ = t;
  if (live_) {
    // One line, never wrapped: a column is left free, so that the cursor
    // stays on the line whatever the terminal does at its right margin.
    const size_t width = std::max<size_t>(terminal_columns(STDOUT_FILENO), 2) - 1;
    std::string line = progress_(status_, done(), false, width);
    if (line.size() > width) line.resize(width);
    std::cout << "\r" << line << "\033[K" << std::flush;
    drawn_ = true;
  } else if (json_) {
    std::cout << progress_(status_, done(), true, 0) << "\n" << std::flush;
  }
}

void path_stream::show_now() {
  status_ = path_.status();
  show(true);
}

void path_stream::finish() {
  // JSON: the last record; a terminal: the line is cleared for the end
  // line that follows.
  if (json_) show_now();
  if (drawn_) std::cout << "\r\033[K" << std::flush;
  drawn_ = false;
}

void path_stream::say(const std::string &text) {
  if (view_.say) {
    view_.say(text);
    return;
  }
  if (drawn_) std::cout << "\r\033[K";
  std::cout << text << "\n" << std::flush;
  drawn_ = false;
}

}  // namespace x4ctl
