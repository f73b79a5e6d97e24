// SPDX-License-Identifier: LGPL-2.1-or-later
// libx4step: the simulated port's requests, as the module's x4step_ioctl()
// (kmod/x4step_ioctl.c, x4step_move.c) takes them: the same checks of the request
// structs, the same engine calls, the same errnos. The argument is in
// this process: copy_from_user is a memcpy (EFAULT for a null pointer).
// What the module decides beyond copying (which requests are invalid, the
// errnos, the answers) is kmod/engine/x4_req.c, which both call.
#include <linux/x4step.h>

#include <cerrno>
#include <climits>
#include <cstring>

#include "port.hpp"

namespace x4step::sim {
namespace {

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

// A request that starts moves writes an X4Step result back (x4step_ioctl_run()).
template <typename T>
int run_result(void *arg, int ret) {
  static_cast<T *>(arg)->result = x4_req_result(ret);
  return x4_req_errno(ret);
}

}  // namespace

int port::ioctl(file &f, unsigned long cmd, void *arg) {
  const lock l(m_);
  if (!arg && _IOC_SIZE(cmd)) {
    errno = EFAULT;
    return -1;
  }
  const int ret = ioctl_locked(f, cmd, arg);
  // A program polling the state in virtual time lets time pass.
  if (cmd == X4STEP_GET_STATUS || cmd == X4STEP_GET_AXES || cmd == X4STEP_GET_PATH)
    advance_locked(vnow_ + poll_quantum_ns);
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
  x4_req_get_axes(&eng_, inputs_locked(), inputs_ns_, &ua);
  if (!claimed_) ua.flags = X4STEP_ST_INPUTS_STALE;
  return out(arg, ua);
}

// The reading requests, and the emergency halt: any descriptor.
int port::any_ioctl_locked(unsigned long cmd, void *arg) {
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
      x4step_step_timing ut;
      x4_req_get_step_timing(&eng_, &ut);
      return out(arg, ut);
    }
    case X4STEP_GET_PROFILE: {
      const auto axis = in<x4step_profile>(arg).axis;
      if (axis < 1 || axis > X4_AXES) return -EINVAL;
      x4step_profile up;
      x4_req_get_profile(&eng_, axis, &up);
      return out(arg, up);
    }
    case X4STEP_GET_SWITCHES: {
      x4step_switches us;
      x4_req_get_switches(&eng_, &us);
      return out(arg, us);
    }
    case X4STEP_GET_AXES:
      return axes_locked(arg);
    case X4STEP_ESTOP: {
      const auto es = in<x4step_estop>(arg);
      if (x4_req_bad_estop(&es)) return -EINVAL;
      if (es.how == X4STEP_HALT_STOP) {
        x4_track_brake(&track_, &eng_, x4_track_chans(&eng_, 0x0f), X4STEP_SRC_ESTOP, X4STEP_HALT_STOP);
        return x4_req_errno(stop_locked(0x0f));
      }
      return x4_req_errno(brake_locked(0x0f, X4STEP_SRC_ESTOP, X4STEP_HALT_BRAKE));
    }
    case X4STEP_GET_PATH:
    case X4STEP_GET_PATH_CONFIG:
    case X4STEP_GET_PROBE:
      return path_read_locked(cmd, arg);
    default:
      return -ENOTTY;
  }
}

