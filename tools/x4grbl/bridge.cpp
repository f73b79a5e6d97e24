// SPDX-License-Identifier: GPL-2.0
// x4grbl: the GRBL machine (bridge.hpp). GRBL 1.1's behaviour as gnea/grbl
// documents it (doc/markdown: interface.md, commands.md, settings.md,
// jogging.md) and as its protocol.c / system.c / report.c do it, on
// x4step's interpreter, planner and path queue.
#include "bridge.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>

#include "codes.hpp"
#include "commands.hpp"
#include "machine_io.hpp"
#include "operate.hpp"

namespace x4grbl {

using namespace std::chrono_literals;
using clock_type = std::chrono::steady_clock;

namespace {

constexpr const char *welcome = "\r\nGrbl 1.1h ['$' for help]";
constexpr const char *unlock_hint = "[MSG:'$H'|'$X' to unlock]";
// Segments planned ahead of the path queue before a line waits for room
// (its ok, with it): the queue itself holds 256 or more.
constexpr std::size_t backlog_segments_max = 32;
// GRBL's config.h: WCO and Ov refresh every N status reports, busy / idle.
constexpr int wco_busy = 30, wco_idle = 10, ovr_busy = 20, ovr_idle = 10;
// Override limits and steps (config.h).
constexpr unsigned ovr_min = 10, ovr_max = 200;

unsigned clamp_override(int v) { return unsigned(std::clamp(v, int(ovr_min), int(ovr_max))); }

std::string upper_no_blanks(const std::string &s) {
  std::string r;
  for (char c : s)
    if (c != ' ' && c != '\t') r += char(std::toupper(static_cast<unsigned char>(c)));
  return r;
}

std::string number3(double v, int decimals) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, std::fabs(v) < 0.5e-4 ? 0.0 : v);
  return buf;
}

}  // namespace

// What the planner gave, in order, waiting for the path queue.
struct bridge::item {
  enum kind { segment, dwell, pin, pause, say } k = segment;
  x4step::segment seg;
  bool rapid = false;
  double seconds = 0;
  m::pin which = m::pin::none;
  bool on = false;
  std::string text;
};

// The planner's output: everything into the backlog (nothing in check mode).
class bridge::output : public m::planner_output {
 public:
  explicit output(bridge &b) : b_(b) {}
  void segment(const x4step::segment &s, const m::segment_info &i) override {
    if (b_.check_mode_) return;
    item it;
    it.seg = s;
    it.rapid = i.rapid;
    b_.backlog_.push_back(std::move(it));
    b_.backlog_segments_++;
  }
  void dwell(double seconds) override {
    item it;
    it.k = item::dwell;
    it.seconds = seconds;
    add(std::move(it));
  }
  void pause(bool optional, int tool) override {
    if (optional) return;  // M1: GRBL has no optional stop switch
    item it;
    it.k = item::pause;
    if (tool >= 0) it.text = "[MSG:M6: change to tool " + std::to_string(tool) + ", then cycle start]";
    add(std::move(it));
  }
  m::probe_result probe(const x4step::segment &s, const m::segment_info &, g::probe_kind k) override {
    if (b_.check_mode_) return {};  // checked: contact assumed at the end
    return b_.run_probe(s, k);
  }
  void spindle(bool on) override { pin(b_.mc_.spindle, on); }
  void coolant(bool mist, bool flood) override {
    pin(b_.mc_.mist, mist);
    pin(b_.mc_.flood, flood);
  }
  void message(std::string_view text) override {
    item it;
    it.k = item::say;
    it.text = "[MSG:" + std::string(text) + "]";
    add(std::move(it));
  }
  void warning(const g::error &w) override { b_.message(w.message()); }

 private:
  void pin(m::pin p, bool on) {
    if (p == m::pin::none) return;
    item it;
    it.k = item::pin;
    it.which = p;
    it.on = on;
    add(std::move(it));
  }
  void add(item &&it) {
    if (!b_.check_mode_) b_.backlog_.push_back(std::move(it));
  }
  bridge &b_;
};

// The console homing (x4ctl's home_machine) follows: the client is served
// meanwhile; a reset brakes the homing as ESC would.
namespace {
class serving_console : public x4ctl::console {
 public:
  serving_console(std::function<void(int)> serve, const bool &reset)
      : serve_(std::move(serve)), reset_(reset) {}
  std::ostream &out() override { return text_; }
  bool live() const override { return false; }
  bool has_keyboard() const override { return false; }
  x4ctl::key read_key(x4ctl::milliseconds timeout) override {
    if (serve_) serve_(int(std::max<long>(1, std::min<long>(timeout.count(), 20))));
    return reset_ ? x4ctl::key::esc : x4ctl::key::none;
  }
  std::string text() const { return text_.str(); }

 private:
  std::function<void(int)> serve_;
  const bool &reset_;
  std::ostringstream text_;
};
}  // namespace

bridge::bridge(const x4ctl::config &c, bool keep_port)
    : c_(c),
      mc_(x4ctl::load_machine(c, "x4grbl")),
      keep_port_(keep_port),
      settings_(x4ctl::machine_path(c)) {}

bridge::~bridge() = default;

// ---- the client ---------------------------------------------------------------

