// SPDX-License-Identifier: LGPL-2.1-or-later
// libx4step: the simulated port's requests, as the module's x4_ioctl()
// (kmod/x4step_main.c) takes them: the same checks of the request
// structs, the same engine calls, the same errnos. The argument is in
// this process: copy_from_user is a memcpy (EFAULT for a null pointer).
// Glue duplicated from the module (the reserved-field checks, x4_errno(),
// the result conversion of x4_ioctl_run()): see the report of issue 19.
#include <linux/x4step.h>

#include <cerrno>
#include <cstring>

#include "port.hpp"

namespace x4step::sim {
namespace {

// x4_errno(): an X4Step result as the module's errno (negative).
int to_errno(int result) {
  switch (result) {
    case X4_OK:
      return 0;
    case X4_ERR_IS_ACTIVE:
      return -EBUSY;
    case X4_ERR_IS_LOADED:
      return -EEXIST;
    case X4_ERR_NOT_LOADED:
      return -ENODATA;
    case X4_ERR_NOT_ACTIVE:
      return -ESRCH;
    case X4_ERR_RATE_BUDGET:
      return -ERANGE;
    default:
      return -EINVAL;
  }
}

bool all_zero(const void *p, size_t n) {
  const auto *b = static_cast<const unsigned char *>(p);
  for (size_t i = 0; i < n; i++)
    if (b[i]) return false;
  return true;
}

template <typename T>
T in(const void *arg) {
  T v;
  std::memcpy(&v, arg, sizeof v);
  return v;
}

template <typename T>
int out(void *arg, const T &v) {
  std::memcpy(arg, &v, sizeof v);
  return 0;
}

bool bad_endless(const x4step_endless &e) {
  return (e.direction != 1 && e.direction != -1) || e.flags || e.reserved[0] || e.reserved[1];
}

bool bad_goto(const x4step_goto &g) {
  return g.axes > 0x0f || g.flags & ~X4STEP_GOTO_RELATIVE || g.reserved[0] || g.reserved[1] || g.reserved[2];
}

bool bad_home(const x4step_home &h) {
  return h.phases > (X4STEP_HOME_AUTO | X4STEP_HOME_BRAKE) || h.reserved[0] || h.reserved[1];
}

// The result x4_ioctl_run() writes back: over the write budget, the
// API's nearest code (the errno stays ERANGE).
std::int32_t api_result(int r) { return r == X4_ERR_RATE_BUDGET ? X4_ERR_FREQ_TOO_HIGH : r; }

}  // namespace

int port::ioctl(file &f, unsigned long cmd, void *arg) {
  const lock l(m_);
  if (!arg && _IOC_SIZE(cmd)) {
    errno = EFAULT;
    return -1;
  }
  const int ret = ioctl_locked(f, cmd, arg);
  // A program polling the state in virtual time lets time pass.
  if (cmd == X4STEP_GET_STATUS || cmd == X4STEP_GET_AXES) advance_locked(vnow_ + poll_quantum_ns);
  if (ret < 0) {
    errno = -ret;
    return -1;
  }
  return ret;
}

int port::status_locked(void *arg) {
  x4step_status st{};
  st.inputs = inputs_locked();
  st.inputs_time_ns = inputs_ns_;
  if (!claimed_) st.flags |= X4STEP_ST_INPUTS_STALE;
  if (x4_engine_busy(&eng_)) st.flags |= X4STEP_ST_ACTIVE;
  if (eng_.loaded) st.flags |= X4STEP_ST_LOADED;
  if (claimed_) st.flags |= X4STEP_ST_CONTROLLED;
  st.last_brake_code = last_brake_code_;
  st.outputs = eng_.ctl;
  st.data = eng_.data;
  for (int i = 0; i < X4_AXES; i++) st.steps[i] = eng_.steps[i];
  st.moves_ended = eng_.ends;
  st.brake_time_ns = brake_time_ns_;
  return out(arg, st);
}

int port::axes_locked(void *arg) {
  x4step_axes ua{};
  ua.inputs = inputs_locked();
  if (!claimed_) ua.flags = X4STEP_ST_INPUTS_STALE;
  if (inputs_ns_) ua.switches = x4_engine_active(&eng_, static_cast<u8>(ua.inputs));
  for (int i = 0; i < X4_AXES; i++) {
    x4_axis_state st;
    x4_engine_axis(&eng_, i, &st);
    ua.axis[i].position = st.position;
    ua.axis[i].state = st.state;
    ua.axis[i].error = st.error;
    ua.axis[i].velocity = st.velocity;
  }
  return out(arg, ua);
}

int port::ioctl_locked(file &f, unsigned long cmd, void *arg) {
  // Reading commands, and the emergency halt, work on any descriptor.
  switch (cmd) {
    case X4STEP_GET_INFO: {
      x4step_info info{};
      info.abi_version = X4STEP_ABI_VERSION;
      info.axes = X4STEP_AXES;
      info.port = static_cast<__u32>(number_);
      info.event_buffer = static_cast<__u32>(events_.size());
      return out(arg, info);
    }
    case X4STEP_GET_STATUS:
      return status_locked(arg);
    case X4STEP_GET_CONFIG: {
      x4step_config cfg{};
      cfg.clock_invert = clock_invert_;
      cfg.dir_invert = dir_invert_;
      cfg.flags = cfg_flags_;
      cfg.output_mode = eng_.mode;
      return out(arg, cfg);
    }
    case X4STEP_GET_TIMING:  // the simulated timer is never late
      return out(arg, x4step_timing{});
    case X4STEP_GET_TIMING_V2:
      std::memset(arg, 0, X4STEP_TIMING_V2_SIZE);
      return 0;
    case X4STEP_GET_STEP_TIMING: {
      x4step_step_timing ut{};
      ut.pulse_ns = eng_.timing.pulse_ns;
      ut.space_ns = eng_.timing.space_ns;
      ut.dir_setup_ns = eng_.timing.dir_setup_ns;
      ut.dir_hold_ns = eng_.timing.dir_hold_ns;
      return out(arg, ut);
    }
    case X4STEP_GET_PROFILE: {
      const auto axis = in<x4step_profile>(arg).axis;
      if (axis < 1 || axis > X4_AXES) return -EINVAL;
      const x4_profile &p = eng_.prof[axis - 1];
      x4step_profile up{};
      up.axis = axis;
      up.v0 = p.v0;
      up.ve = p.ve;
      up.vm = p.vm;
      up.a0 = p.a0;
      up.ae = p.ae;
      return out(arg, up);
    }
    case X4STEP_GET_SWITCHES: {
      x4step_switches us{};
      std::memcpy(us.ref, eng_.sw.ref, sizeof us.ref);
      std::memcpy(us.plus, eng_.sw.plus, sizeof us.plus);
      std::memcpy(us.minus, eng_.sw.minus, sizeof us.minus);
      us.nc = eng_.sw.nc;
      return out(arg, us);
    }
    case X4STEP_GET_AXES:
      return axes_locked(arg);
    case X4STEP_ESTOP: {
      const auto es = in<x4step_estop>(arg);
      if (es.how > X4STEP_HALT_STOP || es.flags || !all_zero(es.reserved, sizeof es.reserved)) return -EINVAL;
      if (es.how == X4STEP_HALT_STOP) {
        ev_brake_locked(ev_chans_locked(0x0f), X4STEP_SRC_ESTOP, X4STEP_HALT_STOP);
        return to_errno(stop_locked(0x0f));
      }
      return to_errno(brake_locked(0x0f, X4STEP_SRC_ESTOP, X4STEP_HALT_BRAKE));
    }
    case X4STEP_GET_PATH:
    case X4STEP_GET_PATH_CONFIG:
    case X4STEP_SET_PATH_CONFIG:
    case X4STEP_PATH_CTL:
      return -ENOTTY;  // paths are not simulated yet
    case X4STEP_SET_PROFILE:
    case X4STEP_GOTO:
    case X4STEP_HOME:
    case X4STEP_HALT:
    case X4STEP_SET_POSITION:
    case X4STEP_SET_SWITCHES:
    case X4STEP_LOAD:
    case X4STEP_START:
    case X4STEP_BRAKE:
    case X4STEP_STOP:
    case X4STEP_MOVE_ENDLESS:
    case X4STEP_SET_OUTPUT:
    case X4STEP_SET_OUTPUTS:
    case X4STEP_SET_BRAKE_CODES:
    case X4STEP_SET_CONFIG:
    case X4STEP_SET_STEP_TIMING:
      break;
    default:
      return -ENOTTY;
  }

  if (controller_ != &f) return -EBADF;
  switch (cmd) {
    case X4STEP_LOAD: {
      auto *um = static_cast<x4step_move *>(arg);
      const auto m_in = in<x4step_move>(arg);
      um->result = X4_ERR_PARAM_FAIL;
      if (m_in.flags) return -EINVAL;
      x4_move m{};
      for (int i = 0; i < X4_AXES; i++) m.steps[i] = m_in.steps[i];
      m.freq_hz = m_in.freq_hz;
      m.ramp_ms = m_in.ramp_ms;
      const int ret = x4_engine_load(&eng_, &m);
      um->result = ret;
      return to_errno(ret);
    }
    case X4STEP_START:
      return to_errno(
          run_locked([](x4_engine *e, const void *, std::uint64_t now) { return x4_engine_start(e, now); },
                     nullptr, X4STEP_KIND_LOADED));
    case X4STEP_BRAKE:
      return to_errno(brake_locked(0x0f, X4STEP_SRC_IOCTL, 0));
    case X4STEP_STOP:
      return to_errno(stop_locked(0x0f));
    case X4STEP_MOVE_ENDLESS: {
      auto *ue = static_cast<x4step_endless *>(arg);
      const auto e = in<x4step_endless>(arg);
      ue->result = X4_ERR_PARAM_FAIL;
      if (bad_endless(e)) return -EINVAL;
      const int ret = run_locked(
          [](x4_engine *eng, const void *a, std::uint64_t now) {
            const auto *k = static_cast<const x4step_endless *>(a);
            return x4_engine_endless(eng, k->axis, k->direction < 0, k->freq_hz, k->ramp_ms, now);
          },
          &e, X4STEP_KIND_ENDLESS);
      ue->result = api_result(ret);
      return to_errno(ret);
    }
    case X4STEP_GOTO: {
      auto *ug = static_cast<x4step_goto *>(arg);
      const auto g = in<x4step_goto>(arg);
      ug->result = X4_ERR_PARAM_FAIL;
      if (bad_goto(g)) return -EINVAL;
      const int ret =
          goto_locked(static_cast<std::uint8_t>(g.axes), g.target, g.flags & X4STEP_GOTO_RELATIVE);
      ug->result = api_result(ret);
      return to_errno(ret);
    }
    case X4STEP_HOME: {
      auto *uh = static_cast<x4step_home *>(arg);
      const auto h = in<x4step_home>(arg);
      uh->result = X4_ERR_PARAM_FAIL;
      if (bad_home(h)) return -EINVAL;
      const int ret = run_locked(
          [](x4_engine *eng, const void *a, std::uint64_t now) {
            const auto *k = static_cast<const x4step_home *>(a);
            return x4_engine_home(eng, k->axis, static_cast<u8>(k->phases), k->vref1, k->vref2, k->sref, now);
          },
          &h, X4STEP_KIND_HOME);
      uh->result = api_result(ret);
      return to_errno(ret);
    }
    case X4STEP_HALT: {
      const auto h = in<x4step_halt>(arg);
      if (!h.axes || h.axes > 0x0f || h.how > X4STEP_HALT_STOP || h.reserved[0] || h.reserved[1])
        return -EINVAL;
      const auto axes = static_cast<std::uint8_t>(h.axes);
      return to_errno(h.how == X4STEP_HALT_STOP ? stop_locked(axes)
                                                : brake_locked(axes, X4STEP_SRC_IOCTL, 0));
    }
    case X4STEP_SET_POSITION: {
      const auto up = in<x4step_position>(arg);
      if (!up.axes || up.axes > 0x0f || up.reserved) return -EINVAL;
      ev_stop_locked(ev_chans_locked(static_cast<std::uint8_t>(up.axes)));
      const int ret = x4_engine_set_position(&eng_, static_cast<u8>(up.axes), up.position);
      halted_locked();
      return to_errno(ret);
    }
    case X4STEP_SET_PROFILE: {
      const auto up = in<x4step_profile>(arg);
      if (up.reserved[0] || up.reserved[1] || up.axis < 1 || up.axis > X4_AXES) return -EINVAL;
      const x4_profile p{up.v0, up.ve, up.vm, up.a0, up.ae};
      return to_errno(x4_engine_set_profile(&eng_, static_cast<s32>(up.axis), &p));
    }
    case X4STEP_SET_SWITCHES: {
      const auto us = in<x4step_switches>(arg);
      if (!all_zero(us.reserved, sizeof us.reserved)) return -EINVAL;
      x4_switches sw{};
      std::memcpy(sw.ref, us.ref, sizeof sw.ref);
      std::memcpy(sw.plus, us.plus, sizeof sw.plus);
      std::memcpy(sw.minus, us.minus, sizeof sw.minus);
      sw.nc = us.nc;
      return to_errno(x4_engine_set_switches(&eng_, &sw));
    }
    case X4STEP_SET_OUTPUT:
    case X4STEP_SET_OUTPUTS: {
      std::uint32_t mask, levels;
      if (cmd == X4STEP_SET_OUTPUT) {
        const auto o = in<x4step_output>(arg);
        if ((o.signal != X4STEP_OUT_SIGNAL1 && o.signal != X4STEP_OUT_SIGNAL2) || o.level > 1) return -EINVAL;
        mask = o.signal;
        levels = o.level ? o.signal : 0;
      } else {
        const auto o = in<x4step_outputs>(arg);
        const std::uint32_t signals = X4STEP_OUT_SIGNAL1 | X4STEP_OUT_SIGNAL2;
        if (!o.mask || o.mask & ~signals || o.levels & ~o.mask || o.flags ||
            !all_zero(o.reserved, sizeof o.reserved))
          return -EINVAL;
        mask = o.mask;
        levels = o.levels;
      }
      if (mask & X4STEP_OUT_SIGNAL1) x4_engine_set_signal(&eng_, X4_CTL_SIGNAL1, levels & X4STEP_OUT_SIGNAL1);
      if (mask & X4STEP_OUT_SIGNAL2) x4_engine_set_signal(&eng_, X4_CTL_SIGNAL2, levels & X4STEP_OUT_SIGNAL2);
      write_locked(now_locked());
      return 0;
    }
    case X4STEP_SET_BRAKE_CODES: {
      const auto bc = in<x4step_brake_codes>(arg);
      if (bc.reserved || bc.count > X4STEP_MAX_BRAKE_CODES) return -EINVAL;
      for (std::uint32_t i = 0; i < bc.count; i++)
        if (!bc.codes[i] || bc.codes[i] > 255) return -EINVAL;
      std::memcpy(brake_codes_, bc.codes, sizeof brake_codes_);
      n_brake_codes_ = bc.count;
      return 0;
    }
    case X4STEP_SET_CONFIG: {
      const auto cfg = in<x4step_config>(arg);
      if (!all_zero(cfg.reserved, sizeof cfg.reserved)) return -EINVAL;
      if (cfg.clock_invert > 0xf || cfg.dir_invert > 0xf || cfg.flags & ~X4STEP_CFG_KEYS_SWALLOW ||
          cfg.output_mode > X4STEP_MODE_SMC_PHASE_HOLD)
        return -EINVAL;
      const int ret = x4_engine_configure(&eng_, &eng_.timing, static_cast<u8>(cfg.output_mode));
      if (!ret) {
        set_invert_locked(static_cast<std::uint8_t>(cfg.clock_invert),
                          static_cast<std::uint8_t>(cfg.dir_invert));
        cfg_flags_ = cfg.flags;
        write_rest_locked();
      }
      return to_errno(ret);
    }
    default: {  // X4STEP_SET_STEP_TIMING
      const auto ut = in<x4step_step_timing>(arg);
      if (!all_zero(ut.reserved, sizeof ut.reserved)) return -EINVAL;
      const x4_timing t{ut.pulse_ns, ut.space_ns, ut.dir_setup_ns, ut.dir_hold_ns};
      return to_errno(x4_engine_configure(&eng_, &t, eng_.mode));
    }
  }
}

}  // namespace x4step::sim
