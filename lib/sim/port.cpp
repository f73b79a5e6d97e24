// SPDX-License-Identifier: LGPL-2.1-or-later
// libx4step: the simulated port (port.hpp): its life, its clock, and the
// engine on its pins, as kmod/x4step_port.c, x4step_motion.c and
// x4step_main.c do it. The functions named *_locked here mirror the
// module's of the same name.
#include "port.hpp"

#include <linux/x4step.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstring>
#include <map>

#include "terminal.hpp"
#include "vcd.hpp"
#include "x4step.hpp"

namespace x4step::sim {
namespace {

constexpr unsigned events_kept = 256;  // the module's X4_EVENTS

std::mutex registry_lock;
std::map<int, std::weak_ptr<port>> registry;

}  // namespace

port::port(int number, options o)
    : number_(number),
      opt_(std::move(o)),
      epoch_(std::chrono::steady_clock::now()),
      machine_(opt_.model),
      events_(events_kept) {
  if (!opt_.vcd.empty()) vcd_ = std::make_unique<vcd_writer>(opt_.vcd);
  track_.push = track_push;
  track_.self = this;
  // x4step_port_init() with the module's default parameters.
  const x4_timing t{0, 0, X4_DIR_SETUP_NS, 0};
  x4_engine_init(&eng_);
  x4_engine_configure(&eng_, &t, X4_MODE_CLOCK_DIR);
  eng_.budget = X4_WRITE_BUDGET;
  load_state_locked();  // nothing else has the port yet
  if (opt_.time == time_mode::real) thread_ = std::thread([this] { timer_thread(); });
  if (opt_.terminal_keys)  // options_from_env(): stdin is a terminal
    tty_ = std::make_unique<terminal>(
        [this] {
          const lock l(m_);
          return claimed_ && x4_engine_busy(&eng_);
        },
        [this](unsigned code) { key(code); });
}

port::~port() {
  tty_.reset();
  {
    const lock l(m_);
    quit_ = true;
  }
  timer_.notify_all();
  if (thread_.joinable()) thread_.join();
  const lock l(m_);
  save_state_locked();
}

std::shared_ptr<port> port::get(int number, const options &o) {
  const std::lock_guard<std::mutex> l(registry_lock);
  if (auto p = registry[number].lock()) return p;
  auto p = std::make_shared<port>(number, o);
  registry[number] = p;
  return p;
}

std::shared_ptr<port> port::find(int number) {
  const std::lock_guard<std::mutex> l(registry_lock);
  const auto it = registry.find(number);
  return it == registry.end() ? nullptr : it->second.lock();
}

// ---- the clock ------------------------------------------------------------

std::uint64_t port::now_locked() const {
  if (opt_.time == time_mode::virtual_) return vnow_;
  return static_cast<std::uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - epoch_)
          .count());
}

// CLOCK_MONOTONIC ns of engine time now (event and input time stamps).
std::uint64_t port::steady_ns_locked() const {
  return static_cast<std::uint64_t>(
             std::chrono::duration_cast<std::chrono::nanoseconds>(epoch_.time_since_epoch()).count()) +
         now_locked();
}

port::time_point port::now() const {
  const lock l(m_);
  return epoch_ + std::chrono::nanoseconds(now_locked());
}

std::uint64_t port::engine_now() const {
  const lock l(m_);
  return now_locked();
}

// ---- the pins -------------------------------------------------------------

unsigned port::inputs_locked() {
  if (claimed_) {
    inputs_read_ = machine_.inputs(now_locked());
    inputs_ns_ = steady_ns_locked();
  }
  return inputs_read_;
}

// x4step_port_write_locked(): the pins, if they change, at engine time t.
void port::write_locked(std::uint64_t t) {
  if (!claimed_) return;
  std::uint8_t data = eng_.data;
  if (eng_.mode == X4_MODE_CLOCK_DIR) data ^= data_invert_;
  const std::uint8_t ctl = eng_.ctl;
  if (written_valid_ && data == data_written_ && ctl == ctl_written_) return;
  data_written_ = data;
  ctl_written_ = ctl;
  written_valid_ = true;
  machine_.write_data(data);
  if (recording_) writes_.push_back({t, data, ctl});
  if (vcd_) vcd_->write(t, data, ctl);
}

void port::write_rest_locked() {
  std::uint8_t bytes[X4_SMC_AXES];
  const int n = x4_phase_rest_writes(&eng_, bytes);
  for (int i = 0; i < n; i++) {
    eng_.data = bytes[i];
    write_locked(now_locked());
  }
}