void bridge::connect() {
  connected_ = true;
  std::string why_locked;
  if (!port_) {
    locked_port_ = false;  // tried again for each client: x4ctl may have let it go
    try {
      port_ =
          std::make_unique<x4ctl::controller_port>(x4ctl::open_controller(x4ctl::machine_device(c_, mc_)));
      x4ctl::prepare_port(*port_, mc_);
      path_ = std::make_unique<x4step::path>(port_->controller());
      if (path_->status().state == x4step::path_state::idle) path_->clear();
      // G38.x watch the machine file's probe input.
      if (mc_.probe_input)
        path_->configure(x4step::path_config{}.probe_input(unsigned(mc_.probe_input), mc_.probe_nc));
    } catch (const std::exception &e) {
      path_.reset();
      port_.reset();
      why_locked = e.what();
      log_ += std::string("cannot open the port: ") + e.what() + "\n";
      locked_port_ = true;
    }
  }
  if (path_) starved_base_ = path_->status().starved;
  finish_reset();
  // After the welcome line: a sender reads from there on.
  if (!why_locked.empty()) message("x4grbl: " + why_locked);
  log_ += "client connected\n";
}

void bridge::disconnect() {
  connected_ = false;
  // Refills that came after the path had begun to stop: the bridge fell behind.
  if (path_) log_ += "path starved " + std::to_string(path_->status().starved - starved_base_) + " times\n";
  lines_.clear();
  partial_.clear();
  pending_bytes_ = 0;
  out_text_.clear();
  status_asked_ = false;
  log_ += "client gone: motion held and flushed\n";
  // Called from inside home() (it serves the client): the homing brakes
  // as on a reset, and home() releases the port once it let go of it.
  if (homing_) {
    reset_pending_ = true;
    return;
  }
  release();
}

void bridge::release() {
  abort_motion();
  if (port_ && !keep_port_) {
    outputs_off();
    path_.reset();
    port_.reset();  // the controller's close brakes a running path to rest
  }
  out_text_.clear();
}

void bridge::shutdown() {
  lines_.clear();
  abort_motion();
  if (path_) path_->wait(10s);
  if (port_) outputs_off();
  path_.reset();
  port_.reset();
}

std::string bridge::take_output() {
  if (std::exchange(status_asked_, false)) out_text_ += status_report() + "\r\n";
  return std::exchange(out_text_, {});
}
std::string bridge::take_log() { return std::exchange(log_, {}); }

bool bridge::busy() const { return motion_pending() || aborting_ || !lines_.empty() || homing_; }

void bridge::say(const std::string &line) { out_text_ += line + "\r\n"; }

void bridge::reply(int error) { say(error ? "error:" + std::to_string(error) : "ok"); }

// ---- receiving ------------------------------------------------------------------

void bridge::receive(std::string_view bytes) {
  for (const char ch : bytes) {
    const auto c = static_cast<unsigned char>(ch);
    // Real-time bytes never enter a line (GRBL: '?', '!', '~', 0x18, every byte >= 0x80).
    if (c == '?' || c == '!' || c == '~' || c == 0x18 || c >= 0x80) {
      realtime(c);
      continue;
    }
    if (c == '\n' || c == '\r') {
      // "\r\n" is one line; an empty one is a line too (GRBL: ok, for syncing).
      const bool crlf = c == '\n' && last_cr_;
      last_cr_ = c == '\r';
      if (crlf) continue;
      pending_bytes_ += partial_.size() + 1;
      lines_.push_back(line_in{std::move(partial_), partial_overflow_});
      partial_.clear();
      partial_overflow_ = false;
      continue;
    }
    last_cr_ = false;
    // A line too long is dropped to its end, then refused (error:11).
    if (partial_.size() >= max_line)
      partial_overflow_ = true;
    else
      partial_ += char(c);
  }
}

void bridge::realtime(unsigned char c) {
  switch (c) {
    case '?':
      // A flag, as GRBL's: a burst of '?' is one report, made when the
      // output is taken (one a byte grew without bound under a flood).
      status_asked_ = true;
      return;
    case 0x18:
      soft_reset();
      return;
    case '!':
    case 0x84: {  // safety door: no door input, a feed hold
      if (jogging_) {
        abort_motion();  // GRBL: a hold during a jog cancels it
        return;
      }
      // GRBL (protocol.c): Idle and Run become Hold, at once, even with
      // nothing moving yet, and it lasts until '~': a line that comes
      // next, or the end of a dwell, must not start the machine again.
      const run_state s = state();
      if (s != run_state::idle && s != run_state::cycle && s != run_state::hold) return;
      hold_asked_ = true;
      if (path_ && !path_idle()) {
        try {
          path_->hold();
        } catch (const x4step::error &) {
          // Between segments: feed_path() starts nothing while the hold is asked.
        }
      }
      return;
    }
    case '~':
      if (paused_ || hold_asked_) {
        paused_ = false;
        hold_asked_ = false;
        if (path_) try {
            path_->resume();
          } catch (const x4step::error &) {
          }
      }
      return;
    case 0x85:
      if (jogging_) abort_motion();
      return;
    case 0x90:
    case 0x91:
    case 0x92:
    case 0x93:
    case 0x94: {
      const int step[] = {0, 10, -10, 1, -1};
      const unsigned v = c == 0x90 ? 100 : clamp_override(int(feed_override_) + step[c - 0x90]);
      if (v != feed_override_) {
        feed_override_ = v;
        ovr_counter_ = 0;
        if (path_) path_->set_override(v);
      }
      return;
    }
    case 0x95:
    case 0x96:
    case 0x97:
      rapid_override_ = c == 0x95 ? 100 : c == 0x96 ? 50 : 25;
      ovr_counter_ = 0;
      return;
    case 0x99:
    case 0x9A:
    case 0x9B:
    case 0x9C:
    case 0x9D: {
      const int step[] = {0, 10, -10, 1, -1};
      spindle_override_ = c == 0x99 ? 100 : clamp_override(int(spindle_override_) + step[c - 0x99]);
      ovr_counter_ = 0;
      return;
    }
    case 0xA0:
    case 0xA1: {
      const run_state s = state();
      if (s != run_state::idle && s != run_state::cycle && s != run_state::hold) return;
      bool &on = c == 0xA0 ? flood_ : mist_;
      on = !on;
      set_output(c == 0xA0 ? mc_.flood : mc_.mist, on);
      ovr_counter_ = 0;
      return;
    }
    default:
      return;  // undefined real-time bytes are ignored, as GRBL does
  }
}

