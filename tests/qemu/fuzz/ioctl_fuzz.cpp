// SPDX-License-Identifier: GPL-2.0
//
// ioctl_fuzz: a guest-side fuzzer for the x4step character device.
//
//   ioctl_fuzz [--seed N] [--seconds S] [--device /dev/x4step0] [--invalid-only]
//              [--threads N] [--verbose]
//
// Phases (time split of --seconds):
//   0  probes: valid MOVE_ENDLESS, GOTO, HOME and LOAD arguments in read-only
//      memory (the call must fail with EFAULT and then must not have started or
//      loaded anything);
//   a  random command numbers: every _IOC_NR 0..255 of our magic with every
//      direction and several sizes, then random ones, exact commands with random
//      payloads and other magics; bad pointers (NULL, 1, kernel and non-canonical
//      addresses, PROT_NONE, the end of a page before a guard page, read-only
//      memory);
//   b  structurally valid commands with boundary and random field values
//      (including config output modes, step timings, profiles, switches, goto
//      targets at the 32-bit limits, reference runs, halts);
//   c  several threads on the one controller descriptor with random valid and
//      invalid sequences, read-only monitors (GET_STATUS, GET_AXES, poll,
//      read() of events), a thread opening and closing read-only and
//      read-write descriptors (read-write: EBUSY);
//   c2 the controller closes; threads race to become the next one (at most one
//      at a time; closing brakes moves with ramps of at most 20 ms: no close may
//      take seconds);
//   d  everything closed: a fresh controller opens, the engine is idle; the
//      config, step timing, switches and profiles found at the start are
//      restored.
// With --invalid-only only the probes and phases a and b run and no call that could be valid is
// made (state-changing commands only with invalid arguments, START only when
// nothing is loaded, BRAKE/STOP/HALT only when none of their axes runs): the
// port trace of such a run must show no clock edge (tests/qemu/fuzz/check-no-edges.sh).
//
// Invariants checked here (each violation is printed and fails the run):
//  - unknown commands (our magic or another) fail with ENOTTY;
//  - state-changing commands on a read-only descriptor fail with EBADF;
//  - bad pointers fail with EFAULT; flags/reserved fields non-zero, bad
//    signals, brake codes, config masks, profiles, switches, axis masks fail
//    with EINVAL; LOAD's, MOVE_ENDLESS's, GOTO's and HOME's out-of-range
//    arguments fail with EINVAL and the documented X4Step code in `result`
//    (single-threaded: the exact code), and `result` always matches the errno;
//  - errors of valid calls are the documented state errors only;
//  - a call that fails changes nothing (single-threaded phases: ACTIVE and
//    LOADED do not appear, outputs, config, step timing, switches and profiles
//    stay, an axis that did not run does not start, move or change state);
//    successful SET_PROFILE/SET_SWITCHES/SET_POSITION/HALT (stop) read back;
//  - GET_STATUS, GET_INFO, GET_CONFIG, GET_STEP_TIMING, GET_TIMING, GET_AXES,
//    GET_SWITCHES and GET_PROFILE report only sane values (known flag, state
//    and error bits, step counters within 2 * 16777216, speeds within
//    X4STEP_VEL_MAX, switch inputs 0..5, valid profiles, reserved fields zero,
//    histogram adding up, clock pins low at rest);
//  - poll() never reports an error; at most one controller at a time;
//  - read() of events (monitors, non-blocking descriptors, random sizes and
//    memory) returns whole, sane events, seq increasing, time monotonic, or
//    EINVAL (below one event), EFAULT (memory it cannot write), EAGAIN.
// The controller descriptor is always closed at the end (the module brakes on
// close): no motor keeps running after the fuzzer.
//
// Exit status: 0 all invariants held, 1 violations, 2 usage or setup errors.

#include <fcntl.h>
#include <linux/x4step.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cstdarg>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;

constexpr int64_t kStepsMax = 16777216;
constexpr unsigned kInputs = 5;             // switch inputs 1..5
constexpr uint32_t kRampSecondsMax = 3600;  // a profile ramp's longest time
// GET_AXES' speeds: at most X4STEP_VEL_MAX, give or take the rounding.
constexpr uint32_t kVelSlack = X4STEP_VEL_MAX + X4STEP_VEL_MAX / 100;
// Positioning moves faster than kLongHz travel at most kShortSteps: in QEMU
// (TCG) one fast axis (up to X4STEP_VEL_MAX) leaves the guest no time for user space.
constexpr int32_t kLongHz = 2000;
constexpr int32_t kShortSteps = 2000;
constexpr unsigned kMagic = X4STEP_IOC_MAGIC;
constexpr size_t kPage = 4096;

// ------------------------------------------------------------------ options

struct Options {
  uint64_t seed = 1;
  double seconds = 30;
  std::string device = "/dev/x4step0";
  bool invalid_only = false;
  int threads = 3;
  bool verbose = false;
};
Options opt;

// ------------------------------------------------------------------ reporting

std::atomic<long> g_violations{0};
std::mutex g_print;

