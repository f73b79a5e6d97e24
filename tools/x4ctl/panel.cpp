// SPDX-License-Identifier: GPL-2.0
// x4ctl panel: one screen redrawn in place with ANSI escape sequences, keys
// from the terminal in raw mode (std_console). Idle, it waits for a key; a
// move (jog, go to, home) is followed to its end with the screen redrawn at
// every look and every key braking it, so that one thing moves at a time.
// A terminal reports no key release, so a jog "while held" lasts as long as
// the key's auto-repeat keeps coming. A program (o) is checked from where
// the machine stands and run (r) as `x4ctl gcode` runs it (run_checked),
// the screen redrawn at every status read of the path.
#include "panel.hpp"

#include <unistd.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>
#include <utility>

#include "commands.hpp"
#include "gcode_cmd.hpp"
#include "held_key.hpp"
#include "operate.hpp"
#include "run_display.hpp"
#include "show.hpp"
#include "term.hpp"

namespace x4ctl {
namespace {

// The alternate screen, cursor hidden, for as long as it lives.
class full_screen {
 public:
  explicit full_screen(std::ostream &out) : out_(out) { out_ << "\x1b[?1049h\x1b[?25l\x1b[2J" << std::flush; }
  ~full_screen() { out_ << "\x1b[?25h\x1b[?1049l" << std::flush; }
  full_screen(const full_screen &) = delete;
  full_screen &operator=(const full_screen &) = delete;

 private:
  std::ostream &out_;
};

// Feeds the + and - keys step through, units/min.
constexpr double feed_steps[] = {1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10000, 20000, 50000};
constexpr int jog_steps = 4;  // while held, then 3 increments

// The console of a jog while its key is held: that key's repeats keep it
// going, their end or any other key brakes it (as any_key_brakes does).
class while_held : public console {
 public:
  while_held(std_console &inner, key held, char ch, std::function<void()> each_read)
      : inner_(inner), held_(held), ch_(ch), each_read_(std::move(each_read)), key_(steady::now()) {}
  std::ostream &out() override { return inner_.out(); }
  bool live() const override { return false; }
  bool has_keyboard() const override { return inner_.has_keyboard(); }
  void keys_on() override { inner_.keys_on(); }
  void keys_off() override { inner_.keys_off(); }
  x4step::axis_set requested_axes() const override { return inner_.requested_axes(); }
  key read_key(milliseconds timeout) override {
    if (each_read_) each_read_();
    const key k = inner_.read_key(timeout);
    if (k == held_ && inner_.last_char() == ch_) {
      key_.repeat(steady::now());  // a repeat that comes while it brakes starts no new jog
      return key::none;
    }
    switch (k) {
      case key::none:
        if (!let_go_ && key_.let_go(steady::now())) {
          let_go_ = true;
          return key::esc;
        }
        return k;
      case key::interrupt:
        interrupted_ = true;
        return k;
      case key::brake_request:
      case key::stop_request:
        return k;
      default:
        other_ = true;
        return key::esc;
    }
  }
  /// The jog ended because its key was let go (not braked by another key).
  bool let_go() const { return let_go_ && !other_; }
  bool interrupted() const { return interrupted_; }

 private:
  std_console &inner_;
  key held_;
  char ch_;
  std::function<void()> each_read_;
  held_key key_;
  bool let_go_ = false, other_ = false, interrupted_ = false;
};

// A move ended by letting go of its key was not braked by anyone: no message.
bool held_let_go(const any_key_brakes &) { return false; }
bool held_let_go(const while_held &keys) { return keys.let_go(); }

class panel {
 public:
  panel(const config &c, const m::machine &mc, std::string dev, controller_port &p, std_console &con)
      : c_(c), mc_(mc), file_(machine_path(c)), dev_(std::move(dev)), p_(p), ctl_(p.controller()), con_(con) {
    for (size_t a = 0; a < g::n_axes; a++)
      if (mc_.axes[a]) max_feed_ = std::max(max_feed_, mc_.axes[a]->max_velocity * 60);
    feed_ = feed_steps[0];
    for (double f : feed_steps)
      if (f <= max_feed_ / 4) feed_ = f;
    if (c.feed) feed_ = std::min(*c.feed, max_feed_);  // no axis goes faster anyway
    offset_ = load_coordinates(mc_, "panel").work_offset();
  }