// ---- lines ----------------------------------------------------------------------

void bridge::tick() {
  if (!connected_) return;
  update_motion();
  pump();
  feed_path();
}

void bridge::pump() {
  while (!lines_.empty() && !aborting_ && !reset_pending_ && !alarm_critical_ && !homing_) {
    // A line is taken (and acknowledged) only while the planner has room.
    if (backlog_segments_ >= backlog_segments_max) return;
    const line_in l = std::move(lines_.front());
    lines_.pop_front();
    pending_bytes_ -= std::min(pending_bytes_, l.text.size() + 1);
    if (!take_line(l)) return;
    feed_path();
  }
}

// False: stop taking lines for now (an alarm, a homing cycle).
bool bridge::take_line(const line_in &l) {
  if (l.overflow) {
    reply(error_code::line_overflow);
    return true;
  }
  std::string text = l.text;
  const size_t first = text.find_first_not_of(" \t");
  if (first == std::string::npos) {
    reply(0);  // an empty line: ok
    return true;
  }
  if (text[first] == '$') {
    system_command(upper_no_blanks(text.substr(first)));
    return !alarm_critical_;
  }
  if (locked_port_) {
    reply(error_code::gcode_lock);
    return true;
  }
  if (alarm_ || locked_ || jogging_ || sleeping_) {
    reply(error_code::gcode_lock);
    return true;
  }
  gcode_line(text);
  return !alarm_critical_;
}

void bridge::gcode_line(const std::string &line) {
  // Offsets another program wrote (x4ctl touch-off) count from the next line on.
  if (!motion_pending()) reload_coordinates();
  try {
    const bool more = interp_->execute_line(line, "line", ++line_no_);
    save_coordinates();
    if (!more) {
      // M2, M30: GRBL resets the modes once the motion is done.
      item it;
      it.k = item::say;
      it.text = "[MSG:Pgm End]";
      if (!check_mode_) backlog_.push_back(std::move(it));
      // Planned, not yet run: the next program starts where this one ends.
      new_program(planned_end());
    }
    reply(0);
  } catch (const line_abandoned &) {
    // A reset (or the client's end) during a probe: no reply, as GRBL's reset.
  } catch (const g::error &e) {
    if (e.message().find("soft limit") != std::string::npos) {
      message(e.message());
      raise_alarm(alarm_code::soft_limit, true);
      return;
    }
    // A probe that failed: GRBL's alarms (then ok: the line itself was good).
    const bool started_tripped = e.message().find("already tripped") != std::string::npos;
    if (started_tripped || e.message().find("without making contact") != std::string::npos ||
        e.message().find("without breaking contact") != std::string::npos) {
      message(e.message());
      raise_alarm(started_tripped ? alarm_code::probe_initial : alarm_code::probe_contact, false);
      resync();  // the interpreter, left by the throw, still stands before the probe
      reply(0);
      return;
    }
    message(e.message());
    reply(error_code_of(e.message()));
  } catch (const x4ctl::failure &e) {
    message(e.what());
    reply(error_code::unsupported);
  }
}