void note(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
void note(const char *fmt, ...) {
  std::lock_guard<std::mutex> lk(g_print);
  va_list ap;
  va_start(ap, fmt);
  std::fputs("x4fuzz: ", stdout);
  std::vfprintf(stdout, fmt, ap);
  std::fputc('\n', stdout);
  std::fflush(stdout);
  va_end(ap);
}

void violation(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
// Each kind of violation (its format) is shown 3 times, then only counted.
struct Kind {
  const char *fmt;
  long count;
};
Kind g_kinds[64];
int g_nkinds = 0;

void violation(const char *fmt, ...) {
  ++g_violations;
  std::lock_guard<std::mutex> lk(g_print);
  int i = 0;
  while (i < g_nkinds && g_kinds[i].fmt != fmt) i++;
  if (i == g_nkinds && g_nkinds < 64) g_kinds[g_nkinds++] = {fmt, 0};
  if (i < 64 && ++g_kinds[i].count > 3) return;
  va_list ap;
  va_start(ap, fmt);
  std::fputs("x4fuzz: VIOLATION: ", stdout);
  std::vfprintf(stdout, fmt, ap);
  std::fputc('\n', stdout);
  std::fflush(stdout);
  va_end(ap);
}

void violation_summary() {
  std::lock_guard<std::mutex> lk(g_print);
  for (int i = 0; i < g_nkinds; i++)
    std::printf("x4fuzz: %6ld x VIOLATION %s\n", g_kinds[i].count, g_kinds[i].fmt);
}

[[noreturn]] void die(const char *what) {
  std::printf("x4fuzz: %s: %s\n", what, std::strerror(errno));
  std::printf("FAIL ioctl_fuzz setup\n");
  std::exit(2);
}

// ------------------------------------------------------------------ random

struct Rng {
  uint64_t s;
  explicit Rng(uint64_t seed) : s(seed * 0x9e3779b97f4a7c15ull + 0x1234567ull) {}
  uint64_t next() {  // splitmix64
    uint64_t z = (s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  uint32_t below(uint32_t n) { return n ? static_cast<uint32_t>(next() % n) : 0; }
  bool chance(unsigned pct) { return below(100) < pct; }
  int32_t s32() { return static_cast<int32_t>(next()); }
  int32_t range(int32_t lo, int32_t hi) {  // inclusive
    return static_cast<int32_t>(lo + static_cast<int64_t>(next() % (static_cast<uint64_t>(hi - lo) + 1)));
  }
  template <class T, size_t N>
  T pick(const T (&a)[N]) {
    return a[below(N)];
  }
};

// ------------------------------------------------------------------ commands

struct Cmd {
  unsigned long nr;
  const char *name;
  size_t size;
  bool state;            // changes state: controller only
  long result_off = -1;  // offset of the s32 X4Step `result` written back, if any
};

const Cmd kCmds[] = {
    {X4STEP_GET_INFO, "GET_INFO", sizeof(x4step_info), false},
    {X4STEP_LOAD, "LOAD", sizeof(x4step_move), true, offsetof(x4step_move, result)},
    {X4STEP_START, "START", 0, true},
    {X4STEP_BRAKE, "BRAKE", 0, true},
    {X4STEP_STOP, "STOP", 0, true},
    {X4STEP_MOVE_ENDLESS, "MOVE_ENDLESS", sizeof(x4step_endless), true, offsetof(x4step_endless, result)},
    {X4STEP_GET_STATUS, "GET_STATUS", sizeof(x4step_status), false},
    {X4STEP_SET_OUTPUT, "SET_OUTPUT", sizeof(x4step_output), true},
    {X4STEP_SET_OUTPUTS, "SET_OUTPUTS", sizeof(x4step_outputs), true},
    {X4STEP_SET_BRAKE_CODES, "SET_BRAKE_CODES", sizeof(x4step_brake_codes), true},
    {X4STEP_SET_CONFIG, "SET_CONFIG", sizeof(x4step_config), true},
    {X4STEP_GET_CONFIG, "GET_CONFIG", sizeof(x4step_config), false},
    {X4STEP_GET_TIMING, "GET_TIMING", sizeof(x4step_timing), false},
    {X4STEP_GET_TIMING_V2, "GET_TIMING_V2", X4STEP_TIMING_V2_SIZE, false},
    {X4STEP_SET_STEP_TIMING, "SET_STEP_TIMING", sizeof(x4step_step_timing), true},
    {X4STEP_GET_STEP_TIMING, "GET_STEP_TIMING", sizeof(x4step_step_timing), false},
    {X4STEP_SET_PROFILE, "SET_PROFILE", sizeof(x4step_profile), true},
    {X4STEP_GET_PROFILE, "GET_PROFILE", sizeof(x4step_profile), false},
    {X4STEP_GOTO, "GOTO", sizeof(x4step_goto), true, offsetof(x4step_goto, result)},
    {X4STEP_HOME, "HOME", sizeof(x4step_home), true, offsetof(x4step_home, result)},
    {X4STEP_HALT, "HALT", sizeof(x4step_halt), true},
    {X4STEP_SET_POSITION, "SET_POSITION", sizeof(x4step_position), true},
    {X4STEP_SET_SWITCHES, "SET_SWITCHES", sizeof(x4step_switches), true},
    {X4STEP_GET_SWITCHES, "GET_SWITCHES", sizeof(x4step_switches), false},
    {X4STEP_GET_AXES, "GET_AXES", sizeof(x4step_axes), false},
    {X4STEP_GET_PATH, "GET_PATH", sizeof(x4step_path_status), false},
    {X4STEP_GET_PATH_CONFIG, "GET_PATH_CONFIG", sizeof(x4step_path_config), false},
    {X4STEP_SET_PATH_CONFIG, "SET_PATH_CONFIG", sizeof(x4step_path_config), true},
    {X4STEP_PATH_CTL, "PATH_CTL", sizeof(x4step_path_ctl), true},
    {X4STEP_GET_PROBE, "GET_PROBE", sizeof(x4step_probe), false},
    {X4STEP_ESTOP, "ESTOP", sizeof(x4step_estop), false},
};
constexpr int kNumCmds = sizeof(kCmds) / sizeof(kCmds[0]);
constexpr int kUnknownOurs = kNumCmds;  // stats slot: our magic, unknown number
constexpr int kForeign = kNumCmds + 1;  // stats slot: other magics
constexpr int kSlots = kNumCmds + 2;

int cmd_index(unsigned long cmd) {
  for (int i = 0; i < kNumCmds; i++)
    if (kCmds[i].nr == cmd) return i;
  return _IOC_TYPE(cmd) == kMagic ? kUnknownOurs : kForeign;
}
const char *slot_name(int i) {
  return i < kNumCmds ? kCmds[i].name : i == kUnknownOurs ? "unknown-0xB4" : "other-magic";
}

// Magics the VFS handles itself before the driver sees them (FIOCLEX,
// FIONBIO, FIOASYNC, FIOQSIZE, FIONREAD: 'T'; FIFREEZE/FITHAW/FS_IOC_FSGETXATTR:
// 'X'; FS_IOC_GETFLAGS/FIEMAP: 'f'; FICLONE/FIDEDUPERANGE: 0x94; FIBMAP/FIGETBSZ:
// 0; FS_IOC_GETFSUUID: 0x15): never sent (FIFREEZE would freeze devtmpfs).
bool vfs_magic(unsigned magic) {
  return magic == 0 || magic == 0x15 || magic == 'T' || magic == 'X' || magic == 'f' || magic == 0x94;
}

// Per-slot statistics: calls, accepted (returned 0), errors by errno.
struct Stats {
  std::atomic<long> calls[kSlots];
  std::atomic<long> ok[kSlots];
  std::atomic<long> err[kSlots][64];
  std::atomic<long> skipped{0};
  Stats() { reset(); }
  void reset() {
    for (int i = 0; i < kSlots; i++) {
      calls[i] = 0;
      ok[i] = 0;
      for (auto &e : err[i]) e = 0;
    }
    skipped = 0;
  }
  long total() const {
    long n = 0;
    for (int i = 0; i < kSlots; i++) n += calls[i];
    return n;
  }
  void print(const char *phase) const {
    std::lock_guard<std::mutex> lk(g_print);
    std::printf("x4fuzz: phase %s: %ld ioctls (%ld valid-looking calls skipped)\n", phase, total(),
                skipped.load());
    for (int i = 0; i < kSlots; i++) {
      if (!calls[i]) continue;
      std::printf("x4fuzz:   %-16s %8ld calls %8ld accepted", slot_name(i), calls[i].load(), ok[i].load());
      for (int e = 1; e < 64; e++)
        if (err[i][e]) std::printf(" %s:%ld", strerrorname(e), err[i][e].load());
      std::printf("\n");
    }
    std::fflush(stdout);
  }
  static const char *strerrorname(int e) {
    switch (e) {
      case EPERM:
        return "EPERM";
      case ESRCH:
        return "ESRCH";
      case EBADF:
        return "EBADF";
      case ENOMEM:
        return "ENOMEM";
      case EFAULT:
        return "EFAULT";
      case EBUSY:
        return "EBUSY";
      case EEXIST:
        return "EEXIST";
      case ENODEV:
        return "ENODEV";
      case EINVAL:
        return "EINVAL";
      case ENOTTY:
        return "ENOTTY";
      case ENODATA:
        return "ENODATA";
      default:
        return "E?";
    }
  }
};
Stats g_stats;

uint64_t bit(int e) { return 1ull << e; }

std::string errset(uint64_t m) {
  std::string s;
  for (int e = 0; e < 64; e++)
    if (m & bit(e)) {
      if (!s.empty()) s += "|";
      s += e ? Stats::strerrorname(e) : "0";
    }
  return s;
}

// ------------------------------------------------------------------ memory

// Each thread's memory for payloads: a read-write buffer, a page followed by a
// PROT_NONE guard page, a read-only page and an inaccessible page.
struct Arena {
  uint8_t *rw = nullptr;    // 3 pages read-write
  uint8_t *edge = nullptr;  // 1 page read-write, then the guard page
  uint8_t *ro = nullptr;    // 1 page read-only
  uint8_t *none = nullptr;  // 1 page PROT_NONE
  Arena() {
    void *m = mmap(nullptr, 7 * kPage, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (m == MAP_FAILED) die("mmap");
    auto *p = static_cast<uint8_t *>(m);
    rw = p;
    edge = p + 3 * kPage;
    ro = p + 5 * kPage;
    none = p + 6 * kPage;
    if (mprotect(edge + kPage, kPage, PROT_NONE) || mprotect(ro, kPage, PROT_READ) ||
        mprotect(none, kPage, PROT_NONE))
      die("mprotect");
  }
  Arena(const Arena &) = delete;
  Arena &operator=(const Arena &) = delete;
  ~Arena() { munmap(rw, 7 * kPage); }
};

enum PtrKind { P_BUF, P_EDGE, P_RO, P_NULL, P_ONE, P_KERNEL, P_NONCANON, P_NONE, P_KINDS };
const char *const kPtrNames[] = {"buf",      "page-end", "read-only",     "NULL",
                                 "(void*)1", "kernel",   "non-canonical", "PROT_NONE"};

struct Payload {
  PtrKind kind = P_BUF;
  unsigned long arg = 0;
  size_t readable = 0;             // bytes the kernel can read at arg
  size_t writable = 0;             // bytes the kernel can write at arg
  const uint8_t *bytes = nullptr;  // what it reads (the first `readable`)
};

constexpr size_t kMaxPayload = sizeof(x4step_timing) + 64;

// Place `content` (kMaxPayload bytes) where `kind` says; `size` is the size the
// command uses (for page-end placement).
Payload place(Arena &ar, Rng &r, PtrKind kind, const uint8_t *content, size_t size) {
  Payload p;
  p.kind = kind;
  switch (kind) {
    case P_BUF: {
      size_t off = r.below(8) * 8;
      std::memcpy(ar.rw + off, content, kMaxPayload);
      p.arg = reinterpret_cast<unsigned long>(ar.rw + off);
      p.readable = p.writable = 3 * kPage - off;
      p.bytes = ar.rw + off;
      break;
    }
    case P_EDGE: {
      // k bytes before the guard page: fits exactly, one short, random.
      size_t k;
      switch (r.below(4)) {
        case 0:
          k = size;
          break;
        case 1:
          k = size ? size - 1 : 0;
          break;
        case 2:
          k = 0;
          break;
        default:
          k = r.below(static_cast<uint32_t>(size + 1));
          break;
      }
      if (k > kPage) k = kPage;
      uint8_t *at = ar.edge + kPage - k;
      std::memset(at, 0, k);
      std::memcpy(at, content, std::min(k, kMaxPayload));
      p.arg = reinterpret_cast<unsigned long>(at);
      p.readable = p.writable = k;
      p.bytes = at;
      break;
    }
    case P_RO: {
      if (mprotect(ar.ro, kPage, PROT_READ | PROT_WRITE)) die("mprotect");
      std::memcpy(ar.ro, content, std::min(kMaxPayload, kPage));
      if (mprotect(ar.ro, kPage, PROT_READ)) die("mprotect");
      p.arg = reinterpret_cast<unsigned long>(ar.ro);
      p.readable = kPage;
      p.writable = 0;
      p.bytes = ar.ro;
      break;
    }
    case P_NULL:
      p.arg = 0;
      break;
    case P_ONE:
      p.arg = 1;
      break;
    case P_KERNEL:
      p.arg = 0xffffffff81000000ul + r.below(1 << 20);
      break;
    case P_NONCANON:
      p.arg = 0x0000800000000000ul + r.below(1 << 20);
      break;
    case P_NONE:
      p.arg = reinterpret_cast<unsigned long>(ar.none + r.below(kPage));
      break;
    default:
      break;
  }
  return p;
}

PtrKind random_ptr_kind(Rng &r, bool mostly_good) {
  if (mostly_good && r.chance(90)) return P_BUF;
  unsigned x = r.below(100);
  if (x < 40) return P_BUF;
  if (x < 60) return P_EDGE;
  if (x < 72) return P_RO;
  return static_cast<PtrKind>(P_NULL + r.below(P_KINDS - P_NULL));
}

// ------------------------------------------------------------------ expectations

// X4Step result codes (kmod/engine/x4_check.h).
enum {
  XR_OK = 0,
  XR_NO_STEPS = 1,
  XR_FREQ_HIGH = 2,
  XR_FREQ_LOW = 3,
  XR_RAMP_HIGH = 4,
  XR_RAMP_FREQ = 5,
  XR_NOT_ACTIVE = 7,
  XR_PARAM = 8,
  XR_IS_ACTIVE = 10,
  XR_NOT_LOADED = 11,
  XR_IS_LOADED = 12,
  XR_STEPS_HIGH = 13
};

// The errno that goes with an X4Step code in `result` (x4step.h), -1 for none.
int code_errno(int32_t code) {
  switch (code) {
    case XR_OK:
      return 0;
    case XR_NOT_ACTIVE:
      return ESRCH;
    case XR_IS_ACTIVE:
      return EBUSY;
    case XR_NOT_LOADED:
      return ENODATA;
    case XR_IS_LOADED:
      return EEXIST;
    default:
      return code >= XR_NO_STEPS && code <= XR_STEPS_HIGH ? EINVAL : -1;
  }
}

int ramp_code(int32_t freq, int32_t ramp) {
  if (freq > 20000) return XR_FREQ_HIGH;
  if (freq < 10) return XR_FREQ_LOW;
  if (ramp > 1000) return XR_RAMP_HIGH;
  if (ramp < 0) return XR_PARAM;
  if (ramp > freq) return XR_RAMP_FREQ;
  return XR_OK;
}

int load_code(const x4step_move &m) {
  int c = ramp_code(m.freq_hz, m.ramp_ms);
  if (c) return c;
  bool any = false;
  for (int32_t s : m.steps) {
    if (s > kStepsMax || s < -kStepsMax) return XR_STEPS_HIGH;
    any |= s != 0;
  }
  return any ? XR_OK : XR_NO_STEPS;
}

// The profile rules of x4step.h (reserved fields aside).
bool profile_ok(const x4step_profile &p) {
  auto ramp_ok = [&](uint32_t a) {
    return a <= X4STEP_ACC_MAX && (!a || p.vm <= uint64_t{kRampSecondsMax} * a);
  };
  return p.vm >= 1 && p.vm <= X4STEP_VEL_MAX && p.v0 <= p.vm && p.ve <= p.vm && ramp_ok(p.a0) &&
         ramp_ok(p.ae);
}

// Switch inputs 0..5, nc 5 bits, reserved bytes zero.
bool switches_ok(const x4step_switches &s) {
  for (uint8_t b : s.reserved)
    if (b) return false;
  for (int i = 0; i < X4STEP_AXES; i++)
    if (s.ref[i] > kInputs || s.plus[i] > kInputs || s.minus[i] > kInputs) return false;
  return s.nc < 1u << kInputs;
}

// A reference run speed: signed, non-zero, at most X4STEP_VEL_MAX.
bool vref_ok(int32_t v) { return v && v <= X4STEP_VEL_MAX && v >= -X4STEP_VEL_MAX; }

// What a call may return: success (valid) and/or the errnos in `errs`.
struct Expect {
  bool may_succeed = false;
  uint64_t errs = 0;
  int result_code = -1;  // the X4Step code expected in `result` with EINVAL (-1: any)
  const char *why = "";  // why it is invalid
};

// What the device showed just before a call (read back just after, too).
struct Snapshot {
  x4step_status st;
  x4step_config cfg;
  x4step_step_timing tim;
  x4step_axes axes;
  x4step_switches sw;
  x4step_profile prof[X4STEP_AXES];
  uint32_t running() const {  // the axes with X4STEP_AX_RUN
    uint32_t m = 0;
    for (int i = 0; i < X4STEP_AXES; i++)
      if (axes.axis[i].state & X4STEP_AX_RUN) m |= 1u << i;
    return m;
  }
};

// What the fuzzer knows about the device when it makes the call.
struct Known {
  bool controller = false;   // the descriptor is the controller
  bool idle = false;         // single-threaded and GET_STATUS said: nothing runs, nothing loaded
  bool active = true;        // a move may run (single-threaded: GET_STATUS said so)
  uint32_t run = 0xf;        // the axes that may be moving (single-threaded: GET_AXES said so)
  bool state_known = false;  // single-threaded: mode, timing, switches and profiles are the device's
  uint32_t mode = 0;         // x4step_config.output_mode
  x4step_step_timing timing{};
  x4step_switches sw{};
  x4step_profile prof[X4STEP_AXES]{};
  // Single-threaded: moves may end meanwhile, none can start.
  void learn(const Snapshot &s) {
    idle = !(s.st.flags & (X4STEP_ST_ACTIVE | X4STEP_ST_LOADED));
    active = s.st.flags & X4STEP_ST_ACTIVE;
    run = s.running();
    state_known = true;
    mode = s.cfg.output_mode;
    timing = s.tim;
    sw = s.sw;
    std::memcpy(prof, s.prof, sizeof prof);
  }
};

// The axes the output mode drives: the SMC boards 3 (all 4 if unknown).
uint32_t mode_axes(const Known &k) { return k.mode != X4STEP_MODE_CLOCK_DIR ? 0x7 : 0xf; }

// Whether steps at freq fit the port's step timing (x4step.h): X4ErrFreqTooHigh if not.
int fit_code(const Known &k, int32_t freq) {
  if (k.mode != X4STEP_MODE_CLOCK_DIR) return XR_OK;
  uint64_t period = 1000000000ull / static_cast<uint64_t>(freq);
  const x4step_step_timing &t = k.timing;
  bool fits = t.pulse_ns ? uint64_t{t.pulse_ns} + t.space_ns <= period : t.space_ns <= period / 2;
  return fits ? XR_OK : XR_FREQ_HIGH;
}

bool timing_in_range(const x4step_step_timing &t) {
  const uint32_t max = 1000000;
  return t.pulse_ns <= max && (t.pulse_ns == 0 || t.pulse_ns >= 1000) && t.space_ns <= max &&
         t.dir_setup_ns <= max && t.dir_hold_ns <= max;
}

// Set before any SET_CONFIG to a phase mode goes out: the data register then
// holds phase patterns, not clock and direction bits.
std::atomic<bool> g_phase_mode_possible{false};

// The axes whose profile may be faster than kLongHz (known exactly after each
// single-threaded call), and whether valid profiles may be (not while threads
// run: one thread's fast profile could meet another's long move).
std::atomic<uint32_t> g_fast_axes{0xf};
std::atomic<bool> g_fast_profiles{true};

uint32_t fast_axes(const Snapshot &s) {
  uint32_t m = 0;
  for (int i = 0; i < X4STEP_AXES; i++)
    if (s.prof[i].vm > kLongHz) m |= 1u << i;
  return m;
}

Expect expect(unsigned long cmd, const Payload &p, const Known &k) {
  Expect e;
  auto invalid = [&](const char *why, uint64_t errs = bit(EINVAL)) {
    e.errs = errs;
    e.why = why;
    return e;
  };
  auto bad_arg = [&](int code, const char *why) {  // EINVAL with `code` in `result`
    e.result_code = code;
    return invalid(why);
  };
  auto valid = [&](uint64_t errs) {
    e.may_succeed = true;
    e.errs = errs;
    return e;
  };
  int i = cmd_index(cmd);
  if (i >= kNumCmds) return invalid("unknown command", bit(ENOTTY));
  const Cmd &c = kCmds[i];
  if (cmd == X4STEP_ESTOP) {  // changes state, from any descriptor
    x4step_estop es;
    if (p.readable < sizeof es) return invalid("bad pointer", bit(EFAULT));
    std::memcpy(&es, p.bytes, sizeof es);
    if (es.how > X4STEP_HALT_STOP || es.flags || es.reserved[0] || es.reserved[1])
      return invalid("how not BRAKE or STOP, or flags or reserved");
    return valid(bit(ESRCH));  // nothing runs
  }
  if (!c.state) {
    uint64_t nomem = cmd == X4STEP_GET_TIMING || cmd == X4STEP_GET_TIMING_V2 ? bit(ENOMEM) : 0;
    // GET_PROFILE reads the axis first, then writes the whole profile.
    uint32_t axis;
    if (cmd == X4STEP_GET_PROFILE && p.readable >= sizeof axis) {
      std::memcpy(&axis, p.bytes, sizeof axis);
      if (axis < 1 || axis > X4STEP_AXES) return invalid("axis not 1..4");
    }
    return p.writable >= c.size ? valid(nomem) : invalid("bad pointer", bit(EFAULT) | nomem);
  }
  if (!k.controller) return invalid("read-only descriptor", bit(EBADF));
  if (c.size && p.readable < c.size) return invalid("bad pointer", bit(EFAULT));
  // The ioctls with a `result` make sure it is writable before they look at
  // the arguments.
  if (c.result_off >= 0 && p.writable < c.size) return invalid("result not writable", bit(EFAULT));
  // Mode, step timing, switches or profiles unknown (threads): maybe refused.
  const uint64_t unknown = k.state_known ? 0 : bit(EINVAL);
  // EBUSY only if a move may run (and the arguments are valid: checked first).
  const uint64_t busy = k.active ? bit(EBUSY) : 0;
  // A start may need more port writes per second than the port's budget
  // beside what runs (a goto of fast axes even alone): ERANGE, with the
  // result X4ErrFreqTooHigh (checked with the result below).
  const uint64_t budget = bit(ERANGE);
  switch (cmd) {
    case X4STEP_START:
      return k.idle ? invalid("nothing loaded", bit(ENODATA)) : valid(bit(ENODATA) | bit(EBUSY) | budget);
    case X4STEP_BRAKE:
    case X4STEP_STOP:
      return k.idle ? invalid("nothing runs", bit(ESRCH)) : valid(bit(ESRCH));
    case X4STEP_LOAD: {
      x4step_move m;
      std::memcpy(&m, p.bytes, sizeof m);
      if (m.flags) return bad_arg(XR_PARAM, "flags != 0");
      // Frequency, then ramp, then paths; then the port's timing and mode.
      int code = load_code(m);
      if (!code && k.state_known) code = fit_code(k, m.freq_hz);
      if (!code && k.state_known && !(mode_axes(k) & 8) && m.steps[3]) code = XR_PARAM;
      if (code) return bad_arg(code, "argument out of range");
      return valid((k.idle ? 0 : bit(EEXIST)) | unknown);
    }
    case X4STEP_MOVE_ENDLESS: {
      x4step_endless m;
      std::memcpy(&m, p.bytes, sizeof m);
      if (m.flags || m.reserved[0] || m.reserved[1]) return bad_arg(XR_PARAM, "flags/reserved != 0");
      if (m.direction != 1 && m.direction != -1) return bad_arg(XR_PARAM, "direction not +-1");
      if (m.axis < 1 || m.axis > X4STEP_AXES || !(mode_axes(k) & (1u << (m.axis - 1))))
        return bad_arg(XR_PARAM, "axis");
      // Axis 4 in an unknown mode (threads): maybe refused for the axis first.
      if (int code = ramp_code(m.freq_hz, m.ramp_ms))
        return bad_arg(k.state_known || m.axis < X4STEP_AXES ? code : -1, "freq/ramp");
      if (k.state_known && fit_code(k, m.freq_hz)) return bad_arg(XR_FREQ_HIGH, "freq vs step timing");
      // Then refused if a move is loaded (EEXIST), or runs on the axis (EBUSY).
      return valid((k.idle ? 0 : bit(EEXIST)) | ((k.run & (1u << (m.axis - 1))) ? bit(EBUSY) : 0) | unknown |
                   budget);
    }
    case X4STEP_SET_OUTPUT: {
      x4step_output o;
      std::memcpy(&o, p.bytes, sizeof o);
      if ((o.signal != X4STEP_OUT_SIGNAL1 && o.signal != X4STEP_OUT_SIGNAL2) || o.level > 1)
        return invalid("signal/level");
      return valid(0);
    }
    case X4STEP_SET_OUTPUTS: {
      x4step_outputs o;
      std::memcpy(&o, p.bytes, sizeof o);
      const uint32_t sig = X4STEP_OUT_SIGNAL1 | X4STEP_OUT_SIGNAL2;
      for (uint32_t r : o.reserved)
        if (r) return invalid("reserved != 0");
      if (!o.mask || (o.mask & ~sig) || (o.levels & ~o.mask) || o.flags) return invalid("mask/levels/flags");
      return valid(0);
    }
    case X4STEP_SET_BRAKE_CODES: {
      x4step_brake_codes b;
      std::memcpy(&b, p.bytes, sizeof b);
      if (b.reserved) return invalid("reserved != 0");
      if (b.count > X4STEP_MAX_BRAKE_CODES) return invalid("count > 20");
      for (uint32_t j = 0; j < b.count; j++)
        if (b.codes[j] == 0 || b.codes[j] > 255) return invalid("code not 1..255");
      return valid(0);
    }
    case X4STEP_SET_CONFIG: {
      x4step_config cf;
      std::memcpy(&cf, p.bytes, sizeof cf);
      for (uint32_t r : cf.reserved)
        if (r) return invalid("reserved != 0");
      if (cf.clock_invert > 0xf || cf.dir_invert > 0xf || (cf.flags & ~X4STEP_CFG_KEYS_SWALLOW))
        return invalid("mask out of range");
      if (cf.output_mode > X4STEP_MODE_SMC_PHASE_HOLD) return invalid("output_mode > 2");
      return valid(busy);
    }
    case X4STEP_SET_STEP_TIMING: {
      x4step_step_timing t;
      std::memcpy(&t, p.bytes, sizeof t);
      for (uint32_t r : t.reserved)
        if (r) return invalid("reserved != 0");
      if (!timing_in_range(t)) return invalid("timing out of range");
      return valid(busy);
    }
    case X4STEP_SET_PROFILE: {
      x4step_profile pr;
      std::memcpy(&pr, p.bytes, sizeof pr);
      if (pr.reserved[0] || pr.reserved[1]) return invalid("reserved != 0");
      if (pr.axis < 1 || pr.axis > X4STEP_AXES) return invalid("axis not 1..4");
      if (!profile_ok(pr)) return invalid("profile out of range");
      return valid(0);  // for the axis' next move: also while it runs
    }
    case X4STEP_GOTO: {
      x4step_goto g;
      std::memcpy(&g, p.bytes, sizeof g);
      if ((g.flags & ~X4STEP_GOTO_RELATIVE) || g.reserved[0] || g.reserved[1] || g.reserved[2])
        return bad_arg(XR_PARAM, "flags/reserved != 0");
      if (!g.axes || (g.axes & ~mode_axes(k))) return bad_arg(XR_PARAM, "axes");
      // Each axis' profile speed must fit the step timing; then the axes
      // must be idle.
      for (int a = 0; a < X4STEP_AXES && k.state_known; a++)
        if ((g.axes & (1u << a)) && fit_code(k, static_cast<int32_t>(k.prof[a].vm)))
          return bad_arg(XR_FREQ_HIGH, "profile speed vs step timing");
      return valid(((g.axes & k.run) ? bit(EBUSY) : 0) | unknown | budget);
    }
    case X4STEP_HOME: {
      x4step_home h;
      std::memcpy(&h, p.bytes, sizeof h);
      if (h.reserved[0] || h.reserved[1]) return bad_arg(XR_PARAM, "reserved != 0");
      if (!(h.phases & X4STEP_HOME_AUTO) || h.phases > (X4STEP_HOME_AUTO | X4STEP_HOME_BRAKE) ||
          ((h.phases & X4STEP_HOME_BRAKE) && !(h.phases & X4STEP_HOME_PHASE1)))
        return bad_arg(XR_PARAM, "phases");
      if (h.axis < 1 || h.axis > X4STEP_AXES || !(mode_axes(k) & (1u << (h.axis - 1))))
        return bad_arg(XR_PARAM, "axis");
      bool p1 = h.phases & X4STEP_HOME_PHASE1, p2 = h.phases & X4STEP_HOME_PHASE2;
      if ((p1 && !vref_ok(h.vref1)) || (p2 && !vref_ok(h.vref2))) return bad_arg(XR_PARAM, "vref");
      if (!h.sref || h.sref > INT32_MAX) return bad_arg(XR_PARAM, "sref not 1..2^31-1");
      if (k.state_known && !k.sw.ref[h.axis - 1]) return bad_arg(XR_PARAM, "no reference switch");
      if (k.state_known && p1 && (h.phases & X4STEP_HOME_BRAKE) && k.prof[h.axis - 1].ae &&
          uint64_t(std::abs(h.vref1)) > 3600ull * k.prof[h.axis - 1].ae)
        return bad_arg(XR_PARAM, "phase 1's brake along ae longer than an hour");
      if (k.state_known && ((p1 && fit_code(k, std::abs(h.vref1))) || (p2 && fit_code(k, std::abs(h.vref2)))))
        return bad_arg(XR_FREQ_HIGH, "vref vs step timing");
      return valid(((k.run & (1u << (h.axis - 1))) ? bit(EBUSY) : 0) | unknown | budget);
    }
    case X4STEP_HALT: {
      x4step_halt h;
      std::memcpy(&h, p.bytes, sizeof h);
      if (!h.axes || h.axes > 0xf || h.how > X4STEP_HALT_STOP || h.reserved[0] || h.reserved[1])
        return invalid("axes/how/reserved");
      return (h.axes & k.run) ? valid(bit(ESRCH)) : invalid("none of the axes runs", bit(ESRCH));
    }
    case X4STEP_SET_POSITION: {
      x4step_position sp;
      std::memcpy(&sp, p.bytes, sizeof sp);
      if (!sp.axes || sp.axes > 0xf || sp.reserved) return invalid("axes/reserved");
      return valid(0);  // stops the axes' moves first
    }
    case X4STEP_SET_SWITCHES: {
      x4step_switches sw;
      std::memcpy(&sw, p.bytes, sizeof sw);
      if (!switches_ok(sw)) return invalid("input > 5, nc > 0x1f or reserved != 0");
      return valid(busy);
    }
    case X4STEP_SET_PATH_CONFIG: {
      x4step_path_config pc;
      std::memcpy(&pc, p.bytes, sizeof pc);
      if (pc.reserved || pc.probe > 5 || (pc.flags & ~(X4STEP_PATH_KEYS_ABORT | X4STEP_PATH_PROBE_NC)))
        return invalid("reserved, probe input > 5 or unknown flags");
      if (pc.depth && (pc.depth < X4STEP_PATH_DEPTH_MIN || pc.depth > X4STEP_PATH_DEPTH_MAX ||
                       (pc.depth & (pc.depth - 1))))
        return invalid("depth not a power of 2 in 256..4096");
      // A path may be queued (phase c writes segments): EBUSY.
      return valid(busy | bit(EBUSY) | bit(ENOMEM));
    }
    case X4STEP_PATH_CTL: {
      x4step_path_ctl pc;
      std::memcpy(&pc, p.bytes, sizeof pc);
      if (pc.reserved[0] || pc.reserved[1] || (pc.value && pc.cmd != X4STEP_PATH_OVERRIDE))
        return invalid("reserved, or a value with another command than OVERRIDE");
      if (pc.cmd == X4STEP_PATH_OVERRIDE)
        return pc.value >= 1 && pc.value <= 200 ? valid(0) : invalid("override not 1..200");
      if (pc.cmd < X4STEP_PATH_HOLD || pc.cmd > X4STEP_PATH_CLEAR) return invalid("unknown command");
      if (pc.cmd == X4STEP_PATH_CLEAR) return valid(0);
      return valid(bit(ESRCH));  // no path (or an abort under way)
    }
    default:
      break;
  }
  return invalid("?");
}

// ------------------------------------------------------------------ sanity of reads

bool status_sane(const x4step_status &st, std::string &why) {
  char buf[200];
  const uint32_t known = X4STEP_ST_ACTIVE | X4STEP_ST_LOADED | X4STEP_ST_CONTROLLED | X4STEP_ST_INPUTS_STALE;
  if (st.flags & ~known)
    why = "unknown flags";
  else if (!(st.flags & X4STEP_ST_INPUTS_STALE) != !!(st.flags & X4STEP_ST_CONTROLLED))
    why = "inputs stale while controlled, or live without a controller";
  else if (st.last_brake_code > 255)
    why = "last_brake_code > 255";
  else if (st.inputs & ~0x1fu)
    why = "inputs beyond 5 bits";
  else if (st.outputs & ~0xfu)
    why = "outputs beyond 4 bits";
  else if (st.data > 0xff)
    why = "data beyond 8 bits";
  else if (st.reserved0)
    why = "reserved != 0";
  else if ((st.flags & X4STEP_ST_ACTIVE) && !(st.flags & X4STEP_ST_CONTROLLED))
    why = "active without controller";
  else if (!(st.flags & X4STEP_ST_ACTIVE) && (st.outputs & (X4STEP_OUT_AKTIV | X4STEP_OUT_BOOST)))
    why = "AKTIV/BOOST high while idle";
  else if (!(st.flags & X4STEP_ST_ACTIVE) && (st.data & 0xaa) && !g_phase_mode_possible)
    why = "clock high while idle";
  else {
    for (int64_t s : st.steps)
      if (s > 2 * kStepsMax || s < -2 * kStepsMax) why = "step counter out of range";
  }
  if (why.empty()) return true;
  std::snprintf(buf, sizeof buf, " (flags 0x%x code %u in 0x%x out 0x%x data 0x%x steps %lld %lld %lld %lld)",
                st.flags, st.last_brake_code, st.inputs, st.outputs, st.data,
                static_cast<long long>(st.steps[0]), static_cast<long long>(st.steps[1]),
                static_cast<long long>(st.steps[2]), static_cast<long long>(st.steps[3]));
  why += buf;
  return false;
}

bool axes_sane(const x4step_axes &ax, std::string &why) {
  const uint32_t known = X4STEP_AX_RUN | X4STEP_AX_SYNC | X4STEP_AX_ERROR | X4STEP_AX_REF1 | X4STEP_AX_REF2 |
                         X4STEP_AX_ACCEL | X4STEP_AX_CRUISE | X4STEP_AX_DECEL;
  const uint32_t moving =
      X4STEP_AX_REF1 | X4STEP_AX_REF2 | X4STEP_AX_ACCEL | X4STEP_AX_CRUISE | X4STEP_AX_DECEL;
  const uint32_t errors =
      X4STEP_AXERR_REF_TRAVEL | X4STEP_AXERR_LIMIT_POS | X4STEP_AXERR_LIMIT_NEG | X4STEP_AXERR_AMBIGUOUS;
  char buf[200];
  if ((ax.inputs | ax.switches) >> kInputs)
    why = "inputs/switches beyond 5 bits";
  else if (ax.reserved || (ax.flags & ~X4STEP_ST_INPUTS_STALE))
    why = "reserved != 0 or unknown flags";
  for (int i = 0; why.empty() && i < X4STEP_AXES; i++) {
    const x4step_axis &a = ax.axis[i];
    int ramp = !!(a.state & X4STEP_AX_ACCEL) + !!(a.state & X4STEP_AX_CRUISE) + !!(a.state & X4STEP_AX_DECEL);
    if (a.state & ~known)
      why = "unknown state bits";
    else if (a.error & ~errors)
      why = "unknown error bits";
    else if (!(a.state & X4STEP_AX_ERROR) != !a.error)
      why = "AX_ERROR and the error bits disagree";
    else if (!(a.state & X4STEP_AX_RUN) && ((a.state & moving) || a.velocity))
      why = "an axis that does not run has a motion state or speed";
    else if (ramp > 1 || ((a.state & X4STEP_AX_REF1) && (a.state & X4STEP_AX_REF2)))
      why = "two motion states at once";
    else if (a.velocity > kVelSlack)
      why = "speed beyond X4STEP_VEL_MAX";
    else
      continue;
    std::snprintf(buf, sizeof buf, " (axis %d: position %d state 0x%x error 0x%x velocity %u)", i + 1,
                  a.position, a.state, a.error, a.velocity);
    why += buf;
  }
  if (why.empty()) return true;
  std::snprintf(buf, sizeof buf, " (inputs 0x%x switches 0x%x)", ax.inputs, ax.switches);
  why += buf;
  return false;
}

std::string hex(const void *p, size_t n) {
  std::string s;
  char b[4];
  for (size_t i = 0; i < n; i++) {
    std::snprintf(b, sizeof b, "%02x", static_cast<const uint8_t *>(p)[i]);
    s += b;
  }
  return s;
}

// Check what a successful read wrote to `out`; `req` is the u32 the argument
// began with before the call (GET_PROFILE: the axis asked for).
void check_read_result(unsigned long cmd, const uint8_t *out, uint32_t req) {
  std::string why;
  if (cmd == X4STEP_GET_STATUS) {
    x4step_status st;
    std::memcpy(&st, out, sizeof st);
    if (!status_sane(st, why)) violation("GET_STATUS: %s", why.c_str());
  } else if (cmd == X4STEP_GET_INFO) {
    x4step_info in;
    std::memcpy(&in, out, sizeof in);
    bool res = false;
    for (uint32_t r : in.reserved) res |= r != 0;
    const bool ring = in.event_buffer >= 16 && !(in.event_buffer & (in.event_buffer - 1));
    if (in.abi_version != X4STEP_ABI_VERSION || in.axes != X4STEP_AXES || in.port > 15 || res || !ring)
      violation("GET_INFO: abi %u axes %u port %u events %u reserved %d", in.abi_version, in.axes, in.port,
                in.event_buffer, res);
  } else if (cmd == X4STEP_GET_CONFIG) {
    x4step_config cf;
    std::memcpy(&cf, out, sizeof cf);
    bool res = false;
    for (uint32_t r : cf.reserved) res |= r != 0;
    if (cf.clock_invert > 0xf || cf.dir_invert > 0xf || (cf.flags & ~X4STEP_CFG_KEYS_SWALLOW) ||
        cf.output_mode > X4STEP_MODE_SMC_PHASE_HOLD || res)
      violation("GET_CONFIG: clock 0x%x dir 0x%x flags 0x%x mode %u reserved %d", cf.clock_invert,
                cf.dir_invert, cf.flags, cf.output_mode, res);
  } else if (cmd == X4STEP_GET_STEP_TIMING) {
    x4step_step_timing t;
    std::memcpy(&t, out, sizeof t);
    bool res = false;
    for (uint32_t r : t.reserved) res |= r != 0;
    if (!timing_in_range(t) || res)
      violation("GET_STEP_TIMING: pulse %u space %u setup %u hold %u reserved %d", t.pulse_ns, t.space_ns,
                t.dir_setup_ns, t.dir_hold_ns, res);
  } else if (cmd == X4STEP_GET_TIMING || cmd == X4STEP_GET_TIMING_V2) {
    // Big: read it in place (version 2's part).
    const auto *t = reinterpret_cast<const x4step_timing *>(out);
    uint64_t sum = t->beyond;
    for (uint32_t h : t->hist) sum += h;
    if (sum != t->events || t->reserved || (t->events == 0 && t->late_max_ns))
      violation("GET_TIMING: events %llu, histogram+beyond %llu, max %llu, reserved %llu",
                static_cast<unsigned long long>(t->events), static_cast<unsigned long long>(sum),
                static_cast<unsigned long long>(t->late_max_ns),
                static_cast<unsigned long long>(t->reserved));
  } else if (cmd == X4STEP_GET_PROFILE) {
    x4step_profile pr;
    std::memcpy(&pr, out, sizeof pr);
    if (pr.axis != req || pr.reserved[0] || pr.reserved[1] || !profile_ok(pr))
      violation("GET_PROFILE of axis %u: axis %u v0 %u ve %u vm %u a0 %u ae %u reserved %u %u", req, pr.axis,
                pr.v0, pr.ve, pr.vm, pr.a0, pr.ae, pr.reserved[0], pr.reserved[1]);
  } else if (cmd == X4STEP_GET_SWITCHES) {
    x4step_switches sw;
    std::memcpy(&sw, out, sizeof sw);
    if (!switches_ok(sw))
      violation("GET_SWITCHES: input > 5, nc > 0x1f or reserved != 0: %s", hex(&sw, sizeof sw).c_str());
  } else if (cmd == X4STEP_GET_AXES) {
    x4step_axes ax;
    std::memcpy(&ax, out, sizeof ax);
    if (!axes_sane(ax, why)) violation("GET_AXES: %s", why.c_str());
  }
}

// ------------------------------------------------------------------ one call

// Read into v and check what came back; v holds the request (GET_PROFILE:
// the axis `req`), the rest zero.
template <class T>
bool read_dev(int fd, unsigned long cmd, T &v, uint32_t req = 0) {
  std::memset(&v, 0, sizeof v);
  std::memcpy(&v, &req, sizeof req);
  if (ioctl(fd, cmd, &v)) {
    violation("%s failed: %s", slot_name(cmd_index(cmd)), std::strerror(errno));
    return false;
  }
  check_read_result(cmd, reinterpret_cast<const uint8_t *>(&v), req);
  return true;
}

bool snapshot(int fd, Snapshot &s) {
  bool ok = read_dev(fd, X4STEP_GET_STATUS, s.st) && read_dev(fd, X4STEP_GET_CONFIG, s.cfg) &&
            read_dev(fd, X4STEP_GET_STEP_TIMING, s.tim) && read_dev(fd, X4STEP_GET_AXES, s.axes) &&
            read_dev(fd, X4STEP_GET_SWITCHES, s.sw);
  for (uint32_t a = 1; ok && a <= X4STEP_AXES; a++) ok = read_dev(fd, X4STEP_GET_PROFILE, s.prof[a - 1], a);
  return ok;
}

// A call that must work (setup and restore).
void must(int fd, unsigned long cmd, const void *arg, const char *what) {
  if (ioctl(fd, cmd, arg))
    violation("%s: %s failed: %s", what, slot_name(cmd_index(cmd)), std::strerror(errno));
}

// A failed call changed nothing. Single-threaded: the moves that ran before
// it may have gone on or ended, nothing else changed meanwhile.
void check_unchanged(const char *name, int err, const char *why, const Snapshot &b, const Snapshot &a) {
  const char *es = std::strerror(err);
  const uint32_t sig = X4STEP_OUT_SIGNAL1 | X4STEP_OUT_SIGNAL2;
  if (!(b.st.flags & X4STEP_ST_ACTIVE) && (a.st.flags & X4STEP_ST_ACTIVE))
    violation("%s failed (%s, %s) but a move started", name, es, why);
  if (!(b.st.flags & X4STEP_ST_LOADED) && (a.st.flags & X4STEP_ST_LOADED))
    violation("%s failed (%s, %s) but a move got loaded", name, es, why);
  if ((b.st.outputs & sig) != (a.st.outputs & sig))
    violation("%s failed (%s) but the signal outputs changed 0x%x -> 0x%x", name, es, b.st.outputs,
              a.st.outputs);
  if (std::memcmp(&b.cfg, &a.cfg, sizeof a.cfg)) violation("%s failed (%s) but the config changed", name, es);
  if (std::memcmp(&b.tim, &a.tim, sizeof a.tim))
    violation("%s failed (%s) but the step timing changed", name, es);
  if (std::memcmp(&b.sw, &a.sw, sizeof a.sw)) violation("%s failed (%s) but the switches changed", name, es);
  if (std::memcmp(b.prof, a.prof, sizeof a.prof)) violation("%s failed (%s) but a profile changed", name, es);
  for (int i = 0; i < X4STEP_AXES; i++) {
    const x4step_axis &x = b.axes.axis[i], &y = a.axes.axis[i];
    if (!(x.state & X4STEP_AX_RUN) && std::memcmp(&x, &y, sizeof x))
      violation(
          "%s failed (%s, %s) but idle axis %d changed: at %d -> %d, state 0x%x -> 0x%x, error 0x%x -> 0x%x",
          name, es, why, i + 1, x.position, y.position, x.state, y.state, x.error, y.error);
  }
}

// What a successful call must have done (single-threaded): read back.
void check_effect(unsigned long cmd, const Payload &p, const Snapshot &a) {
  if (cmd == X4STEP_SET_OUTPUT) {
    x4step_output o;
    std::memcpy(&o, p.bytes, sizeof o);
    if (!!(a.st.outputs & o.signal) != !!o.level)
      violation("SET_OUTPUT signal %u level %u: outputs 0x%x", o.signal, o.level, a.st.outputs);
  } else if (cmd == X4STEP_SET_OUTPUTS) {
    x4step_outputs o;
    std::memcpy(&o, p.bytes, sizeof o);
    if ((a.st.outputs & o.mask) != o.levels)
      violation("SET_OUTPUTS mask 0x%x levels 0x%x: outputs 0x%x", o.mask, o.levels, a.st.outputs);
  } else if (cmd == X4STEP_SET_PROFILE) {
    x4step_profile pr;
    std::memcpy(&pr, p.bytes, sizeof pr);
    const x4step_profile &g = a.prof[pr.axis - 1];
    if (std::memcmp(&g, &pr, sizeof pr))
      violation("SET_PROFILE axis %u v0 %u ve %u vm %u a0 %u ae %u: reads back v0 %u ve %u vm %u a0 %u ae %u",
                pr.axis, pr.v0, pr.ve, pr.vm, pr.a0, pr.ae, g.v0, g.ve, g.vm, g.a0, g.ae);
  } else if (cmd == X4STEP_SET_SWITCHES) {
    if (std::memcmp(&a.sw, p.bytes, sizeof a.sw))
      violation("SET_SWITCHES %s: reads back %s", hex(p.bytes, sizeof a.sw).c_str(),
                hex(&a.sw, sizeof a.sw).c_str());
  } else if (cmd == X4STEP_SET_POSITION || cmd == X4STEP_HALT) {
    // Stopped at once; SET_POSITION: at the new coordinate, synchronized.
    bool set = cmd == X4STEP_SET_POSITION;
    x4step_position sp{};
    x4step_halt h{};
    if (set) {
      std::memcpy(&sp, p.bytes, sizeof sp);
    } else {
      std::memcpy(&h, p.bytes, sizeof h);
      if (h.how != X4STEP_HALT_STOP) return;
      sp.axes = h.axes;
    }
    for (int i = 0; i < X4STEP_AXES; i++) {
      const x4step_axis &y = a.axes.axis[i];
      if ((sp.axes & (1u << i)) &&
          ((y.state & X4STEP_AX_RUN) ||
           (set && (y.position != sp.position[i] || !(y.state & X4STEP_AX_SYNC) || y.error))))
        violation("%s axes 0x%x: axis %d at %d (set %d), state 0x%x, error 0x%x", slot_name(cmd_index(cmd)),
                  sp.axes, i + 1, y.position, set ? sp.position[i] : 0, y.state, y.error);
    }
  }
}

struct Ctx {
  int fd = -1;
  Known known;
  bool single = false;  // single-threaded: check that failed calls change nothing
};

// Make one call and check it. Returns ioctl's result (-1 with errno, or 0).
int call(Ctx &cx, unsigned long cmd, const Payload &p) {
  Known k = cx.known;
  Snapshot before;
  int idx = cmd_index(cmd);
  bool state_cmd = idx < kNumCmds && kCmds[idx].state;
  bool have_before = cx.single && k.controller && state_cmd && snapshot(cx.fd, before);
  if (have_before) k.learn(before);
  if (cmd == X4STEP_SET_CONFIG && p.readable >= sizeof(x4step_config)) {
    x4step_config cf;
    std::memcpy(&cf, p.bytes, sizeof cf);
    if (cf.output_mode != X4STEP_MODE_CLOCK_DIR) g_phase_mode_possible = true;
  }
  Expect e = expect(cmd, p, k);
  if (opt.invalid_only && state_cmd && e.may_succeed) {
    g_stats.skipped++;
    return -2;
  }
  uint32_t req = 0;  // GET_PROFILE: the axis asked for
  if (p.readable >= sizeof req) std::memcpy(&req, p.bytes, sizeof req);
  errno = 0;
  int ret = ioctl(cx.fd, cmd, p.arg);
  int err = ret ? errno : 0;
  g_stats.calls[idx]++;
  if (!ret)
    g_stats.ok[idx]++;
  else if (err > 0 && err < 64)
    g_stats.err[idx][err]++;

  if (opt.verbose)
    note("%s 0x%lx %s -> %d %s", slot_name(idx), cmd, kPtrNames[p.kind], ret, ret ? std::strerror(err) : "");
  if (ret == 0 && !e.may_succeed) {
    violation("%s (0x%lx, %s pointer) succeeded, expected %s: %s", slot_name(idx), cmd, kPtrNames[p.kind],
              errset(e.errs).c_str(), e.why);
  } else if (ret != 0 && (err <= 0 || err >= 64 || !(e.errs & bit(err)))) {
    violation("%s (0x%lx, %s pointer) failed with %s, expected %s%s%s", slot_name(idx), cmd,
              kPtrNames[p.kind], std::strerror(err), e.may_succeed ? "success or " : "",
              errset(e.errs).c_str(), e.may_succeed ? "" : (std::string(": ") + e.why).c_str());
  }
  // LOAD, MOVE_ENDLESS, GOTO and HOME write the X4Step code back once they
  // got the argument: it goes with the errno, and is the predicted one.
  if (idx < kNumCmds && kCmds[idx].result_off >= 0 && p.writable >= kCmds[idx].size &&
      (ret == 0 || (err != EBADF && err != EFAULT && err != ENODEV))) {
    int32_t got;
    std::memcpy(&got, p.bytes + kCmds[idx].result_off, sizeof got);
    if (code_errno(got) != err && !(got == XR_FREQ_HIGH && err == ERANGE))
      violation("%s: result %d with %s", slot_name(idx), got, ret ? std::strerror(err) : "success");
    else if (err == EINVAL && e.result_code >= 0 && got != e.result_code)
      violation("%s: result %d, expected X4Step code %d (%s)", slot_name(idx), got, e.result_code, e.why);
  }
  if (ret == 0 && idx < kNumCmds && !kCmds[idx].state) check_read_result(cmd, p.bytes, req);

  Snapshot after;
  if (have_before && snapshot(cx.fd, after)) {
    if (after.cfg.output_mode == X4STEP_MODE_CLOCK_DIR) g_phase_mode_possible = false;
    g_fast_axes = fast_axes(after);
    if (ret != 0)
      check_unchanged(slot_name(idx), err, e.why, before, after);
    else
      check_effect(cmd, p, after);
  }
  return ret ? -1 : 0;
}

// ------------------------------------------------------------------ generators

const int32_t kStepVals[] = {0,         1,        -1,        2,        -2,        100,     -100,    16777215,
                             -16777215, 16777216, -16777216, 16777217, -16777217, INT_MAX, INT_MIN, 1 << 30};
const int32_t kFreqVals[] = {9, 10, 11, 100, 1000, 5000, 19999, 20000, 20001, 0, -1, INT_MIN, INT_MAX};
const int32_t kRampVals[] = {0, 1, 10, 999, 1000, 1001, -1, INT_MIN, INT_MAX};

int32_t steps_val(Rng &r, bool small) {
  if (small) return r.range(-200, 200);
  unsigned x = r.below(10);
  if (x < 5) return r.pick(kStepVals);
  if (x < 8) return r.range(-2000, 2000);
  return r.s32();
}
int32_t freq_val(Rng &r, bool small) {
  if (small) return r.range(1000, 20000);
  unsigned x = r.below(10);
  if (x < 6) return r.pick(kFreqVals);
  if (x < 9) return r.range(10, 20000);
  return r.s32();
}
int32_t ramp_val(Rng &r, int32_t freq, bool small) {
  if (small) return r.range(0, 20);
  unsigned x = r.below(10);
  if (x < 5) return r.pick(kRampVals);
  if (x < 7) return freq + r.range(-1, 1);  // around ramp == freq
  if (x < 9) return r.range(0, 1000);
  return r.s32();
}
uint32_t maybe_nonzero(Rng &r, unsigned pct) {
  if (!r.chance(pct)) return 0;
  switch (r.below(3)) {
    case 0:
      return 1;
    case 1:
      return 0x80000000u;
    default:
      return static_cast<uint32_t>(r.next()) | 1;
  }
}

const int32_t kTargetVals[] = {0,       1,       -1,          2,           -2,      1000,      -1000,
                               INT_MAX, INT_MIN, INT_MAX - 1, INT_MIN + 1, 1 << 30, -(1 << 30)};
const uint32_t kVelVals[] = {0, 1, 2, 999, 1000, 45000, 99999, 100000, 100001, 0x80000000u, 0xffffffffu};
const uint32_t kAccVals[] = {0, 1, 2, 13, 1000, 999999, 1000000, 1000001, 0x80000000u, 0xffffffffu};
const int32_t kVrefVals[] = {0,      1,      -1,      1000,   -1000,   45000,   -45000, 99999,
                             -99999, 100000, -100000, 100001, -100001, INT_MAX, INT_MIN};
const uint32_t kSrefVals[] = {0, 1, 2, 1000, 0x7ffffffeu, 0x7fffffffu, 0x80000000u, 0xffffffffu};

uint32_t axis_val(Rng &r) { return r.chance(90) ? r.range(0, 5) : static_cast<uint32_t>(r.next()); }
uint32_t mask_val(Rng &r) {
  unsigned x = r.below(100);
  return x < 90 ? r.range(0, 0x10) : x < 95 ? r.range(0x11, 0xff) : static_cast<uint32_t>(r.next());
}
uint32_t speed_val(Rng &r, uint32_t vm) {  // v0, ve: around vm
  switch (r.below(5)) {
    case 0:
      return 0;
    case 1:
      return vm;
    case 2:
      return vm + 1;
    case 3:
      return r.below(vm + 1);
    default:
      return r.pick(kVelVals);
  }
}
uint32_t acc_val(Rng &r, uint32_t vm) {  // a0, ae: limits, and ramps around 3600 s long
  uint32_t longest = static_cast<uint32_t>((uint64_t{vm} + kRampSecondsMax - 1) / kRampSecondsMax);
  switch (r.below(5)) {
    case 0:
      return r.pick(kAccVals);
    case 1:
      return longest;
    case 2:
      return longest - 1;
    default:
      return r.range(0, X4STEP_ACC_MAX);
  }
}

// `small`: ramps of at most 20 ms (or none), so that a close brakes quickly.
x4step_profile profile_val(Rng &r, bool small) {
  x4step_profile pr{};
  if (small) {
    pr.vm = r.range(100, kLongHz);
    pr.v0 = r.below(pr.vm + 1);
    pr.ve = r.below(pr.vm + 1);
    pr.a0 = r.chance(20) ? 0 : r.range(50 * pr.vm, X4STEP_ACC_MAX);
    pr.ae = r.chance(20) ? 0 : r.range(50 * pr.vm, X4STEP_ACC_MAX);
    return pr;
  }
  unsigned x = r.below(10);
  pr.vm = x < 5 ? r.pick(kVelVals) : x < 9 ? r.range(1, X4STEP_VEL_MAX) : static_cast<uint32_t>(r.next());
  pr.v0 = speed_val(r, pr.vm);
  pr.ve = speed_val(r, pr.vm);
  pr.a0 = acc_val(r, pr.vm);
  pr.ae = acc_val(r, pr.vm);
  if (!g_fast_profiles && profile_ok(pr) && pr.vm > kLongHz) {
    pr.vm = kLongHz;
    pr.v0 = std::min<uint32_t>(pr.v0, kLongHz);
    pr.ve = std::min<uint32_t>(pr.ve, kLongHz);
  }
  return pr;
}

// The positioning commands, structurally valid, with boundary values.
unsigned long gen_positioning(Rng &r, uint8_t *c, bool small) {
  unsigned x = r.below(100);
  if (x < 16) {
    x4step_profile pr = profile_val(r, small);
    pr.axis = axis_val(r);
    for (auto &res : pr.reserved) res = maybe_nonzero(r, 4);
    std::memcpy(c, &pr, sizeof pr);
    return X4STEP_SET_PROFILE;
  }
  if (x < 38) {
    // Targets at the 32-bit limits, relative and absolute; `small`: short.
    // Axes with a fast profile go a short way (relative).
    x4step_goto g{};
    uint32_t fast = g_fast_axes;
    g.axes = mask_val(r);
    g.flags = (r.chance(50) ? X4STEP_GOTO_RELATIVE : 0) | (maybe_nonzero(r, 5) & ~1u);
    if (small) g.flags = r.chance(80) ? X4STEP_GOTO_RELATIVE : 0;
    if (g.axes & fast) g.flags |= X4STEP_GOTO_RELATIVE;
    for (int a = 0; a < X4STEP_AXES; a++) {
      unsigned y = r.below(10);
      g.target[a] = fast & (1u << a)   ? r.range(-kShortSteps, kShortSteps)
                    : small && g.flags ? r.range(-200, 200)
                    : y < 5            ? r.pick(kTargetVals)
                    : y < 8            ? r.range(-2000, 2000)
                                       : r.s32();
    }
    for (auto &res : g.reserved) res = maybe_nonzero(r, 4);
    g.result = r.s32();
    std::memcpy(c, &g, sizeof g);
    return X4STEP_GOTO;
  }
  if (x < 50) {
    x4step_home h{};
    h.axis = axis_val(r);
    h.phases = r.chance(90) ? r.range(0, 8) : static_cast<uint32_t>(r.next());
    for (int32_t *v : {&h.vref1, &h.vref2}) {
      unsigned y = r.below(10);
      *v = y < 5 ? r.pick(kVrefVals) : y < 9 ? r.range(-X4STEP_VEL_MAX, X4STEP_VEL_MAX) : r.s32();
    }
    unsigned y = r.below(10);
    h.sref = small   ? r.range(1, 200)
             : y < 6 ? r.pick(kSrefVals)
             : y < 9 ? r.range(1, 100000)
                     : static_cast<uint32_t>(r.next());
    auto fast = [](int32_t v) { return vref_ok(v) && std::abs(v) > kLongHz; };
    if ((fast(h.vref1) || fast(h.vref2)) && h.sref > kShortSteps) h.sref = r.range(1, kShortSteps);
    for (auto &res : h.reserved) res = maybe_nonzero(r, 5);
    h.result = r.s32();
    std::memcpy(c, &h, sizeof h);
    return X4STEP_HOME;
  }
  if (x < 64) {
    x4step_halt h{};
    h.axes = mask_val(r);
    h.how = r.chance(90) ? r.range(0, 2) : static_cast<uint32_t>(r.next());
    for (auto &res : h.reserved) res = maybe_nonzero(r, 5);
    std::memcpy(c, &h, sizeof h);
    return X4STEP_HALT;
  }
  if (x < 72) {
    x4step_position sp{};
    sp.axes = mask_val(r);
    sp.reserved = maybe_nonzero(r, 5);
    for (auto &pos : sp.position) pos = r.chance(50) ? r.pick(kTargetVals) : r.s32();
    std::memcpy(c, &sp, sizeof sp);
    return X4STEP_SET_POSITION;
  }
  if (x < 84) {
    // Inputs 0..5 mostly; limits rarer than references (they stop moves).
    x4step_switches sw{};
    auto input = [&](unsigned pct) {
      return static_cast<uint8_t>(!r.chance(pct) ? 0 : r.chance(95) ? r.range(1, kInputs) : r.range(6, 255));
    };
    for (int i = 0; i < X4STEP_AXES; i++) {
      sw.ref[i] = input(60);
      sw.plus[i] = input(15);
      sw.minus[i] = input(15);
    }
    sw.nc = static_cast<uint8_t>(r.chance(90) ? r.range(0, 0x1f) : r.range(0x20, 0xff));
    if (r.chance(5)) sw.reserved[r.below(sizeof sw.reserved)] = static_cast<uint8_t>(r.range(1, 255));
    std::memcpy(c, &sw, sizeof sw);
    return X4STEP_SET_SWITCHES;
  }
  if (x < 92) {
    uint32_t axis = axis_val(r);
    std::memcpy(c, &axis, sizeof axis);
    return X4STEP_GET_PROFILE;
  }
  return x < 96 ? X4STEP_GET_SWITCHES : X4STEP_GET_AXES;
}

// A structurally valid command with boundary and random field values (phase b).
// `small`: short, slow-ramped moves only (quick to brake).
unsigned long gen_structured(Rng &r, uint8_t *c, bool small) {
  std::memset(c, 0, kMaxPayload);
  if (r.chance(40)) return gen_positioning(r, c, small);
  unsigned x = r.below(100);
  if (x < 22) {
    x4step_move m{};
    int axes = r.below(4);
    for (int a = 0; a < 4; a++) m.steps[a] = (a == axes || r.chance(30)) ? steps_val(r, small) : 0;
    m.freq_hz = freq_val(r, small);
    m.ramp_ms = ramp_val(r, m.freq_hz, small);
    m.flags = maybe_nonzero(r, 8);
    m.result = r.s32();
    std::memcpy(c, &m, sizeof m);
    return X4STEP_LOAD;
  }
  if (x < 26) {
    x4step_path_ctl pc{};
    pc.cmd = r.chance(85) ? r.range(0, 5) : static_cast<uint32_t>(r.s32());
    pc.value = pc.cmd == X4STEP_PATH_OVERRIDE && r.chance(80) ? r.range(0, 202) : maybe_nonzero(r, 10);
    // Not 1 %: phase c's paths would crawl.
    if (pc.cmd == X4STEP_PATH_OVERRIDE && pc.value >= 1 && pc.value < 50) pc.value += 50;
    pc.reserved[0] = maybe_nonzero(r, 5);
    pc.reserved[1] = maybe_nonzero(r, 5);
    std::memcpy(c, &pc, sizeof pc);
    return X4STEP_PATH_CTL;
  }
  if (x < 28) {
    static const uint32_t depths[] = {0, 1, 255, 256, 257, 384, 512, 1024, 4096, 8192, 0x80000000u};
    x4step_path_config pc{};
    pc.depth = r.chance(90) ? r.pick(depths) : static_cast<uint32_t>(r.s32());
    pc.flags = r.chance(80) ? r.below(4) : static_cast<uint32_t>(r.s32());
    pc.probe = r.chance(90) ? r.below(7) : static_cast<uint32_t>(r.s32());
    pc.reserved = maybe_nonzero(r, 5);
    std::memcpy(c, &pc, sizeof pc);
    return X4STEP_SET_PATH_CONFIG;
  }
  if (x < 36) return X4STEP_START;
  if (x < 46) return X4STEP_BRAKE;
  if (x < 54) return X4STEP_STOP;
  if (x < 64) {
    x4step_endless m{};
    m.axis = r.chance(85) ? r.range(0, 5) : r.s32();
    m.direction = r.chance(85) ? r.range(-2, 2) : r.s32();
    m.freq_hz = freq_val(r, small);
    m.ramp_ms = ramp_val(r, m.freq_hz, small);
    m.flags = maybe_nonzero(r, 8);
    m.reserved[0] = maybe_nonzero(r, 5);
    m.reserved[1] = maybe_nonzero(r, 5);
    m.result = r.s32();
    std::memcpy(c, &m, sizeof m);
    return X4STEP_MOVE_ENDLESS;
  }
  if (x < 74 && r.chance(50)) {
    x4step_outputs o{};
    o.mask = r.chance(90) ? r.range(0, 4) : static_cast<uint32_t>(r.next());
    o.levels = r.chance(90) ? r.range(0, 4) : static_cast<uint32_t>(r.next());
    o.flags = maybe_nonzero(r, 8);
    for (auto &res : o.reserved) res = maybe_nonzero(r, 3);
    std::memcpy(c, &o, sizeof o);
    return X4STEP_SET_OUTPUTS;
  }
  if (x < 74) {
    x4step_output o{};
    o.signal = r.chance(90) ? r.range(0, 5) : static_cast<uint32_t>(r.next());
    o.level = r.chance(90) ? r.range(0, 2) : static_cast<uint32_t>(r.next());
    std::memcpy(c, &o, sizeof o);
    return X4STEP_SET_OUTPUT;
  }
  if (x < 84) {
    x4step_brake_codes b{};
    b.count = r.chance(90) ? r.range(0, 21) : static_cast<uint32_t>(r.next());
    for (auto &code : b.codes) code = static_cast<uint16_t>(r.chance(90) ? r.range(0, 300) : r.next());
    if (r.chance(50))  // mostly valid codes
      for (auto &code : b.codes) code = static_cast<uint16_t>(r.range(1, 255));
    b.reserved = maybe_nonzero(r, 8);
    std::memcpy(c, &b, sizeof b);
    return X4STEP_SET_BRAKE_CODES;
  }
  if (x < 92) {
    x4step_config cf{};
    cf.clock_invert = r.chance(85) ? r.range(0, 0x10) : static_cast<uint32_t>(r.next());
    cf.dir_invert = r.chance(85) ? r.range(0, 0x10) : static_cast<uint32_t>(r.next());
    cf.flags = r.chance(85) ? r.range(0, 2) : static_cast<uint32_t>(r.next());
    for (auto &res : cf.reserved) res = maybe_nonzero(r, 3);
    unsigned m = r.below(100);
    cf.output_mode = m < 70 ? 0 : m < 90 ? r.range(1, 2) : m < 95 ? 3 : static_cast<uint32_t>(r.next());
    // Wiring changes move the clock pins at rest: keep them rare.
    if (r.chance(70)) cf.clock_invert = 0;
    std::memcpy(c, &cf, sizeof cf);
    return X4STEP_SET_CONFIG;
  }
  if (x < 96) {
    static const uint32_t vals[] = {0,      1,      999,     1000,    1001,      20000,
                                    100000, 999999, 1000000, 1000001, 0xffffffff};
    x4step_step_timing t{};
    for (uint32_t *f : {&t.pulse_ns, &t.space_ns, &t.dir_setup_ns, &t.dir_hold_ns})
      *f = r.chance(40) ? 0 : r.chance(70) ? r.pick(vals) : r.below(1100000);
    for (auto &res : t.reserved) res = maybe_nonzero(r, 3);
    std::memcpy(c, &t, sizeof t);
    return X4STEP_SET_STEP_TIMING;
  }
  static const unsigned long reads[] = {X4STEP_GET_STATUS, X4STEP_GET_INFO,      X4STEP_GET_CONFIG,
                                        X4STEP_GET_TIMING, X4STEP_GET_TIMING_V2, X4STEP_GET_STEP_TIMING};
  return r.pick(reads);
}

const uint32_t kSizes[] = {0, 1, 4, 8, 16, 20, 24, 32, 40, 56, 64, 72, 80, 2080, 2079, 2081, 4096, 16383};

unsigned long random_cmd(Rng &r) {
  unsigned x = r.below(100);
  if (x < 40) {  // our magic, any number/direction/size
    return _IOC(r.below(4), kMagic, r.below(256), r.chance(50) ? r.pick(kSizes) : r.below(1 << 14));
  }
  if (x < 75) {  // an exact command, or one bit off
    unsigned long c = kCmds[r.below(kNumCmds)].nr;
    if (r.chance(20)) c ^= 1ul << r.below(32);
    if (vfs_magic(_IOC_TYPE(c))) c = kCmds[0].nr;
    return c;
  }
  unsigned magic;
  do magic = r.below(256);
  while (magic == kMagic || vfs_magic(magic));
  if (r.chance(15))
    return (static_cast<uint32_t>(r.next()) & ~(0xfful << _IOC_TYPESHIFT)) | (magic << _IOC_TYPESHIFT);
  return _IOC(r.below(4), magic, r.below(256), r.below(1 << 14));
}

void random_bytes(Rng &r, uint8_t *c) {
  unsigned mode = r.below(4);
  for (size_t i = 0; i < kMaxPayload; i += 8) {
    uint64_t v = mode == 0 ? 0 : mode == 1 ? r.next() : (r.next() & 0x0000000f0000000full);
    std::memcpy(c + i, &v, std::min<size_t>(8, kMaxPayload - i));
  }
}

size_t cmd_size(unsigned long cmd) {
  int i = cmd_index(cmd);
  return i < kNumCmds ? kCmds[i].size : _IOC_SIZE(cmd);
}

// ------------------------------------------------------------------ phases

bool time_left(Clock::time_point end) { return Clock::now() < end; }

Clock::time_point after(double s) {
  return Clock::now() + std::chrono::microseconds(static_cast<long long>(s * 1e6));
}

int open_dev(int flags) { return open(opt.device.c_str(), flags | O_CLOEXEC); }

// Phase a: command numbers and pointers.
long phase_a(int ctl, int ro, Rng &r, Arena &ar, double secs) {
  Ctx cctl{ctl, {true, false}, true}, cro{ro, {false, false}, true};
  auto end = after(secs);
  uint8_t content[kMaxPayload];
  long n = 0;
  // The sweep: every number of our magic, every direction, a few sizes.
  static const uint32_t sweep_sizes[] = {0, 8, 16, 20, 24, 32, 40, 64, 72, 80, 2080};
  for (unsigned nr = 0; nr < 256 && time_left(end); nr++)
    for (unsigned dir = 0; dir < 4; dir++)
      for (uint32_t size : sweep_sizes) {
        if (dir == 0 && size) continue;
        unsigned long cmd = _IOC(dir, kMagic, nr, size);
        random_bytes(r, content);
        Payload p = place(ar, r, random_ptr_kind(r, false), content, cmd_size(cmd));
        call(r.chance(85) ? cctl : cro, cmd, p);
        n++;
      }
  while (time_left(end)) {
    unsigned long cmd = random_cmd(r);
    random_bytes(r, content);
    Payload p = place(ar, r, random_ptr_kind(r, false), content, cmd_size(cmd));
    call(r.chance(85) ? cctl : cro, cmd, p);
    n++;
  }
  return n;
}

// What the device had at the start: restored at the end.
Snapshot g_initial;

// Probes first: valid MOVE_ENDLESS, GOTO, HOME and LOAD arguments in
// read-only memory, so that `result` cannot be written back. The call fails
// (EFAULT) and must then have started or loaded nothing. If a motor runs
// anyway it is stopped (the violation is recorded); a loaded move is dropped
// by reopening.
template <class T>
void probe(int ctl, Rng &r, Arena &ar, unsigned long cmd, const T &arg) {
  Ctx cx{ctl, {true, false}, true};
  uint8_t content[kMaxPayload] = {};
  std::memcpy(content, &arg, sizeof arg);
  call(cx, cmd, place(ar, r, P_RO, content, sizeof arg));
  x4step_status st;
  if (read_dev(ctl, X4STEP_GET_STATUS, st) && (st.flags & X4STEP_ST_ACTIVE)) ioctl(ctl, X4STEP_STOP);
}

void probes(int &ctl, Rng &r, Arena &ar) {
  x4step_endless e{};
  e.axis = 1;
  e.direction = 1;
  e.freq_hz = 1000;
  probe(ctl, r, ar, X4STEP_MOVE_ENDLESS, e);
  x4step_goto g{};
  g.axes = 1;
  g.flags = X4STEP_GOTO_RELATIVE;
  g.target[0] = 100;
  probe(ctl, r, ar, X4STEP_GOTO, g);
  // A reference run needs a reference switch: set up for the full run only
  // (with --invalid-only no call may succeed).
  x4step_switches sw = g_initial.sw;
  sw.ref[0] = 1;
  if (!opt.invalid_only) must(ctl, X4STEP_SET_SWITCHES, &sw, "probes");
  x4step_home h{};
  h.axis = 1;
  h.phases = X4STEP_HOME_AUTO;
  h.vref1 = -1000;
  h.vref2 = 100;
  h.sref = 1000;
  probe(ctl, r, ar, X4STEP_HOME, h);
  if (!opt.invalid_only) must(ctl, X4STEP_SET_SWITCHES, &g_initial.sw, "probes (restore)");
  x4step_move m{};
  m.steps[0] = 100;
  m.freq_hz = 1000;
  probe(ctl, r, ar, X4STEP_LOAD, m);
  x4step_status st;
  if (read_dev(ctl, X4STEP_GET_STATUS, st) && (st.flags & X4STEP_ST_LOADED)) {
    close(ctl);  // the module forgets the loaded move
    ctl = open_dev(O_RDWR);
    if (ctl < 0) die("reopen the controller");
  }
}

// write() of path segments (ABI 5): 1..4 records, mostly of sane speeds
// (leader 500..5000 steps/s, >= 10^5 steps/s^2: a hold on close ends in
// milliseconds), some fields random, sometimes not whole records, into
// random memory. Only the controller may write (EBADF); whole records or
// EINVAL, ERANGE, EBUSY (moves run), EFAULT, ECANCELED (a stop flushed the
// path: until PATH_CLEAR). `bad`: only invalid records.
// The caller makes sure the queue has room (no write may block).
std::atomic<long> g_writes{0}, g_writes_failed{0}, g_records_queued{0};

void write_segments(int fd, Rng &r, Arena &ar, bool controller, bool bad) {
  x4step_segment seg[4];
  std::memset(seg, 0, sizeof seg);
  const size_t n = 1 + r.below(4);
  for (size_t i = 0; i < n; i++) {
    x4step_segment &g = seg[i];
    const int lead = r.below(4);
    for (int a = 0; a < 4; a++)
      g.steps[a] = a == lead ? r.range(1, 40) * (r.chance(50) ? 1 : -1) : r.chance(30) ? r.range(-40, 40) : 0;
    if (r.chance(3)) g.steps[lead] = r.chance(50) ? 0 : r.s32();
    const uint32_t leader = std::abs(g.steps[lead]);
    g.length = r.chance(95) ? std::max(leader, 1u) * 10 : static_cast<uint32_t>(r.s32());
    g.v_max = r.chance(95) ? r.range(5000, 50000) : static_cast<uint32_t>(r.s32());
    g.v_entry = r.chance(90) ? r.range(0, 50000) : static_cast<uint32_t>(r.s32());
    g.accel = r.chance(95) ? r.range(1000000, 10000000) : static_cast<uint32_t>(r.s32());
    g.tag = static_cast<uint64_t>(r.s32());
    g.flags = maybe_nonzero(r, 5);
    g.reserved = maybe_nonzero(r, 5);
    if (bad) {
      if (r.chance(50))  // not bits 0 and 1: probing segments may be valid
        g.flags |= 4u << r.below(30);
      else
        g.reserved |= 1u << r.below(32);
    }
  }
  size_t size = n * sizeof seg[0];
  if (r.chance(bad ? 30 : 10)) size = r.below(size) | 1;  // not whole records
  const Payload p = place(ar, r, random_ptr_kind(r, true), reinterpret_cast<const uint8_t *>(seg), size);
  const ssize_t ret = write(fd, reinterpret_cast<const void *>(p.arg), size);
  const int err = errno;
  g_writes++;
  if (ret >= 0) {
    g_records_queued += ret / static_cast<ssize_t>(sizeof seg[0]);
    if (!controller || bad || ret % sizeof seg[0] || static_cast<size_t>(ret) > size || !ret)
      violation("write() of %zu bytes (%s, %s) returned %zd", size, controller ? "controller" : "read-only",
                bad ? "invalid records" : "records", ret);
    return;
  }
  g_writes_failed++;
  const bool ok = controller ? err == EINVAL || err == EFAULT || err == ECANCELED ||
                                   (!bad && (err == ERANGE || err == EBUSY))
                             : err == EBADF;
  if (!ok)
    violation("write() of %zu bytes (%s, %s) at %s: %s", size, controller ? "controller" : "read-only",
              bad ? "invalid records" : "records", kPtrNames[p.kind], std::strerror(err));
}

// Room in the path queue for a write that must not block.
bool path_room(int fd) {
  pollfd p{fd, POLLOUT, 0};
  return poll(&p, 1, 0) == 1 && (p.revents & POLLOUT);
}

// Phase b: structured commands, one thread, failed calls must change nothing.
long phase_b(int ctl, int ro, Rng &r, Arena &ar, double secs) {
  Ctx cctl{ctl, {true, false}, true}, cro{ro, {false, false}, true};
  auto end = after(secs);
  uint8_t content[kMaxPayload];
  long n = 0;
  while (time_left(end)) {
    if (r.chance(3)) {  // invalid segment records: refused, nothing changes
      Snapshot before, after_;
      const bool snap = snapshot(ctl, before);
      write_segments(ctl, r, ar, true, true);
      if (snap && snapshot(ctl, after_)) check_unchanged("write", EINVAL, "invalid segments", before, after_);
      x4step_path_status ps;
      if (read_dev(ctl, X4STEP_GET_PATH, ps) && (ps.queued || ps.state != X4STEP_PATH_IDLE))
        violation("invalid segments queued a path: state %u, %u queued", ps.state, ps.queued);
      n++;
      continue;
    }
    unsigned long cmd = gen_structured(r, content, false);
    PtrKind kind = random_ptr_kind(r, true);
    Payload p = place(ar, r, kind, content, cmd_size(cmd));
    call(r.chance(92) ? cctl : cro, cmd, p);
    n++;
  }
  return n;
}

// Phase c: threads.
// ------------------------------------------------------------------ events

// What one descriptor has read of the event stream so far.
struct EventCursor {
  uint64_t seq = 0;
  uint64_t ns = 0;
  long events = 0;
};

// One read() of events on a non-blocking descriptor, of a random size into
// random memory: only whole, sane events (known type, flags and axes,
// reserved fields zero), seq increasing and time never going back on the
// descriptor (gaps are allowed: a reader may fall behind); EINVAL below one
// event's size, EFAULT only where the kernel cannot write, else EAGAIN.
void read_events(int fd, Rng &r, Arena &ar, EventCursor &cur) {
  static const uint32_t sizes[] = {0, 1, 63, 64, 65, 127, 128, 200, 640, 4096};
  const size_t ev = sizeof(x4step_event);
  const size_t size = r.pick(sizes);
  uint8_t content[kMaxPayload];
  std::memset(content, 0xa5, sizeof content);
  const Payload p = place(ar, r, random_ptr_kind(r, true), content, size);
  const ssize_t n = read(fd, reinterpret_cast<void *>(p.arg), size);
  const int err = errno;
  if (n < 0) {
    // The VFS refuses addresses beyond user space (access_ok) before the
    // driver sees the call, whatever the size.
    const bool beyond = p.kind == P_KERNEL || p.kind == P_NONCANON;
    const bool ok = (err == EFAULT && (beyond || (size >= ev && p.writable < size))) ||
                    (!beyond && (size < ev ? err == EINVAL : err == EAGAIN));
    if (!ok) violation("read() of %zu bytes at %s: %s", size, kPtrNames[p.kind], std::strerror(err));
    return;
  }
  if (size < ev || n % ev || static_cast<size_t>(n) > std::min(size, p.writable)) {
    violation("read() of %zu bytes at %s returned %zd", size, kPtrNames[p.kind], n);
    return;
  }
  for (ssize_t i = 0; i < n; i += ev) {
    x4step_event e;
    std::memcpy(&e, reinterpret_cast<const uint8_t *>(p.arg) + i, sizeof e);
    if (e.type < X4STEP_EV_MOVE_STARTED || e.type > X4STEP_EV_PORT_GONE ||
        (e.flags & ~X4STEP_EVF_AMBIGUOUS) || e.axes > 0xf || e.reserved[0] || e.reserved[1] ||
        e.reserved[2] || e.seq <= cur.seq || e.timestamp_ns < cur.ns)
      violation("event %s after #%llu at %llu ns", hex(&e, sizeof e).c_str(),
                static_cast<unsigned long long>(cur.seq), static_cast<unsigned long long>(cur.ns));
    cur.seq = e.seq;
    cur.ns = e.timestamp_ns;
    cur.events++;
  }
}

struct Shared {
  std::atomic<bool> stop{false};
  std::atomic<bool> controller_open{true};  // the main controller descriptor is open
  std::atomic<int> controllers{0};
  std::atomic<long> iterations{0};
  std::atomic<long> opens_ro{0}, opens_rw_busy{0}, controller_wins{0}, polls{0}, events{0};
  std::atomic<long> max_open_us{0}, max_close_us{0};  // racers: longest open(O_RDWR), close
  void keep_max(std::atomic<long> &m, Clock::time_point since) {
    long us = std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - since).count();
    long cur = m;
    while (us > cur && !m.compare_exchange_weak(cur, us)) {
    }
  }
};

void hammer(int ctl, uint64_t seed, Shared &sh, bool writer = false) {
  Rng r(seed);
  Arena ar;
  Ctx cx{ctl, {true, false}, false};
  uint8_t content[kMaxPayload];
  while (!sh.stop) {
    if (writer && r.chance(15) && path_room(ctl)) {  // the one thread that writes
      write_segments(ctl, r, ar, true, r.chance(20));
      sh.iterations++;
      continue;
    }
    unsigned long cmd;
    PtrKind kind;
    unsigned x = r.below(100);
    if (x < 65) {
      cmd = gen_structured(r, content, r.chance(70));
      kind = random_ptr_kind(r, true);
    } else {
      cmd = random_cmd(r);
      random_bytes(r, content);
      kind = random_ptr_kind(r, false);
    }
    Payload p = place(ar, r, kind, content, cmd_size(cmd));
    call(cx, cmd, p);
    sh.iterations++;
  }
}

void monitor(uint64_t seed, Shared &sh) {
  Rng r(seed);
  Arena ar;
  int fd = open_dev(O_RDONLY);
  int evfd = open_dev(O_RDONLY | O_NONBLOCK);  // reads events
  if (fd < 0 || evfd < 0) {
    violation("read-only open for a monitor failed: %s", std::strerror(errno));
    if (fd >= 0) close(fd);
    return;
  }
  Ctx cx{fd, {false, false}, false};
  EventCursor cur;
  uint64_t ended = 0;
  uint8_t content[kMaxPayload];
  while (!sh.stop) {
    x4step_status st;
    x4step_axes ax;
    read_dev(fd, X4STEP_GET_AXES, ax);  // sane while moves run, too
    if (read_dev(fd, X4STEP_GET_STATUS, st)) {
      if (st.moves_ended < ended)
        violation("moves_ended went back: %llu -> %llu", static_cast<unsigned long long>(ended),
                  static_cast<unsigned long long>(st.moves_ended));
      ended = st.moves_ended;
    }
    pollfd pfd{fd, static_cast<short>(POLLIN | POLLRDNORM), 0};
    int pr = poll(&pfd, 1, r.below(3) ? static_cast<int>(r.below(20)) : 0);
    sh.polls++;
    if (pr < 0)
      violation("poll: %s", std::strerror(errno));
    else if (pfd.revents & ~(POLLIN | POLLRDNORM))
      violation("poll revents 0x%x", pfd.revents);
    pollfd epfd{evfd, static_cast<short>(POLLIN | POLLPRI), 0};
    if (poll(&epfd, 1, 0) < 0 || (epfd.revents & ~(POLLIN | POLLPRI)))
      violation("poll (POLLPRI) revents 0x%x", epfd.revents);
    for (int i = r.below(4); i > 0; i--) read_events(evfd, r, ar, cur);
    if (r.chance(5)) write_segments(fd, r, ar, false, r.chance(50));
    if (r.chance(30)) {  // anything on a read-only descriptor
      unsigned long cmd = r.chance(50) ? gen_structured(r, content, true) : random_cmd(r);
      if (cmd_index(cmd) >= kNumCmds || !kCmds[cmd_index(cmd)].state) random_bytes(r, content);
      Payload p = place(ar, r, random_ptr_kind(r, true), content, cmd_size(cmd));
      call(cx, cmd, p);
    }
    sh.iterations++;
  }
  sh.events += cur.events;
  close(evfd);
  close(fd);
}

// Opens and closes descriptors: read-only always works, read-write gets EBUSY
// while the controller is open.
void opener(uint64_t seed, Shared &sh) {
  Rng r(seed);
  Arena ar;
  while (!sh.stop) {
    int mode = r.chance(50) ? O_RDONLY : r.chance(70) ? O_RDWR : O_WRONLY;
    const bool nonblock = r.chance(20);
    int fd = open_dev(mode | (nonblock ? O_NONBLOCK : 0));
    if (mode == O_RDONLY) {
      if (fd < 0)
        violation("read-only open failed: %s", std::strerror(errno));
      else
        sh.opens_ro++;
    } else if (sh.controller_open) {
      if (fd >= 0)
        violation("a second read-write open succeeded while the controller is open");
      else if (errno != EBUSY)
        violation("read-write open failed with %s, expected EBUSY", std::strerror(errno));
      else
        sh.opens_rw_busy++;
    }
    if (fd >= 0) {
      if (r.chance(50)) {
        x4step_status st;
        read_dev(fd, X4STEP_GET_STATUS, st);
      }
      if (r.chance(30)) {
        pollfd pfd{fd, POLLIN, 0};
        poll(&pfd, 1, 0);
      }
      if (nonblock && mode != O_WRONLY) {
        EventCursor cur;
        read_events(fd, r, ar, cur);
      }
      close(fd);
    }
    sh.iterations++;
  }
}

// Phase c2: threads race to become the controller; at most one at a time.
void racer(uint64_t seed, Shared &sh) {
  Rng r(seed);
  Arena ar;
  uint8_t content[kMaxPayload];
  while (!sh.stop) {
    auto t0 = Clock::now();
    int fd = open_dev(O_RDWR);
    sh.keep_max(sh.max_open_us, t0);
    if (fd < 0) {
      if (errno != EBUSY)
        violation("controller race: open failed with %s", std::strerror(errno));
      else
        sh.opens_rw_busy++;
      continue;
    }
    if (++sh.controllers > 1) violation("two controllers at once");
    sh.controller_wins++;
    Ctx cx{fd, {true, false}, false};
    int ops = r.below(6);
    for (int i = 0; i < ops; i++) {
      unsigned long cmd = gen_structured(r, content, true);
      if (cmd == X4STEP_SET_CONFIG) continue;
      Payload p = place(ar, r, random_ptr_kind(r, true), content, cmd_size(cmd));
      call(cx, cmd, p);
      usleep(r.below(2000));  // let the others try to open meanwhile
    }
    if (r.chance(50)) ioctl(fd, X4STEP_STOP);
    sh.controllers--;
    t0 = Clock::now();
    close(fd);  // brakes what runs
    sh.keep_max(sh.max_close_us, t0);
    sh.iterations++;
  }
}

// Phase d: all closed; a fresh controller opens and finds the engine idle.
void phase_d() {
  int fd = open_dev(O_RDWR);
  if (fd < 0) {
    violation("phase d: the controller does not open again: %s", std::strerror(errno));
    return;
  }
  Snapshot now;
  if (snapshot(fd, now)) {
    if (now.st.flags & (X4STEP_ST_ACTIVE | X4STEP_ST_LOADED) || now.running())
      violation(
          "phase d: a fresh controller finds flags 0x%x, axes 0x%x running (expected idle, nothing loaded)",
          now.st.flags, now.running());
    if (!(now.st.flags & X4STEP_ST_CONTROLLED))
      violation("phase d: CONTROLLED not set with a controller open");
  }
  // Back to the wiring, step timing, switches and profiles found at the
  // start, no brake codes.
  must(fd, X4STEP_SET_CONFIG, &g_initial.cfg, "phase d (restore)");
  must(fd, X4STEP_SET_STEP_TIMING, &g_initial.tim, "phase d (restore)");
  must(fd, X4STEP_SET_SWITCHES, &g_initial.sw, "phase d (restore)");
  for (const x4step_profile &pr : g_initial.prof) must(fd, X4STEP_SET_PROFILE, &pr, "phase d (restore)");
  x4step_brake_codes bc{};
  must(fd, X4STEP_SET_BRAKE_CODES, &bc, "phase d");
  close(fd);
  fd = open_dev(O_RDONLY);
  if (fd < 0) {
    violation("phase d: read-only open: %s", std::strerror(errno));
    return;
  }
  x4step_status st;
  if (read_dev(fd, X4STEP_GET_STATUS, st) && (st.flags & (X4STEP_ST_ACTIVE | X4STEP_ST_CONTROLLED)))
    violation("phase d: after close flags 0x%x (expected no move, no controller)", st.flags);
  pollfd pfd{fd, POLLIN, 0};
  if (poll(&pfd, 1, 100) != 1 || !(pfd.revents & POLLIN))
    violation("phase d: idle device not readable in poll");
  close(fd);
}

void usage() {
  std::fprintf(stderr,
               "usage: ioctl_fuzz [--seed N] [--seconds S] [--device PATH] [--invalid-only]\n"
               "                  [--threads N] [--verbose]\n");
  std::exit(2);
}

}  // namespace

int main(int argc, char **argv) {
  for (int i = 1; i < argc; i++) {
    std::string a = argv[i];
    auto val = [&]() -> const char * {
      if (i + 1 >= argc) usage();
      return argv[++i];
    };
    if (a == "--seed")
      opt.seed = std::strtoull(val(), nullptr, 0);
    else if (a == "--seconds")
      opt.seconds = std::atof(val());
    else if (a == "--device")
      opt.device = val();
    else if (a == "--invalid-only")
      opt.invalid_only = true;
    else if (a == "--threads")
      opt.threads = std::atoi(val());
    else if (a == "--verbose")
      opt.verbose = true;
    else
      usage();
  }
  if (opt.seconds <= 0 || opt.threads < 1 || opt.threads > 16) usage();
  setvbuf(stdout, nullptr, _IOLBF, 0);
  note("seed %llu, %.0f s, %s%s", static_cast<unsigned long long>(opt.seed), opt.seconds, opt.device.c_str(),
       opt.invalid_only ? ", invalid calls only" : "");

  auto t0 = Clock::now();
  int ctl = open_dev(O_RDWR);
  if (ctl < 0) die(("open " + opt.device + " read-write").c_str());
  int ro = open_dev(O_RDONLY);
  if (ro < 0) die(("open " + opt.device + " read-only").c_str());
  if (!snapshot(ctl, g_initial)) die("read the configuration");
  g_phase_mode_possible = g_initial.cfg.output_mode != X4STEP_MODE_CLOCK_DIR;
  g_fast_axes = fast_axes(g_initial);
  Rng rng(opt.seed);
  long total = 0;
  {
    Arena ar;
    probes(ctl, rng, ar);
    double s = opt.invalid_only ? opt.seconds * 0.5 : opt.seconds * 0.2;
    total += phase_a(ctl, ro, rng, ar, s);
    g_stats.print("a (command numbers, pointers)");
    g_stats.reset();
    s = opt.invalid_only ? opt.seconds * 0.5 : opt.seconds * 0.3;
    total += phase_b(ctl, ro, rng, ar, s);
    g_stats.print("b (structured, boundary values)");
    g_stats.reset();
  }

  if (!opt.invalid_only) {
    Shared sh;
    std::vector<std::thread> th;
    g_fast_profiles = false;
    for (int i = 0; i < opt.threads; i++)
      th.emplace_back(hammer, ctl, opt.seed * 1000 + 10 + i, std::ref(sh), i == 0);
    for (int i = 0; i < 2; i++) th.emplace_back(monitor, opt.seed * 1000 + 20 + i, std::ref(sh));
    th.emplace_back(opener, opt.seed * 1000 + 30, std::ref(sh));
    std::this_thread::sleep_for(std::chrono::microseconds(static_cast<long long>(opt.seconds * 0.35e6)));
    sh.stop = true;
    for (auto &t : th) t.join();
    th.clear();
    note(
        "phase c: %ld thread iterations, %ld read-only opens, %ld read-write opens refused (EBUSY), %ld "
        "polls, %ld events read",
        sh.iterations.load(), sh.opens_ro.load(), sh.opens_rw_busy.load(), sh.polls.load(), sh.events.load());
    note("phase c: %ld write()s of segments, %ld refused, %ld records queued", g_writes.load(),
         g_writes_failed.load(), g_records_queued.load());
    g_stats.print("c (threads on one controller)");
    g_stats.reset();
    total += sh.iterations;

    // c2: the controller goes; threads race to become the next one. Their
    // moves brake within 20 ms: no slower profile of phase c stays.
    ioctl(ctl, X4STEP_STOP);
    for (uint32_t a = 1; a <= X4STEP_AXES; a++) {
      x4step_profile quick{a, 0, 0, kLongHz, X4STEP_ACC_MAX, X4STEP_ACC_MAX, {}};
      must(ctl, X4STEP_SET_PROFILE, &quick, "before c2");
    }
    g_fast_axes = 0;
    sh.controller_open = false;
    close(ctl);
    ctl = -1;
    Shared sh2;
    sh2.controller_open = false;
    for (int i = 0; i < opt.threads; i++) th.emplace_back(racer, opt.seed * 1000 + 40 + i, std::ref(sh2));
    th.emplace_back(monitor, opt.seed * 1000 + 50, std::ref(sh2));
    th.emplace_back(opener, opt.seed * 1000 + 51, std::ref(sh2));
    std::this_thread::sleep_for(std::chrono::microseconds(static_cast<long long>(opt.seconds * 0.15e6)));
    sh2.stop = true;
    for (auto &t : th) t.join();
    note(
        "phase c2: %ld controller sessions, %ld read-write opens refused (EBUSY), %ld iterations, "
        "longest open %.1f ms, longest close %.1f ms",
        sh2.controller_wins.load(), sh2.opens_rw_busy.load(), sh2.iterations.load(), sh2.max_open_us / 1e3,
        sh2.max_close_us / 1e3);
    if (!sh2.controller_wins) violation("phase c2: no thread ever became the controller");
    // close() starts the brake and returns: it never waits for the motors
    // (their moves have ramps of at most 20 ms anyway).
    if (sh2.max_close_us > 2000000)
      violation("phase c2: closing the controller took %.0f ms (moves with ramps <= 20 ms)",
                sh2.max_close_us / 1e3);
    g_stats.print("c2 (controller races)");
    total += sh2.iterations;
  }

  // Never leave a motor running: stop, then close (the module brakes on close).
  if (ctl >= 0) {
    ioctl(ctl, X4STEP_STOP);
    close(ctl);
  }
  // A racer's last close may have left a brake running; the module keeps
  // the port until it ends, and poll() reports POLLIN once it is free.
  pollfd free_pfd{ro, POLLIN, 0};
  if (poll(&free_pfd, 1, 10000) != 1) violation("the port is not free 10 s after the last close");
  close(ro);
  phase_d();

  double secs = std::chrono::duration<double>(Clock::now() - t0).count();
  long v = g_violations;
  violation_summary();
  note("%ld calls/iterations in %.1f s, %ld violations", total, secs, v);
  std::printf("%s ioctl_fuzz%s seed %llu\n", v ? "FAIL" : "PASS", opt.invalid_only ? " invalid-only" : "",
              static_cast<unsigned long long>(opt.seed));
  return v ? 1 : 0;
}