  void run();
  const g::pose &offset() const { return offset_; }

 private:
  void draw(bool now);
  void jog(size_t a, bool positive, key k);
  template <class Keys>
  void move(const machine_targets &to, const std::string &what, Keys &keys);
  void move(const machine_targets &to, const std::string &what);
  void go_to();
  void home();
  void set_zero();
  void change_feed(bool up);
  void open_program();
  void cycle_start();
  std::optional<std::string> prompt(const std::string &question);
  double increment(size_t a) const;  // the jog step of axis a, units; 0: continuous
  std::string step_text() const;

  const config &c_;
  const m::machine &mc_;
  std::string file_, dev_;
  port &p_;
  x4step::controller &ctl_;
  std_console &con_;
  std::optional<program> prog_;  // o: the program r runs
  std::string prog_text_;        // its name and check, for the screen
  g::pose offset_{};             // work offset: work = machine - offset
  double feed_ = 0, max_feed_ = 0;
  int step_ = 0;           // index of the jog step: 0 while held
  bool to_limit_ = false;  // the next jog runs to the soft limit
  std::string state_ = "idle", message_;
  bool quit_ = false;
  steady::time_point drawn_{};
};

std::string fixed(double v, int decimals) {
  std::ostringstream o;
  o << std::fixed << std::setprecision(decimals) << v;
  std::string s = o.str();
  if (s[0] == '-' && s.find_first_not_of("-0.") == std::string::npos) s.erase(0, 1);  // no "-0.000"
  return s;
}

void panel::draw(bool now) {
  const auto t = steady::now();
  if (!now && t - drawn_ < milliseconds(50)) return;
  drawn_ = t;
  const x4step::axes_status st = p_.get_axes();
  const g::pose at = pose_of(mc_, st);
  std::ostringstream o;
  o << "\x1b[H";
  auto line = [&](const std::string &s) { o << s << "\x1b[K\n"; };
  line("x4ctl panel: " + (mc_.name.empty() ? file_ : mc_.name + " (" + file_ + ")") + " on " + dev_);
  line("");
  line("axis       work     machine  unit");
  for (size_t a = 0; a < g::n_axes; a++) {
    if (!mc_.axes[a]) continue;
    const x4step::axis_status &s = st[motor_of(*mc_.axes[a])];
    const int decimals = unit_of(mc_, a) == "inch" ? 4 : 3;
    std::ostringstream l;
    l << " " << axis_letters[a] << std::setw(13) << fixed(at[a] - offset_[a], decimals) << std::setw(12)
      << fixed(at[a], decimals) << "  " << std::left << std::setw(5) << unit_of(mc_, a) << std::right
      << (s.synced ? "  homed" : "  not homed") << (s.running ? ", moving" : "")
      << (s.error ? ", " + errors_text(s.error) : "");
    line(l.str());
  }
  line("");
  line("feed F" + number(feed_) + " " + units_name(mc_) + "/min   jog step: " + step_text());
  line("program: " + (prog_ ? prog_text_ : "none (o opens one)"));
  line("state: " + state_);
  line(message_);
  line("");
  line("Right/Left X+/X-  Up/Down Y+/Y-  PgUp/PgDn Z+/Z-  ]/[ A+/A-");
  line("i: jog step  c: next jog to the soft limit  +/-: feed  g: go to  h: home");
  line(std::string("z or 0: work zero here") + (mc_.parameter_file.empty() ? " (this session only)" : "") +
       "  space/ESC: stop  q: quit");
  line("o: open program  r: cycle start; running: space hold/resume, ESC abort");
  o << "\x1b[J";
  con_.out() << o.str() << std::flush;
}

double panel::increment(size_t a) const {
  if (step_ == 0) return 0;
  const double largest = unit_of(mc_, a) == "inch" ? 0.1 : 1;
  return largest / std::pow(10, step_ - 1);
}

std::string panel::step_text() const {
  if (to_limit_) return "to the soft limit (next jog only)";
  if (step_ == 0) return "while held";
  std::string s = number(increment(g::X)) + " " + units_name(mc_);
  if (mc_.axes[g::A] || mc_.axes[g::B] || mc_.axes[g::C]) s += ", " + number(increment(g::A)) + " deg";
  return s;
}

void panel::move(const machine_targets &to, const std::string &what) {
  any_key_brakes keys(con_, false, [&] { draw(false); });
  move(to, what, keys);
}

template <class Keys>
void panel::move(const machine_targets &to, const std::string &what, Keys &keys) {
  state_ = what;
  const axes_outcome o = move_machine(p_, keys, mc_, to, feed_ / 60);
  state_ = "idle";
  if (keys.interrupted()) quit_ = true;
  if (!o.halted_by.empty() && !held_let_go(keys)) message_ = what + ": braked (" + o.halted_by + ")";
  for (size_t a = 0; a < g::n_axes; a++)
    if (to[a] && o.end[motor_of(*mc_.axes[a])].error)
      message_ = what + ": " + axis_letters[a] + " " + errors_text(o.end[motor_of(*mc_.axes[a])].error);
}

void panel::jog(size_t a, bool positive, key k) {
  const bool to_limit = std::exchange(to_limit_, false);
  const std::string name = std::string(1, axis_letters[a]) + (positive ? "+" : "-");
  if (!mc_.axes[a]) {
    message_ = name + ": the machine has no " + axis_letters[a] + " axis";
    return;
  }
  const m::axis &ax = *mc_.axes[a];
  const double from = pose_of(mc_, p_.get_axes())[a], limit = jog_limit(ax, positive);
  const bool held = step_ == 0 && !to_limit;
  double to = step_ == 0 || to_limit ? limit : from + (positive ? increment(a) : -increment(a));
  if (positive ? to > limit : to < limit) to = limit;  // an increment stops at the soft limit
  if (positive ? to <= from : to >= from) {
    message_ = name + ": at the soft limit " + (positive ? "MAX_LIMIT " : "MIN_LIMIT ") + number(limit);
    return;
  }
  if (step_ != 0 && std::lround(to * ax.scale) == std::lround(from * ax.scale)) {
    message_ = name + ": the jog step " + number(increment(a)) + " " + unit_of(mc_, a) +
               " is less than half a motor step (SCALE " + number(ax.scale) + "): nothing moves";
    return;
  }
  machine_targets t;
  t[a] = to;
  if (!held) return move(t, "jog " + name);
  while_held keys(con_, k, con_.last_char(), [&] { draw(false); });
  move(t, "jog " + name + " (while held)", keys);
}

std::optional<std::string> panel::prompt(const std::string &question) {
  std::string text;
  for (;;) {
    message_ = question + text + "_";
    draw(true);
    const key k = con_.read_key(milliseconds(200));
    const char ch = con_.last_char();
    if (k == key::none && !con_.gone()) continue;
    // A signal (`x4ctl brake`, `x4ctl stop`), Ctrl-C or a hung-up terminal cancels the prompt:
    // none of them is a character of the answer.
    if (k == key::esc || k == key::interrupt || k == key::brake_request || k == key::stop_request ||
        con_.gone() || quit_requested()) {
      quit_ = k == key::interrupt || quit_requested() || con_.gone();
      message_.clear();
      return std::nullopt;
    }
    const bool character = k == key::other || k == key::space || k == key::plus || k == key::minus;
    if (!character) continue;  // arrows, page keys
    if (ch == '\r' || ch == '\n') return text;
    if ((ch == 0x7f || ch == '\b') && !text.empty())
      text.pop_back();
    else if (std::isprint(static_cast<unsigned char>(ch)))
      text += ch;
  }
}

void panel::go_to() {
  const std::optional<std::string> line =
      prompt("go to (work coordinates, e.g. X10 Y-5; Enter: go, ESC: cancel): ");
  message_.clear();
  if (!line) return;
  machine_targets to;
  std::string what;
  const char *s = line->c_str();
  for (;;) {
    while (*s == ' ') s++;
    if (!*s) break;
    const char *letter = std::strchr(axis_letters, std::toupper(static_cast<unsigned char>(*s)));
    char *end = nullptr;
    const double v = letter ? std::strtod(s + 1, &end) : 0;
    const size_t a = letter ? size_t(letter - axis_letters) : 0;
    if (!letter || end == s + 1 || !std::isfinite(v) || !mc_.axes[a]) {
      message_ = "go to '" + *line + "': give the machine's axis letters with numbers, e.g. X10 Y-5";
      return;
    }
    to[a] = v + offset_[a];
    what += " " + std::string(1, axis_letters[a]) + number(v);
    s = end;
  }
  if (what.empty()) return;
  move(to, "go to" + what);
}

// The last line of a text, without its line end.
std::string last_line(std::string text) {
  if (!text.empty() && text.back() == '\n') text.pop_back();
  return text.substr(text.rfind('\n') + 1);  // npos + 1: all of it
}

void panel::home() {
  std::ostringstream log;  // home_machine's progress, its last line on the screen
  state_ = "homing";
  any_key_brakes keys(con_, false, [&] {
    message_ = last_line(log.str());
    draw(false);
  });
  try {
    home_machine(p_, keys, mc_, machine_axes(mc_, "", "home"), log);
  } catch (...) {
    quit_ = keys.interrupted();
    throw;
  }
  quit_ = keys.interrupted();
  state_ = "idle";
  message_ = last_line(log.str());
}

void panel::set_zero() {
  const g::pose at = pose_of(mc_, p_.get_axes());
  if (mc_.parameter_file.empty()) {
    offset_ = at;
    message_ = "work zero set where the axes stand (for this session only: no [RS274NGC] PARAMETER_FILE)";
    return;
  }
  // As G10 L20 P0 with every axis 0: the active system's offset, in the parameter file.
  const g::coordinate_state now = m::parameter_file(mc_.parameter_file).update([&](g::coordinate_state &s) {
    for (size_t a = 0; a < g::n_axes; a++)
      if (mc_.axes[a]) s.g5x[size_t(s.system)][a] = at[a] - s.g92[a];
  });
  offset_ = now.work_offset();
  message_ = "work zero set where the axes stand (kept in " + mc_.parameter_file + ")";
}

// The name of a file without its directory.
std::string base_name(const std::string &path) { return path.substr(path.rfind('/') + 1); }

// As `x4ctl gcode --check` from where the machine stands (its refusal
// names FILE:LINE:COLUMN); the text is kept, so what was checked is what runs.
void panel::open_program() {
  const std::optional<std::string> file = prompt("program file (Enter: open and check, ESC: cancel): ");
  message_.clear();
  if (!file || file->empty()) return;
  prog_.reset();
  program p = program::from_file(*file);
  p.by = "panel";
  const program_check k = check_at_machine(c_, mc_, ctl_, p);
  const std::string name = base_name(p.name);
  prog_text_ = name + ", " + std::to_string(k.total.lines) + " lines, about " + clock_text(k.total.seconds);
  prog_ = std::move(p);
  message_ = name + ": OK: " + check_line(mc_, k) + "; r runs it";
}

// Checked again from where the machine stands now (a jog since o moves
// the start), then run; the state line is the run's progress line.
void panel::cycle_start() {
  if (!prog_) {
    message_ = "r: no program: o opens one";
    return;
  }
  const program_check k = check_at_machine(c_, mc_, ctl_, *prog_);
  const std::string name = base_name(prog_->name);
  prog_text_ = name + ", " + std::to_string(k.total.lines) + " lines, about " + clock_text(k.total.seconds);
  run_view v;
  v.keys = &con_;
  // "state: " takes 7 columns of 80.
  v.show = [&](const x4step::path_status &s, std::uint64_t done, progress_meter &meter) {
    if (steady::now() - drawn_ < milliseconds(50)) return;
    state_ = meter.record(s, done, false, 72);
    draw(true);
  };
  v.say = [&](const std::string &text) {
    message_ = text;
    draw(true);
  };
  message_ = name + ": running";
  run_result r;
  try {
    r = run_checked(c_, mc_, ctl_, *prog_, k, "", true, nullptr, &v);
  } catch (...) {
    state_ = "idle";
    throw;
  }
  state_ = "idle";
  // What a program that ran to its end changed (G10 L2/L20, G92) is shown.
  offset_ = load_coordinates(mc_, "panel").work_offset();
  if (r.interrupted) quit_ = true;
  message_ = name + ": " + r.end_line;
}

void panel::change_feed(bool up) {
  double f = feed_;
  for (double s : feed_steps)
    if (up ? s > feed_ && s <= max_feed_ : s < feed_) {
      f = s;
      if (up) break;
    }
  feed_ = up ? std::min(std::max(f, feed_), max_feed_) : f;
}

void panel::run() {
  keys_guard keys(con_);
  while (!quit_) {
    draw(true);
    const key k = con_.read_key(milliseconds(200));
    if (quit_requested() || k == key::interrupt || con_.gone()) break;
    if (k == key::none) continue;
    message_.clear();
    try {
      switch (k) {
        case key::right:
        case key::left:
          jog(g::X, k == key::right, k);
          break;
        case key::up:
        case key::down:
          jog(g::Y, k == key::up, k);
          break;
        case key::page_up:
        case key::page_down:
          jog(g::Z, k == key::page_up, k);
          break;
        case key::plus:
        case key::minus:
          change_feed(k == key::plus);
          break;
        case key::other:
          switch (con_.last_char()) {
            case 'q':
            case 'Q':
              quit_ = true;
              break;
            case ']':
            case '[':
              jog(g::A, con_.last_char() == ']', k);
              break;
            case 'i':
              step_ = (step_ + 1) % jog_steps;
              to_limit_ = false;
              break;
            case 'c':
              to_limit_ = !to_limit_;
              break;
            case 'z':
            case '0':
              set_zero();
              break;
            case 'g':
              go_to();
              break;
            case 'h':
              home();
              break;
            case 'o':
              open_program();
              break;
            case 'r':
              cycle_start();
              break;
            default:
              message_ = "keys: see below ('x4ctl help panel')";
              break;
          }
          break;
        default:  // ESC, space: nothing moves at rest
          break;
      }
    } catch (const std::exception &e) {
      message_ = e.what();
      state_ = "idle";
    }
  }
}

}  // namespace

int cmd_panel(const config &c) {
  const m::machine mc = load_machine(c, "panel");
  if (!::isatty(STDIN_FILENO) || !::isatty(STDOUT_FILENO))
    throw failure("needs a terminal: standard input and output");
  const std::string dev = machine_device(c, mc);
  controller_port p(open_controller(dev));
  prepare_port(p, mc);
  std_console con(true);
  panel pn(c, mc, dev, p, con);
  {
    full_screen screen(std::cout);
    pn.run();
  }
  // Left on the normal screen: where the machine stands.
  const g::pose at = pose_of(mc, p.get_axes());
  std::string machine, work;
  for (size_t a = 0; a < g::n_axes; a++)
    if (mc.axes[a]) {
      machine += " " + std::string(1, axis_letters[a]) + number(at[a]);
      work += " " + std::string(1, axis_letters[a]) + number(at[a] - pn.offset()[a]);
    }
  std::cout << "panel: at" << machine << " (" << units_name(mc) << ", machine coordinates); work" << work
            << "\n";
  return 0;
}

}  // namespace x4ctl