void bridge::system_command(const std::string &line) {
  using namespace error_code;
  const run_state s = state();
  const bool idle_or_alarm = s == run_state::idle || s == run_state::alarm;
  const std::string rest = line.substr(1);
  if (rest.empty()) {
    say("[HLP:$$ $# $G $I $N $x=val $Nx=line $J=line $SLP $C $X $H ~ ! ? ctrl-x]");
    return reply(0);
  }
  if (rest.rfind("J=", 0) == 0) return jog_line(rest.substr(2));
  if (rest[0] == 'J') return reply(invalid_jog);
  // A letter GRBL does not know (the numbers and N are settings and startup blocks below).
  if (std::isalpha(static_cast<unsigned char>(rest[0])) && rest[0] != 'N' &&
      !std::strchr("$GCXHSIR#", rest[0]))
    return reply(invalid_statement);
  if (rest == "$") {
    if (s == run_state::cycle || s == run_state::hold) return reply(not_idle);
    port_facts f;
    if (port_) {
      f.pulse_us = double(port_->get_step_timing().pulse().count()) / 1000.0;
      const x4step::config cf = port_->get_config();
      f.clock_invert = cf.clock_invert();
      f.dir_invert = cf.dir_invert();
      f.nc = port_->get_switches().nc;
    }
    out_text_ += settings_.report(mc_, f);
    return reply(0);
  }
  if (rest == "G") {
    say(modes_report());
    return reply(0);
  }
  if (rest == "C") {
    if (check_mode_) {
      // GRBL resets when check mode ends: the modes the check changed go.
      message("Disabled");
      reply(0);
      soft_reset();
      return;
    }
    if (s != run_state::idle) return reply(not_idle);
    check_mode_ = true;
    message("Enabled");
    return reply(0);
  }
  if (rest == "X") {
    if (alarm_critical_) return reply(not_idle);
    if (alarm_ || locked_) {
      message("Caution: Unlocked");
      alarm_ = 0;
      locked_ = false;
      unlocked_ = true;
    }
    return reply(0);
  }
  if (!idle_or_alarm) return reply(not_idle);
  if (rest == "#") {
    out_text_ += parameters_report();
    return reply(0);
  }
  if (rest[0] == 'H') return home(rest.substr(1));
  if (rest == "SLP") {
    abort_motion();
    outputs_off();
    sleeping_ = true;
    message("Sleeping");
    return reply(0);
  }
  if (rest == "I") {
    say(std::string("[VER:1.1h.20190830:x4step ") + X4GRBL_VERSION + "]");
    std::string opt = "N";
    if (mc_.mist != m::pin::none) opt += "M";
    opt += "H";  // $H with axis letters
    const unsigned blocks = path_ ? path_->status().depth : 256;
    say("[OPT:" + opt + "," + std::to_string(blocks + backlog_segments_max) + "," +
        std::to_string(rx_buffer_size) + "]");
    return reply(0);
  }
  if (rest.rfind("RST=", 0) == 0) {
    const std::string what = rest.substr(4);
    if (what != "$" && what != "#" && what != "*") return reply(invalid_statement);
    if (std::string why; what != "#" && settings_.restore_defaults(why)) {
      message(why);
      return reply(invalid_statement);
    }
    if (what != "$") {
      try {
        x4ctl::save_coordinates(mc_, interp_->coordinates(), g::coordinate_state{}, "x4grbl");
      } catch (const std::exception &e) {
        message(e.what());
      }
    }
    message("Restoring defaults");
    reply(0);
    soft_reset();
    return;
  }
  if (rest == "N") {
    for (size_t i = 0; i < settings_.startup().size(); i++)
      say("$N" + std::to_string(i) + "=" + settings_.startup()[i]);
    return reply(0);
  }
  // $Nx=line, $x=value.
  const bool startup = rest[0] == 'N';
  const std::string body = startup ? rest.substr(1) : rest;
  size_t used = 0;
  double number = 0;
  try {
    number = std::stod(body, &used);
  } catch (const std::exception &) {
    return reply(bad_number);
  }
  if (used >= body.size() || body[used] != '=') return reply(invalid_statement);
  const std::string value = body.substr(used + 1);
  std::string why;
  if (startup) {
    if (s != run_state::idle) return reply(not_idle);
    // Checked as GRBL checks it: executed once (into a planner that drops it).
    if (!value.empty()) {
      struct drop : m::planner_output {
        void segment(const x4step::segment &, const m::segment_info &) override {}
      } nothing;
      m::planner p(mc_, nothing, machine_position());
      g::options o;
      o.machine_units = mc_.units;
      o.start = machine_position();
      g::interpreter check(p, o);
      try {
        check.execute_line(value, "$N", 1);
      } catch (const g::error &e) {
        message(e.message());
        return reply(error_code_of(e.message()));
      }
    }
    const int err = settings_.set_startup(int(number), value, why);
    if (!why.empty()) message(why);
    return reply(err);
  }
  size_t vused = 0;
  double v = 0;
  try {
    v = std::stod(value, &vused);
  } catch (const std::exception &) {
    return reply(bad_number);
  }
  if (vused != value.size() || number != std::floor(number) || number > 255) return reply(invalid_statement);
  port_facts f;
  const int err = settings_.set(int(number), v, mc_, f, why);
  if (!why.empty()) message(why);
  if (!err && int(number) != 10 && int(number) != 13) {
    // The machine changed: the planners take it from the next line on.
    const g::pose at = machine_position();
    planner_ = std::make_unique<m::planner>(mc_, *out_, at);
    planner_->work_offset_from([this] { return interp_->work_offset(); });
    new_program();
  }
  reply(err);
}