void port::set_invert_locked(std::uint8_t clock_invert, std::uint8_t dir_invert) {
  std::uint8_t bits = 0;
  for (int i = 0; i < X4_AXES; i++) {
    if (clock_invert & (1u << i)) bits |= 2u << (2 * i);
    if (dir_invert & (1u << i)) bits |= 1u << (2 * i);
  }
  clock_invert_ = clock_invert;
  dir_invert_ = dir_invert;
  data_invert_ = bits;
}

// x4step_fire_locked(): the pending event at engine time t, and its write.
void port::fire_locked(std::uint64_t t) {
  const int c = static_cast<int>(eng_.cur - eng_.ch);
  if (claimed_ && x4_engine_rise_watched(&eng_)) x4_switch_sense(&eng_, static_cast<u8>(inputs_locked()));
  x4_engine_fire(&eng_, t);
  write_locked(t);
  x4_engine_written(&eng_, t);
  x4_track_fired(&track_, &eng_, c);
}

// x4step_port_drain_locked().
void port::drain_locked(std::uint64_t until) {
  while (x4_engine_busy(&eng_) && x4_engine_due(&eng_) <= until) {
    const int c = static_cast<int>(eng_.cur - eng_.ch);
    x4_engine_fire(&eng_, until);
    const std::uint64_t t = now_locked();
    write_locked(t);
    x4_engine_written(&eng_, t);
    x4_track_fired(&track_, &eng_, c);
  }
}

// The end of the module's timer callback: pollers learn of ended moves,
// and a closed controller's brake that ended lets the port go.
void port::tick_done_locked() {
  eng_.shifts = 0;
  eng_.shifted_ns = 0;
  note_ends_locked();
  if (releasing_ && !x4_engine_busy(&eng_)) let_go_locked();
  changed_locked();
}

void port::note_ends_locked() {
  if (moves_ended_ != eng_.ends) {
    moves_ended_ = eng_.ends;
    changed_locked();
  }
}

// What a poll of f reports now (x4step_poll(), x4step_path_poll()).
short port::revents_locked(const file &f) const {
  short r = 0;
  if (f.ev_next < ev_seq_) r |= POLLPRI;
  if (&f == controller_ && (path_slots_.empty() || x4_path_room(&eng_))) r |= POLLOUT | POLLWRNORM;
  if (!x4_engine_busy(&eng_) && !releasing_) r |= POLLIN | POLLRDNORM;
  return r;
}

// Waiters wake, and each descriptor's eventfd is readable exactly while
// its poll would report POLLIN or POLLPRI.
void port::changed_locked() {
  for (file *f : files_) {
    const bool want = (revents_locked(*f) & (POLLIN | POLLPRI)) != 0;
    if (want == f->efd_set) continue;
    std::uint64_t v = 1;
    ssize_t n = want ? ::write(f->efd, &v, sizeof v) : ::read(f->efd, &v, sizeof v);
    (void)n;
    f->efd_set = want;
  }
  wake_.notify_all();
}

// ---- time passing -----------------------------------------------------------

// Virtual time: fire the next event if it is due by `limit`, at its due
// time (the timer is never late); false if none is.
// A scripted key due first goes first.
bool port::step_virtual_locked(std::uint64_t limit) {
  if (!x4_engine_busy(&eng_)) return false;
  const std::uint64_t due = x4_engine_due(&eng_);
  const std::uint64_t key = next_key_ns_locked();
  if (std::min(due, key) > limit) return false;
  if (std::min(due, key) > vnow_) vnow_ = std::min(due, key);
  const std::uint64_t ends = eng_.ends;
  const std::uint64_t seq = ev_seq_;
  if (key <= due)
    keys_due_locked(vnow_);
  else
    fire_locked(vnow_);
  if (eng_.ends != ends || ev_seq_ != seq || releasing_) tick_done_locked();
  return true;
}

void port::advance_locked(std::uint64_t t_ns) {
  if (opt_.time != time_mode::virtual_) return;
  while (step_virtual_locked(t_ns)) {
  }
  if (t_ns > vnow_) vnow_ = t_ns;
  keys_due_locked(vnow_);  // no move runs: they brake nothing
  changed_locked();
}

void port::run_until(std::uint64_t t_ns) {
  const lock l(m_);
  advance_locked(t_ns);
}

void port::let_time_pass() {
  const lock l(m_);
  advance_locked(vnow_ + poll_quantum_ns);
}