int port::ioctl_locked(file &f, unsigned long cmd, void *arg) {
  // Who may make it: x4_req_access(), as for the module's x4step_ioctl()
  // (whose request number is an unsigned int).
  switch (cmd > UINT_MAX ? X4_REQ_UNKNOWN : x4_req_access(static_cast<unsigned>(cmd))) {
    case X4_REQ_ANY:
      return any_ioctl_locked(cmd, arg);
    case X4_REQ_CONTROLLER:
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
      return x4_req_errno(ret);
    }
    case X4STEP_START:
      return x4_req_errno(
          run_locked([](x4_engine *e, const void *, std::uint64_t now) { return x4_engine_start(e, now); },
                     nullptr, X4STEP_KIND_LOADED));
    case X4STEP_BRAKE:
      return x4_req_errno(brake_locked(0x0f, X4STEP_SRC_IOCTL, 0));
    case X4STEP_STOP:
      return x4_req_errno(stop_locked(0x0f));
    case X4STEP_MOVE_ENDLESS: {
      const auto e = in<x4step_endless>(arg);
      static_cast<x4step_endless *>(arg)->result = X4_ERR_PARAM_FAIL;
      if (x4_req_bad_endless(&e)) return -EINVAL;
      return run_result<x4step_endless>(arg, run_locked(
                                                 [](x4_engine *eng, const void *a, std::uint64_t now) {
                                                   const auto *k = static_cast<const x4step_endless *>(a);
                                                   return x4_engine_endless(eng, k->axis, k->direction < 0,
                                                                            k->freq_hz, k->ramp_ms, now);
                                                 },
                                                 &e, X4STEP_KIND_ENDLESS));
    }
    case X4STEP_GOTO: {
      const auto g = in<x4step_goto>(arg);
      static_cast<x4step_goto *>(arg)->result = X4_ERR_PARAM_FAIL;
      if (x4_req_bad_goto(&g)) return -EINVAL;
      return run_result<x4step_goto>(
          arg, goto_locked(static_cast<std::uint8_t>(g.axes), g.target, g.flags & X4STEP_GOTO_RELATIVE));
    }
    case X4STEP_HOME: {
      const auto h = in<x4step_home>(arg);
      static_cast<x4step_home *>(arg)->result = X4_ERR_PARAM_FAIL;
      if (x4_req_bad_home(&h)) return -EINVAL;
      return run_result<x4step_home>(arg, run_locked(
                                              [](x4_engine *eng, const void *a, std::uint64_t now) {
                                                const auto *k = static_cast<const x4step_home *>(a);
                                                return x4_switch_home(eng, k->axis,
                                                                      static_cast<u8>(k->phases), k->vref1,
                                                                      k->vref2, k->sref, now);
                                              },
                                              &h, X4STEP_KIND_HOME));
    }
    case X4STEP_HALT: {
      const auto h = in<x4step_halt>(arg);
      if (x4_req_bad_halt(&h)) return -EINVAL;
      const auto axes = static_cast<std::uint8_t>(h.axes);
      return x4_req_errno(h.how == X4STEP_HALT_STOP ? stop_locked(axes)
                                                    : brake_locked(axes, X4STEP_SRC_IOCTL, 0));
    }
    case X4STEP_SET_POSITION: {
      const auto up = in<x4step_position>(arg);
      if (x4_req_bad_position(&up)) return -EINVAL;
      x4_track_stop(&track_, x4_track_chans(&eng_, static_cast<u8>(up.axes)));
      const int ret = x4_engine_set_position(&eng_, static_cast<u8>(up.axes), up.position);
      halted_locked();
      return x4_req_errno(ret);
    }
    case X4STEP_SET_PROFILE: {
      const auto up = in<x4step_profile>(arg);
      x4_profile p;
      const int ret = x4_req_profile(&up, &p);
      return ret ? ret : x4_req_errno(x4_engine_set_profile(&eng_, static_cast<s32>(up.axis), &p));
    }
    case X4STEP_SET_SWITCHES: {
      const auto us = in<x4step_switches>(arg);
      if (x4_req_bad_switches(&us)) return -EINVAL;
      x4_switches sw;
      x4_req_switches(&us, &sw);
      return x4_req_errno(x4_switch_set(&eng_, &sw));
    }
    case X4STEP_SET_OUTPUT:
    case X4STEP_SET_OUTPUTS: {
      std::uint32_t mask, levels;
      if (cmd == X4STEP_SET_OUTPUT) {
        const auto o = in<x4step_output>(arg);
        if (x4_req_bad_output(&o)) return -EINVAL;
        mask = o.signal;
        levels = o.level ? o.signal : 0;
      } else {
        const auto o = in<x4step_outputs>(arg);
        if (x4_req_bad_outputs(&o)) return -EINVAL;
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
      if (x4_req_bad_brake_codes(&bc)) return -EINVAL;
      std::memcpy(brake_codes_, bc.codes, sizeof brake_codes_);
      n_brake_codes_ = bc.count;
      return 0;
    }
    case X4STEP_SET_CONFIG: {
      const auto cfg = in<x4step_config>(arg);
      if (x4_req_bad_config(&cfg)) return -EINVAL;
      const int ret = x4_engine_configure(&eng_, &eng_.timing, static_cast<u8>(cfg.output_mode));
      if (!ret) {
        set_invert_locked(static_cast<std::uint8_t>(cfg.clock_invert),
                          static_cast<std::uint8_t>(cfg.dir_invert));
        cfg_flags_ = cfg.flags;
        write_rest_locked();
      }
      return x4_req_errno(ret);
    }
    case X4STEP_SET_PATH_CONFIG:
      return path_config_locked(in<x4step_path_config>(arg));
    case X4STEP_PATH_CTL:
      return path_ctl_locked(in<x4step_path_ctl>(arg));
    case X4STEP_SET_STEP_TIMING: {
      const auto ut = in<x4step_step_timing>(arg);
      if (x4_req_bad_step_timing(&ut)) return -EINVAL;
      x4_timing t;
      x4_req_step_timing(&ut, &t);
      return x4_req_errno(x4_engine_configure(&eng_, &t, eng_.mode));
    }
    default:
      return -ENOTTY;
  }
}

}  // namespace x4step::sim