void bridge::jog_line(const std::string &words) {
  using namespace error_code;
  const run_state s = state();
  if (s != run_state::idle && s != run_state::jog) return reply(not_idle);
  if (locked_port_) return reply(gcode_lock);
  // The words GRBL allows in a jog: G20 G21 G90 G91 G53, axis words, F (and N).
  double k = mc_.units == g::units::inch ? 1.0 / 25.4 : 1.0;  // machine units per program unit (mm)
  if (interp_->program_units() == g::units::inch) k = mc_.units == g::units::inch ? 1.0 : 25.4;
  bool incremental = interp_->modal().incremental, machine_coords = false;
  std::array<std::optional<double>, g::n_axes> to;
  std::optional<double> feed;
  for (size_t i = 0; i < words.size();) {
    const char letter = words[i++];
    size_t used = 0;
    double v = 0;
    try {
      v = std::stod(words.substr(i), &used);
    } catch (const std::exception &) {
      return reply(bad_number);
    }
    if (words.substr(i, used).find_first_of("eExXnN") != std::string::npos) return reply(bad_number);
    i += used;
    const char *axes = "XYZABC";
    if (letter == 'G') {
      if (v == 20)
        k = mc_.units == g::units::inch ? 1.0 : 25.4;
      else if (v == 21)
        k = mc_.units == g::units::inch ? 1.0 / 25.4 : 1.0;
      else if (v == 90)
        incremental = false;
      else if (v == 91)
        incremental = true;
      else if (v == 53)
        machine_coords = true;
      else
        return reply(invalid_jog);
    } else if (letter == 'F') {
      feed = v;
    } else if (letter == 'N') {
      continue;
    } else if (const char *a = std::strchr(axes, letter); a && letter) {
      const size_t ai = size_t(a - axes);
      if (!mc_.axes[ai]) return reply(unsupported);
      to[ai] = ai < 3 ? v * k : v;
    } else {
      return reply(invalid_jog);
    }
  }
  if (!feed || *feed <= 0) return reply(undefined_feed);
  if (std::none_of(to.begin(), to.end(), [](const auto &v) { return v.has_value(); }))
    return reply(no_axis_words);
  // Where the jog starts: the end of the jogs queued, else where the machine stands.
  if (!jogging_) {
    jog_out_ = std::make_unique<output>(*this);
    jog_planner_ = std::make_unique<m::planner>(mc_, *jog_out_, machine_position());
    jog_end_ = machine_position();
  }
  const g::pose offset = interp_->work_offset();
  g::straight st{};
  st.end = jog_end_;
  st.mode = g::feed_mode::units_per_minute;
  st.feed = *feed * k;
  for (size_t a = 0; a < g::n_axes; a++) {
    if (!to[a]) continue;
    st.end[a] = incremental ? jog_end_[a] + *to[a] : machine_coords ? *to[a] : *to[a] + offset[a];
    if (!x4ctl::refused_by_limits(mc_, a, jog_end_[a], st.end[a]).empty()) {
      if (!jogging_) jog_planner_.reset();
      return reply(travel_exceeded);
    }
  }
  try {
    jog_planner_->source_line("$J", 0);
    jog_planner_->straight_feed(st);
  } catch (const g::error &e) {
    message(e.message());
    if (!jogging_) jog_planner_.reset();
    return reply(travel_exceeded);
  }
  jog_end_ = st.end;
  jogging_ = true;
  reply(0);
}

// ---- motion -----------------------------------------------------------------------

bool bridge::path_idle() const {
  if (!path_) return true;
  const x4step::path_status st = path_->status();
  return st.state == x4step::path_state::idle && st.queued == 0;
}

bool bridge::motion_pending() const {
  return !backlog_.empty() || dwell_until_ || paused_ || (path_ && !path_idle());
}

void bridge::feed_path() {
  if (!path_ || aborting_) return;
  while (!backlog_.empty()) {
    // A hold ('!', M0) that stopped the path, or came between two items,
    // starts nothing until '~'; a held path still takes segments.
    if ((hold_asked_ || paused_) && path_idle()) return;
    item &it = backlog_.front();
    if (it.k == item::segment) {
      x4step::segment s = it.seg;
      if (it.rapid && rapid_override_ < 100) {
        s.top_speed(
            std::uint32_t(std::max<std::uint64_t>(1, std::uint64_t(s.top_speed()) * rapid_override_ / 100)));
        s.entry_speed(std::min(s.entry_speed(), s.top_speed()));
      }
      try {
        if (path_->try_append(&s, 1) == 0) return;
      } catch (const x4step::error &e) {
        // Flushed beneath us: a limit switch, a brake key that aborts, an emergency halt.
        log_ += std::string("path refused a segment: ") + e.what() + "\n";
        update_motion();
        if (!alarm_) raise_alarm(alarm_code::abort_cycle, true);
        return;
      }
      if (hold_asked_) path_->hold();
      backlog_.pop_front();
      backlog_segments_--;
      continue;
    }
    // Everything else with the path at rest.
    if (!path_idle()) return;
    if (it.k == item::dwell) {
      const auto now = port_->now();
      if (!dwell_until_) dwell_until_ = now + std::chrono::nanoseconds(std::llround(it.seconds * 1e9));
      if (now < *dwell_until_) return;
      dwell_until_.reset();
    } else if (it.k == item::pin) {
      set_output(it.which, it.on);
    } else if (it.k == item::pause) {
      if (!it.text.empty()) say(it.text);
      paused_ = true;
      backlog_.pop_front();
      return;
    } else if (it.k == item::say) {
      say(it.text);
    }
    backlog_.pop_front();
  }
}