// Real time: the hrtimer's job (x4step_tick()), by a thread: fire what is
// due; and the scripted keys at their times.
void port::timer_thread() {
  lock l(m_);
  while (!quit_) {
    const std::uint64_t key = next_key_ns_locked();
    const bool busy = x4_engine_busy(&eng_);
    if (!busy && key == UINT64_MAX) {
      timer_.wait(l);
      continue;
    }
    const std::uint64_t next = busy ? std::min(x4_engine_due(&eng_), key) : key;
    const time_point due = epoch_ + std::chrono::nanoseconds(next);
    if (std::chrono::steady_clock::now() < due) {
      timer_.wait_until(l, due);
      continue;
    }
    if (key <= now_locked()) {
      keys_due_locked(now_locked());
      tick_done_locked();
      continue;
    }
    for (int n = 0; n < 8 && x4_engine_busy(&eng_); n++) {
      const std::uint64_t t = now_locked();
      if (x4_engine_due(&eng_) > t) break;
      fire_locked(t);
    }
    tick_done_locked();
  }
}

int port::poll(file &f, short events, int timeout_ms, short *revents) {
  lock l(m_);
  const auto ready = [&] { return static_cast<short>(revents_locked(f) & events); };
  *revents = ready();
  if (*revents || timeout_ms == 0) return *revents ? 1 : 0;
  if (opt_.time == time_mode::real) {
    if (timeout_ms < 0)
      wake_.wait(l, [&] { return ready() != 0; });
    else
      wake_.wait_for(l, std::chrono::milliseconds(timeout_ms), [&] { return ready() != 0; });
    *revents = ready();
    return *revents ? 1 : 0;
  }
  // Virtual time: run the engine until the wait ends.
  const std::uint64_t limit =
      timeout_ms < 0 ? UINT64_MAX : vnow_ + static_cast<std::uint64_t>(timeout_ms) * 1000000u;
  while (step_virtual_locked(limit)) {
    if ((*revents = ready())) {
      changed_locked();
      return 1;
    }
  }
  if (timeout_ms < 0) {
    // Nothing runs and nothing will: in a real machine only another
    // program or a key could end this wait.
    errno = EDEADLK;
    return -1;
  }
  vnow_ = limit;
  keys_due_locked(vnow_);
  changed_locked();
  return 0;
}

// ---- descriptors ------------------------------------------------------------

// x4step_open().
void port::open(file &f, bool controller) {
  f.efd = ::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK);
  if (f.efd < 0) throw error(std::error_code(errno, std::system_category()), "eventfd");
  const lock l(m_);
  if (controller && (controller_ || releasing_)) {
    ::close(f.efd);
    f.efd = -1;
    throw error(make_error_code(errc::lpt_not_found),
                "sim:" + std::to_string(number_) +
                    ": port busy: another controller of this program has the simulated port");
  }
  f.ev_next = ev_seq_;
  f.controller = controller;
  files_.push_back(&f);
  if (controller) {
    controller_ = &f;
    // Flushes of paths before it are none of its business.
    path_flushes_seen_ = eng_.path.flushes;
    x4_path_set_override(&eng_, 100);
    claimed_locked();
    ev_push_locked(X4STEP_EV_CONTROLLER, 0, X4STEP_CTL_OPENED, 0, 0);
  }
  changed_locked();
}

// x4step_release(): a controller's moves brake; the port is let go when they
// stand (at once in virtual time: the brake runs to its end now).
void port::close(file &f) {
  const lock l(m_);
  if (controller_ == &f) {
    controller_ = nullptr;
    ev_push_locked(X4STEP_EV_CONTROLLER, 0, X4STEP_CTL_CLOSED, 0, 0);
    path_brake_locked(X4STEP_SRC_CLOSE);
    if (x4_engine_busy(&eng_)) brake_locked(0x0f, X4STEP_SRC_CLOSE, 0);
    if (x4_engine_busy(&eng_)) {
      releasing_ = true;
      if (opt_.time == time_mode::virtual_)
        while (step_virtual_locked(UINT64_MAX)) {
        }
    } else {
      let_go_locked();
    }
  }
  for (auto it = files_.begin(); it != files_.end(); ++it)
    if (*it == &f) {
      files_.erase(it);
      break;
    }
  ::close(f.efd);
  f.efd = -1;
  changed_locked();
}

// x4step_port_claimed().
void port::claimed_locked() {
  claimed_ = true;
  written_valid_ = false;
  write_rest_locked();
  inputs_locked();
}