// The path's news: a limit switch, the end of a jog, of an abort.
void bridge::update_motion() {
  if (!port_) return;
  while (const auto e = port_->controller().read_event(0ms)) {
    if (e->type == x4step::event_type::switch_hit &&
        (e->how == unsigned(x4step::switch_kind::limit_pos) ||
         e->how == unsigned(x4step::switch_kind::limit_neg)) &&
        !homing_)
      raise_alarm(alarm_code::hard_limit, true);
  }
  if (!path_) return;
  const bool idle = path_idle();
  if (aborting_ && idle) {
    aborting_ = false;
    backlog_.clear();
    backlog_segments_ = 0;
    path_->clear();
    jogging_ = false;
    jog_planner_.reset();
    resync();
    if (reset_pending_) finish_reset();
    return;
  }
  if (jogging_ && idle && backlog_.empty()) {
    jogging_ = false;
    jog_planner_.reset();
    resync();
  }
}

void bridge::abort_motion() {
  backlog_.clear();
  backlog_segments_ = 0;
  dwell_until_.reset();
  paused_ = false;
  hold_asked_ = false;
  if (!path_) return;
  if (!path_idle()) {
    try {
      path_->abort();
    } catch (const x4step::error &) {
    }
    aborting_ = true;
  } else {
    jogging_ = false;
    jog_planner_.reset();
    resync();
  }
}

// The interpreter and the planner go on from where the machine stands.
void bridge::resync() {
  if (!interp_) return;
  const g::pose at = machine_position();
  interp_->set_position(at);
  planner_->set_position(at);
}

void bridge::set_output(m::pin p, bool on) {
  if (p != m::pin::none && port_)
    port_->set_output(p == m::pin::pin1 ? x4step::signal::one : x4step::signal::two, on);
}

void bridge::outputs_off() {
  for (m::pin p : {mc_.spindle, mc_.mist, mc_.flood}) set_output(p, false);
  flood_ = mist_ = false;
}

// G38.x, as GRBL's probe cycle: the motion before it done, then the probing
// segment to its end (the client served meanwhile: '?', '!', '~', a
// reset); [PRB:] with where it tripped. A reset meanwhile abandons the line.
m::probe_result bridge::run_probe(const x4step::segment &s, g::probe_kind k) {
  const auto wait_until = [this](const std::function<bool()> &done) {
    while (!done()) {
      if (reset_pending_ || aborting_ || !connected_) throw line_abandoned{};
      update_motion();
      feed_path();
      if (serve_) serve_(5);
    }
  };
  wait_until([this] { return backlog_.empty() && !dwell_until_ && !paused_ && path_idle(); });
  x4step::segment p = s;
  p.probe(x4ctl::probe_mode_of(k));
  const std::uint64_t done_before = path_->status().done;
  path_->try_append(&p, 1);
  wait_until([this] { return path_idle() && !hold_asked_; });
  const x4step::probe_latch l = path_->probe();
  // The trip braked and flushed the path: a new one goes on.
  if (l.tripped || path_->status().done == done_before) path_->clear();
  const m::probe_result r = x4ctl::probe_result_of(l, port_->get_axes());
  probe_ = x4ctl::pose_of(mc_, r.trip);
  probe_ok_ = l.tripped;
  say("[PRB:" + axes_text(probe_) + ":" + (probe_ok_ ? "1" : "0") + "]");
  return r;
}

void bridge::home(const std::string &letters) {
  std::vector<size_t> axes;
  try {
    axes = x4ctl::machine_axes(mc_, letters, "x4grbl");
  } catch (const std::exception &) {
    return reply(error_code::invalid_statement);
  }
  if (std::none_of(axes.begin(), axes.end(), [this](size_t a) { return mc_.axes[a]->home.enabled; }))
    return reply(error_code::setting_disabled);
  if (!port_) return reply(error_code::gcode_lock);
  homing_ = true;
  serving_console con(serve_, reset_pending_);
  try {
    x4ctl::home_machine(*port_, con, mc_, axes, con.out());
    homing_ = false;
    alarm_ = 0;
    locked_ = false;
    resync();
    reply(0);
    // A reset that came as the homing ended: done now, else no line would be taken.
    if (reset_pending_)
      finish_reset();
    else if (letters.empty())
      run_startup();
  } catch (const std::exception &e) {
    homing_ = false;
    resync();
    message(e.what());
    raise_alarm(reset_pending_ ? alarm_code::homing_reset : alarm_code::homing_not_found, false);
    reply(error_code::setting_disabled);
    if (reset_pending_) finish_reset();
  }
  if (!connected_) release();  // the client left during the homing
}

void bridge::raise_alarm(int code, bool critical) {
  abort_motion();
  alarm_ = code;
  alarm_critical_ = critical;
  say("ALARM:" + std::to_string(code));
  if (critical) message("Reset to continue");
  log_ += "ALARM:" + std::to_string(code) + "\n";
}

// 0x18: motion brakes along the path (x4step loses no step doing so),
// the rest of the program is dropped, the modes start afresh.
void bridge::soft_reset() {
  lines_.clear();
  partial_.clear();
  partial_overflow_ = false;
  pending_bytes_ = 0;
  reset_pending_ = true;
  if (homing_) return;  // the homing console brakes it; home() finishes the reset
  abort_motion();
  if (!aborting_) finish_reset();
}

void bridge::finish_reset() {
  reset_pending_ = false;
  outputs_off();
  feed_override_ = rapid_override_ = spindle_override_ = 100;
  if (path_) {
    try {
      path_->set_override(100);
    } catch (const x4step::error &) {
    }
  }
  check_mode_ = false;
  sleeping_ = false;
  alarm_critical_ = false;
  wco_counter_ = ovr_counter_ = 0;
  new_program();
  // Homed first (x4ctl's rule): an axis with a home switch not homed locks, as GRBL's homing lock.
  if (port_ && !unlocked_ && !alarm_) {
    const bool can_home = !port_->simulated() || x4step::sim_machine_switches();
    locked_ = can_home && !x4ctl::unhomed_axes(mc_, port_->get_axes(), x4ctl::machine_axes_of(mc_)).empty();
  }
  say(welcome);
  if (alarm_ || locked_ || locked_port_)
    say(unlock_hint);
  else
    run_startup();
}

// Where the motion planned so far ends (the planner's steps), which is
// where the machine will stand once the backlog and the path ran.
g::pose bridge::planned_end() const { return x4ctl::pose_of(mc_, planner_->summary().steps); }

void bridge::run_startup() {
  for (const std::string &block : settings_.startup()) {
    if (block.empty()) continue;
    std::string text = ">" + block + ":";
    try {
      interp_->execute_line(block, "$N", ++line_no_);
      save_coordinates();
      text += "ok";
    } catch (const g::error &e) {
      text += "error:" + std::to_string(error_code_of(e.message()));
    }
    say(text);
  }
}

// A fresh interpreter (GRBL's modes after a reset or M2) from where the
// machine stands, with the parameter file's offsets.
void bridge::new_program() { new_program(machine_position()); }

void bridge::new_program(const g::pose &at) {
  if (!out_) out_ = std::make_unique<output>(*this);
  if (!planner_) {
    planner_ = std::make_unique<m::planner>(mc_, *out_, at);
    planner_->work_offset_from([this] { return interp_ ? interp_->work_offset() : g::pose{}; });
  }
  planner_->set_position(at);
  g::options o;
  o.machine_units = mc_.units;
  o.start = at;
  if (mc_.parameter_file.empty() && interp_) {
    // No parameter file: the offsets live as long as x4grbl, as GRBL's in its EEPROM.
    o.coordinates = interp_->coordinates();
  } else {
    try {
      o.coordinates = x4ctl::load_coordinates(mc_, "x4grbl");
    } catch (const std::exception &e) {
      message(e.what());
    }
  }
  saved_coords_ = o.coordinates;
  interp_ = std::make_unique<g::interpreter>(*planner_, o);
  if (!mc_.tool_table.empty()) {
    try {
      interp_->set_tool_table(g::read_tool_table(mc_.tool_table, mc_.units, mc_.units));
    } catch (const g::error &e) {
      message(e.what());
    }
  }
}

void bridge::reload_coordinates() {
  if (mc_.parameter_file.empty()) return;
  try {
    const g::coordinate_state now = x4ctl::load_coordinates(mc_, "x4grbl");
    if (now != saved_coords_) {
      interp_->set_coordinates(now);
      saved_coords_ = now;
    }
  } catch (const std::exception &e) {
    message(e.what());
  }
}

void bridge::save_coordinates() {
  const g::coordinate_state now = interp_->coordinates();
  if (now == saved_coords_) return;
  try {
    x4ctl::save_coordinates(mc_, saved_coords_, now, "x4grbl");
  } catch (const std::exception &e) {
    message(e.what());
  }
  saved_coords_ = now;
  wco_counter_ = 0;
}

// ---- reports ------------------------------------------------------------------------

bridge::run_state bridge::state() const {
  if (sleeping_) return run_state::sleep;
  if (alarm_ || locked_ || locked_port_) return run_state::alarm;
  if (homing_) return run_state::homing;
  if (jogging_) return run_state::jog;
  if (paused_ || hold_asked_) return run_state::hold;
  if (path_) {
    const x4step::path_state ps = path_->status().state;
    if (ps == x4step::path_state::holding || ps == x4step::path_state::held) return run_state::hold;
  }
  if (motion_pending() || aborting_) return run_state::cycle;
  if (check_mode_) return run_state::check;
  return run_state::idle;
}

g::pose bridge::machine_position() const {
  return port_ ? x4ctl::pose_of(mc_, port_->get_axes()) : g::pose{};
}

// Reported lengths per machine unit: mm, or inches with $13=1.
double bridge::report_scale() const {
  const double mm = mc_.units == g::units::inch ? 25.4 : 1.0;
  return settings_.report_inches() ? mm / 25.4 : mm;
}

std::string bridge::axes_text(const g::pose &p) const {
  const double k = report_scale();
  const int decimals = settings_.report_inches() ? 4 : 3;
  std::string s;
  const size_t n = mc_.axes[g::A] ? 4 : 3;
  for (size_t a = 0; a < n; a++) s += (a ? "," : "") + number3(p[a] * (a < 3 ? k : 1.0), decimals);
  return s;
}