// x4step_port_quiesce(): stop at once, forget the loaded move, outputs low.
void port::quiesce_locked() {
  x4_track_stop(&track_, eng_.busy);
  x4_engine_stop(&eng_);
  drain_locked(UINT64_MAX);
  update_locked(-1, 0);
  eng_.loaded = false;
  eng_.ctl = 0;
  write_rest_locked();
  inputs_locked();
  claimed_ = false;
  moves_ended_ = eng_.ends;
  changed_locked();
}

// x4step_let_go().
void port::let_go_locked() {
  releasing_ = false;
  quiesce_locked();
  ev_push_locked(X4STEP_EV_CONTROLLER, 0, X4STEP_CTL_RELEASED, 0, 0);
  changed_locked();
}

// ---- moves ------------------------------------------------------------------

// x4step_motion_run().
int port::run_locked(starter start, const void *arg, unsigned kind) {
  if (claimed_) x4_switch_sense(&eng_, static_cast<u8>(inputs_locked()));
  const int ret = start(&eng_, arg, now_locked());
  if (ret == X4_OK) {
    last_brake_code_ = 0;
    timer_.notify_all();
    update_locked(-1, kind);
    changed_locked();
  }
  return ret;
}

// x4step_motion_goto(): planned on a copy of the engine, as the module does.
int port::goto_locked(std::uint8_t axes, const std::int32_t *target, bool relative) {
  plan_eng_ = eng_;
  const int ret = x4_engine_plan_goto(&plan_eng_, axes, target, relative, &plan_goto_);
  if (ret) return ret;
  return run_locked(
      [](x4_engine *e, const void *a, std::uint64_t now) {
        return x4_engine_start_goto(e, static_cast<const x4_goto *>(a), now);
      },
      &plan_goto_, X4STEP_KIND_GOTO);
}

// x4step_motion_halted_locked().
void port::halted_locked() {
  write_locked(now_locked());
  drain_locked(0);
  note_ends_locked();
  update_locked(-1, 0);
  changed_locked();
}

// x4step_motion_brake_locked().
int port::brake_locked(std::uint8_t axes, unsigned source, unsigned code) {
  const std::uint8_t chans = x4_track_chans(&eng_, axes);
  const bool aborted = path_brake_locked(source);
  const int ret = x4_engine_halt(&eng_, axes, false);
  if (ret == X4_OK) {
    brake_time_ns_ = steady_ns_locked();
    x4_track_brake(&track_, &eng_, chans, source, code);
  }
  halted_locked();
  return aborted ? X4_OK : ret;
}

// x4step_motion_stop_locked().
int port::stop_locked(std::uint8_t axes) {
  x4_track_stop(&track_, x4_track_chans(&eng_, axes));
  const int ret = x4_engine_halt(&eng_, axes, true);
  halted_locked();
  return ret;
}

// ---- the machine side -------------------------------------------------------

void port::set_inputs(unsigned levels) {
  const lock l(m_);
  machine_.set_inputs(levels);
}

std::array<std::int64_t, 4> port::machine_positions() const {
  const lock l(m_);
  return machine_.positions();
}

bool port::key(unsigned code) {
  const lock l(m_);
  const bool hit = key_locked(code);
  changed_locked();
  return hit;
}

std::uint64_t port::next_key_ns_locked() const {
  return next_key_ < opt_.keys.size() ? opt_.keys[next_key_].t_ns : UINT64_MAX;
}

void port::keys_due_locked(std::uint64_t t_ns) {
  while (next_key_ < opt_.keys.size() && opt_.keys[next_key_].t_ns <= t_ns)
    key_locked(opt_.keys[next_key_++].code);
}

// x4step_motion_brake_key().
bool port::key_locked(unsigned code) {
  bool hit = code == 1;
  for (std::uint32_t i = 0; i < n_brake_codes_ && !hit; i++) hit = brake_codes_[i] == code;
  hit = hit && (x4_engine_busy(&eng_) || path_brake_aborts_locked(X4STEP_SRC_KEY));
  if (hit && brake_locked(0x0f, X4STEP_SRC_KEY, code) == X4_OK) last_brake_code_ = code;
  return hit;
}

void port::record(bool on) {
  const lock l(m_);
  recording_ = on;
  if (!on) writes_.clear();
}

std::vector<pin_write> port::writes() const {
  const lock l(m_);
  return writes_;
}

}  // namespace x4step::sim