std::string bridge::status_report() {
  const run_state s = state();
  std::string r = "<";
  x4step::path_status ps;
  if (path_) ps = path_->status();
  switch (s) {
    case run_state::idle:
      r += "Idle";
      break;
    case run_state::cycle:
      r += "Run";
      break;
    case run_state::hold:
      r += ps.state == x4step::path_state::holding ? "Hold:1" : "Hold:0";
      break;
    case run_state::jog:
      r += "Jog";
      break;
    case run_state::homing:
      r += "Home";
      break;
    case run_state::alarm:
      r += "Alarm";
      break;
    case run_state::check:
      r += "Check";
      break;
    case run_state::sleep:
      r += "Sleep";
      break;
  }
  const g::pose mpos = machine_position();
  const g::pose wco = interp_ ? interp_->work_offset() : g::pose{};
  const unsigned mask = settings_.status_mask();
  if (mask & 1) {
    r += "|MPos:" + axes_text(mpos);
  } else {
    g::pose w = mpos;
    for (size_t a = 0; a < w.size(); a++) w[a] -= wco[a];
    r += "|WPos:" + axes_text(w);
  }
  if (mask & 2) {
    const long blocks =
        long(ps.depth) + long(backlog_segments_max) - long(ps.queued) - long(backlog_segments_);
    r += "|Bf:" + std::to_string(std::max(0L, blocks)) + "," +
         std::to_string(rx_buffer_size - std::min(rx_buffer_size, pending_bytes_ + partial_.size()));
  }
  // Feed now along the path (mm or inch per minute) and the spindle's speed.
  const double feed = double(ps.speed) / m::path_units_per_unit(mc_.units) * 60 * report_scale();
  const g::interpreter::modes md = interp_ ? interp_->modal() : g::interpreter::modes{};
  const double rpm = md.spindle == g::spindle_dir::off ? 0 : md.speed * spindle_override_ / 100;
  r += "|FS:" + std::to_string(std::lround(feed)) + "," + std::to_string(std::lround(rpm));
  // Pn: the inputs that are active: home switches by their axis' letter.
  if (port_) {
    const x4step::axes_status at = port_->get_axes();
    std::string pn;
    for (size_t a = 0; a < 4; a++)
      if (mc_.axes[a] && mc_.axes[a]->home.enabled &&
          (at.switches_active >> (mc_.axes[a]->home.input - 1)) & 1)
        pn += "XYZA"[a];
    if (mc_.probe_input && (((at.inputs >> (mc_.probe_input - 1)) & 1) != 0) != mc_.probe_nc) pn += "P";
    if (!pn.empty()) r += "|Pn:" + pn;
  }
  const bool busy =
      s == run_state::cycle || s == run_state::hold || s == run_state::jog || s == run_state::homing;
  if (wco != last_wco_) wco_counter_ = 0;
  bool wco_now = false;
  if (wco_counter_ > 0) {
    wco_counter_--;
  } else {
    wco_counter_ = (busy ? wco_busy : wco_idle) - 1;
    if (ovr_counter_ == 0) ovr_counter_ = 1;
    r += "|WCO:" + axes_text(wco);
    last_wco_ = wco;
    wco_now = true;
  }
  if (ovr_counter_ > 0) {
    ovr_counter_--;
  } else if (!wco_now) {
    ovr_counter_ = (busy ? ovr_busy : ovr_idle) - 1;
    r += "|Ov:" + std::to_string(feed_override_) + "," + std::to_string(rapid_override_) + "," +
         std::to_string(spindle_override_);
    std::string acc;
    if (md.spindle == g::spindle_dir::cw) acc += "S";
    if (md.spindle == g::spindle_dir::ccw) acc += "C";
    if (flood_ || md.flood) acc += "F";
    if (mist_ || md.mist) acc += "M";
    if (!acc.empty()) r += "|A:" + acc;
  }
  return r + ">";
}

std::string bridge::parameters_report() const {
  const g::coordinate_state c = interp_->coordinates();
  std::string r;
  for (size_t i = 0; i < 6; i++) r += "[G5" + std::to_string(4 + i) + ":" + axes_text(c.g5x[i]) + "]\r\n";
  r += "[G28:" + axes_text(c.g28) + "]\r\n";
  r += "[G30:" + axes_text(c.g30) + "]\r\n";
  r += "[G92:" + axes_text(c.g92) + "]\r\n";
  r += "[TLO:0.000]\r\n";
  r += "[PRB:" + axes_text(probe_) + ":" + (probe_ok_ ? "1" : "0") + "]\r\n";
  return r;
}

std::string bridge::modes_report() const {
  const g::interpreter::modes md = interp_->modal();
  std::string r = "[GC:G" + std::to_string(md.motion / 10);
  if (md.motion % 10) r += "." + std::to_string(md.motion % 10);
  r += md.system < 6 ? " G5" + std::to_string(4 + md.system) : " G59." + std::to_string(md.system - 5);
  r += md.in == g::plane::xy ? " G17" : md.in == g::plane::zx ? " G18" : " G19";
  r += md.program == g::units::inch ? " G20" : " G21";
  r += md.incremental ? " G91" : " G90";
  r += md.feed_in == g::feed_mode::inverse_time ? " G93" : " G94";
  r += md.spindle == g::spindle_dir::cw ? " M3" : md.spindle == g::spindle_dir::ccw ? " M4" : " M5";
  if (md.mist) r += " M7";
  if (md.flood) r += " M8";
  if (!md.mist && !md.flood) r += " M9";
  r += " T" + std::to_string(md.tool);
  char buf[64];
  std::snprintf(buf, sizeof buf, " F%g S%g]", md.feed, md.speed);
  return r + buf;
}

}  // namespace x4grbl
