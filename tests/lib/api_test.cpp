// SPDX-License-Identifier: LGPL-2.1-or-later
// libx4step on the host, without the kernel module: every error the
// library decides itself.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/x4step.h>
#include <poll.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cstdarg>
#include <cstring>
#include <filesystem>
#include <functional>
#include <regex>
#include <sstream>
#include <thread>
#include <vector>

#include "x4step.h"
#include "x4step.hpp"
#include "x4step_access.hpp"
#include "x4step_ext.h"
#include "x4step_path.hpp"

using namespace std::chrono_literals;

// The errc a call throws, errc::ok if none.
template <typename F>
x4step::errc thrown(F &&f) {
  try {
    f();
  } catch (const x4step::error &e) {
    EXPECT_EQ(&e.code().category(), &x4step::category()) << e.what();
    return static_cast<x4step::errc>(e.code().value());
  }
  return x4step::errc::ok;
}

TEST(CApi, BeforeInit) {
  EXPECT_EQ(X4ReInit(), X4ErrInitNotDone);
  EXPECT_EQ(X4Load(1, 0, 0, 0, 1000, 50), X4ErrInitNotDone);
  EXPECT_EQ(X4Load(0, 0, 0, 0, 99999, 5000), X4ErrInitNotDone);  // state first
  EXPECT_EQ(X4Start(), X4ErrInitNotDone);
  EXPECT_EQ(X4Brake(), X4ErrInitNotDone);
  EXPECT_EQ(X4Stop(), X4ErrInitNotDone);
  EXPECT_EQ(X4MovePos(1, 1000, 50), X4ErrInitNotDone);
  EXPECT_EQ(X4MoveNeg(1, 1000, 50), X4ErrInitNotDone);
  EXPECT_EQ(X4SetOut(SIGNAL1ON), X4ErrInitNotDone);
  char codes[] = {28, 0};
  EXPECT_EQ(X4BrakeCodes(codes), X4ErrInitNotDone);
  EXPECT_EQ(X4GetState(), 0);
  EXPECT_EQ(X4GetSteps(1), 0);
  EXPECT_EQ(X4GetIn(), 0);
  EXPECT_EQ(X4LastBrakeCode(), 0);
}

TEST(CApi, InitArguments) {
  EXPECT_EQ(X4Init(0), X4ErrParamFail);
  EXPECT_EQ(X4Init(5), X4ErrParamFail);
  EXPECT_EQ(X4Init(-1), X4ErrParamFail);
  if (access("/dev/x4step3", F_OK) != 0) {
    EXPECT_EQ(X4Init(LPT4), X4ErrLPTNotFound);
  }
  EXPECT_EQ(X4ReInit(), X4ErrInitNotDone);
}

TEST(CApi, ConstantsAsDocumented) {
  EXPECT_EQ(X4NoErr, 0);
  EXPECT_EQ(X4ErrNoErr, X4NoErr);
  const int codes[] = {X4ErrNoSteps,     X4ErrFreqTooHigh, X4ErrFreqTooLow,  X4ErrRampTooHigh, X4ErrRampFreq,
                       X4ErrLPTNotFound, X4ErrNotActive,   X4ErrParamFail,   X4ErrInitNotDone, X4ErrIsActive,
                       X4ErrNotLoaded,   X4ErrIsLoaded,    X4ErrStepsTooHigh};
  for (int i = 0; i < 13; i++) EXPECT_EQ(codes[i], i + 1);
  EXPECT_EQ(SIGNAL1ON, 1);
  EXPECT_EQ(SIGNAL1OFF, 2);
  EXPECT_EQ(SIGNAL2ON, 3);
  EXPECT_EQ(SIGNAL2OFF, 4);
  EXPECT_EQ(LPT1, 1);
  EXPECT_EQ(LPT4, 4);
}

TEST(CApi, TimerCountsMilliseconds) {
  X4ClearTimer();
  EXPECT_LT(X4GetTimer(), 5);
  std::this_thread::sleep_for(30ms);
  const long t = X4GetTimer();
  EXPECT_GE(t, 30);
  EXPECT_LT(t, 1000);
  X4ClearTimer();
  EXPECT_LT(X4GetTimer(), t);
}

TEST(CppApi, CheckMatchesTheManual) {
  using x4step::errc;
  using x4step::move;
  EXPECT_EQ(x4step::check(move{{1000, 800, 600, 400}, 1000, 50ms}), errc::ok);
  EXPECT_EQ(x4step::check(move{{0, 0, 0, 0}, 1000, 50ms}), errc::no_steps);
  EXPECT_EQ(x4step::check(move{{1, 0, 0, 0}, 20001, 0ms}), errc::freq_too_high);
  EXPECT_EQ(x4step::check(move{{1, 0, 0, 0}, 9, 0ms}), errc::freq_too_low);
  EXPECT_EQ(x4step::check(move{{1, 0, 0, 0}, 2000, 1001ms}), errc::ramp_too_high);
  EXPECT_EQ(x4step::check(move{{1, 0, 0, 0}, 100, 90ms}), errc::ok);  // manual 5.3
  EXPECT_EQ(x4step::check(move{{1, 0, 0, 0}, 10, 50ms}), errc::ramp_freq);
  EXPECT_EQ(x4step::check(move{{16777216, -16777216, 0, 0}, 1000, 0ms}), errc::ok);
  EXPECT_EQ(x4step::check(move{{0, 0, 16777217, 0}, 1000, 0ms}), errc::steps_too_high);
  EXPECT_EQ(x4step::check(move{{0, 0, 0, 1L << 40}, 1000, 0ms}), errc::steps_too_high);
  EXPECT_EQ(x4step::check(move{{1, 0, 0, 0}, 1000, -1ms}), errc::param_fail);
  EXPECT_EQ(x4step::check(move{{1, 0, 0, 0}, 1000, std::chrono::milliseconds(1LL << 40)}),
            errc::ramp_too_high);
  EXPECT_EQ(x4step::check_endless(1000, 0ms), errc::ok);
  EXPECT_EQ(x4step::check_endless(20, 50ms), errc::ramp_freq);
}

// A segment is checked by the kernel's own check (x4_segment_check()):
// steps beyond 32 bits, LONG_MIN among them, are too many, not wrapped.
TEST(CppApi, SegmentCheckIsTheKernels) {
  using x4step::axis;
  using x4step::errc;
  const auto seg = [](long x, std::uint32_t length, std::uint32_t v, std::uint32_t a) {
    return x4step::segment{}.steps(axis::x, x).steps(axis::y, 1).length(length).top_speed(v).accel(a);
  };
  EXPECT_EQ(x4step::check(seg(100, 1000, 5000, 50000)), errc::ok);
  EXPECT_EQ(x4step::check(seg(-16777216, 16777216, 5000, 50000)), errc::ok);
  EXPECT_EQ(x4step::check(seg(-16777217, 16777216, 5000, 50000)), errc::steps_too_high);
  EXPECT_EQ(x4step::check(seg(LONG_MIN, 1000, 5000, 50000)), errc::steps_too_high);
  EXPECT_EQ(x4step::check(seg(LONG_MAX, 1000, 5000, 50000)), errc::steps_too_high);
  EXPECT_EQ(x4step::check(seg((1L << 32) + 100, 1000, 5000, 50000)), errc::steps_too_high);
  EXPECT_EQ(x4step::check(x4step::segment{}.length(1000).top_speed(5000).accel(50000)), errc::no_steps);
  EXPECT_EQ(x4step::check(seg(100, 0, 5000, 50000)), errc::param_fail);
  EXPECT_EQ(x4step::check(seg(100, 1000, 5000, 50000).entry_speed(0x80000000u)), errc::param_fail);
  EXPECT_EQ(x4step::check(seg(100, 100000, 1000, 1)), errc::param_fail);  // leader at 0.001 steps/s^2
  EXPECT_EQ(x4step::check(seg(100, 100, 100000, 1000000)), errc::ok);     // 100000 steps/s
  EXPECT_EQ(x4step::check(seg(100, 100, 100001, 1000000)), errc::freq_too_high);
}

// Axes are 1..4 and sets of them; integers become either only explicitly
// (what does not compile is tests/lib/typed-axes.sh's).
TEST(CppApi, AxesAndAxisSets) {
  using x4step::axis;
  using x4step::axis_set;
  static_assert(axis::x.number() == 1 && axis::y.number() == 2 && axis::z.number() == 3 &&
                axis::a.number() == 4);
  static_assert(axis{3}.index() == 2 && axis{3}.bit() == 0x4u);
  static_assert((axis::x | axis::z).mask() == 0x5u);
  static_assert(axis_set::all().mask() == 0xfu && axis_set().empty());
  static_assert(~(axis::x | axis::z) == (axis::y | axis::a));
  static_assert(((axis::x | axis::y) & (axis::y | axis::z)) == axis_set(axis::y));
  EXPECT_TRUE(axis::valid(1) && axis::valid(4));
  EXPECT_FALSE(axis::valid(0) || axis::valid(5) || axis::valid(-1));
  for (int bad : {0, 5, -1}) EXPECT_EQ(thrown([&] { axis{bad}; }), x4step::errc::param_fail) << bad;
  EXPECT_EQ(thrown([] { axis_set{0x10u}; }), x4step::errc::param_fail);
  EXPECT_EQ(thrown([] { axis_set{~0u}; }), x4step::errc::param_fail);
  EXPECT_EQ(axis_set{0x9u}, axis::x | axis::a);
  EXPECT_TRUE((axis::y | axis::a).contains(axis::a));
  EXPECT_FALSE((axis::y | axis::a).contains(axis::z));
  std::vector<int> walked;
  for (axis a : axis::a | axis::x | axis::z) walked.push_back(a.number());
  EXPECT_EQ(walked, (std::vector<int>{1, 3, 4}));
  EXPECT_EQ(std::distance(axis_set::all().begin(), axis_set::all().end()), 4);
  EXPECT_EQ(axis_set().begin(), axis_set().end());
}

// Each setter sets its own value: none is taken for another.
TEST(CppApi, SettingsAreBuiltByName) {
  constexpr auto p = x4step::profile{}.start_speed(1).top_speed(2).end_speed(3).accel(4).decel(5);
  static_assert(p.start_speed() == 1 && p.top_speed() == 2 && p.end_speed() == 3 && p.accel() == 4 &&
                p.decel() == 5);
  constexpr x4step::profile d;  // the kernel's default
  static_assert(d.start_speed() == 0 && d.top_speed() == 1000 && d.end_speed() == 0 && d.accel() == 1000 &&
                d.decel() == 1000);
  constexpr auto h =
      x4step::homing{}.phase1_speed(-7).phase2_speed(8).max_travel(9).phase1(false).phase2(true).brake(true);
  static_assert(h.phase1_speed() == -7 && h.phase2_speed() == 8 && h.max_travel() == 9 && !h.phase1() &&
                h.phase2() && h.brake());
  constexpr x4step::homing hd;
  static_assert(hd.phase1_speed() == -1000 && hd.phase2_speed() == 100 && hd.max_travel() == 100000 &&
                hd.phase1() && hd.phase2() && !hd.brake());
  using std::chrono::nanoseconds;
  constexpr auto t = x4step::step_timing{}.pulse(1ns).space(2ns).dir_setup(3ns).dir_hold(4ns);
  static_assert(t.pulse() == 1ns && t.space() == 2ns && t.dir_setup() == 3ns && t.dir_hold() == 4ns);
  constexpr x4step::step_timing td;
  static_assert(td.pulse() == 0ns && td.space() == 0ns && td.dir_setup() == 100us && td.dir_hold() == 0ns);
  using x4step::axis;
  constexpr auto c = x4step::config{}
                         .clock_invert(axis::y)
                         .dir_invert(axis::x | axis::a)
                         .keys_swallow(true)
                         .mode(x4step::output_mode::smc_phase);
  static_assert(c.clock_invert() == axis::y && c.dir_invert() == (axis::x | axis::a) && c.keys_swallow() &&
                c.mode() == x4step::output_mode::smc_phase);
  constexpr x4step::config cd;
  static_assert(cd.clock_invert().empty() && cd.dir_invert().empty() && !cd.keys_swallow() &&
                cd.mode() == x4step::output_mode::clock_dir);
}

TEST(CppApi, ErrorsCarryTheX4Codes) {
  const std::error_code ec = x4step::errc::ramp_freq;
  EXPECT_EQ(ec.value(), X4ErrRampFreq);
  EXPECT_EQ(&ec.category(), &x4step::category());
  EXPECT_STREQ(ec.category().name(), "x4step");
  for (int i = 1; i <= 13; i++) EXPECT_FALSE(x4step::category().message(i).empty());
  EXPECT_NE(x4step::category().message(5).find("ramp"), std::string::npos);
}

TEST(CppApi, OpeningAMissingOrForeignDevice) {
  EXPECT_EQ(x4step::device_path(1), "/dev/x4step0");
  try {
    x4step::device_path(5);
    FAIL() << "no throw";
  } catch (const x4step::error &e) {
    EXPECT_EQ(e.code(), x4step::errc::param_fail);
  }
  try {
    x4step::controller c("/nonexistent/x4step9");
    FAIL() << "no throw";
  } catch (const x4step::error &e) {
    EXPECT_EQ(e.code(), x4step::errc::lpt_not_found);
  }
  try {
    x4step::monitor m("/dev/null");  // opens, but is no x4step device
    FAIL() << "no throw";
  } catch (const x4step::error &e) {
    EXPECT_EQ(e.code(), x4step::errc::lpt_not_found);
  }
}

TEST(CApi, ExtensionsBeforeInit) {
  EXPECT_EQ(X4SetStepTiming(5000, 0, 100000, 0), X4ErrInitNotDone);
  EXPECT_EQ(X4SetOutputMode(X4MODE_SMC_PHASE), X4ErrInitNotDone);
}

// ---- positioning ------------------------------------------------------------------

TEST(CppApi, ProfileRules) {
  using x4step::errc;
  using x4step::profile;
  const profile p;  // 0 -> 1000 steps/s, a0 = ae = 1000: the kernel's default
  EXPECT_EQ(x4step::check(p), errc::ok);
  EXPECT_EQ(x4step::check(profile(p).top_speed(100000).accel(1000000).decel(1000000)), errc::ok);
  EXPECT_EQ(x4step::check(profile(p).start_speed(100).end_speed(200).accel(0).decel(0)), errc::ok);  // jumps
  EXPECT_EQ(x4step::check(profile(p).start_speed(1000).end_speed(1000).accel(1).decel(1)), errc::ok);
  EXPECT_EQ(x4step::check(profile(p).top_speed(0)), errc::param_fail);
  EXPECT_EQ(x4step::check(profile(p).top_speed(100001)), errc::param_fail);
  EXPECT_EQ(x4step::check(profile(p).start_speed(1001)), errc::param_fail);  // v0 > vm
  EXPECT_EQ(x4step::check(profile(p).end_speed(1001)), errc::param_fail);    // ve > vm
  EXPECT_EQ(x4step::check(profile(p).accel(1000001)), errc::param_fail);
  EXPECT_EQ(x4step::check(profile(p).decel(1000001)), errc::param_fail);
  // vm / a at most 3600 s: 36000 steps/s at 10 steps/s^2 just fits, from any v0.
  EXPECT_EQ(x4step::check(profile(p).top_speed(36000).accel(10).decel(10)), errc::ok);
  EXPECT_EQ(x4step::check(profile(p).top_speed(36001).accel(10)), errc::param_fail);
  EXPECT_EQ(x4step::check(profile(p).top_speed(36001).decel(10)), errc::param_fail);
  EXPECT_EQ(x4step::check(profile(p).top_speed(36001).start_speed(30000).accel(10)), errc::param_fail);
  EXPECT_EQ(x4step::check(profile(p).top_speed(36001).end_speed(30000).decel(10)), errc::param_fail);
}

TEST(CppApi, HomingRules) {
  using x4step::errc;
  using x4step::homing;
  const homing h;  // -1000 then 100 steps/s, 100000 steps, both phases
  EXPECT_EQ(x4step::check(h), errc::ok);
  EXPECT_EQ(x4step::check(homing(h).phase1_speed(100000).phase2_speed(-100000).max_travel(1)), errc::ok);
  EXPECT_EQ(x4step::check(homing(h).phase1_speed(-1).phase2_speed(1).max_travel(2147483647)), errc::ok);
  EXPECT_EQ(x4step::check(homing(h).phase1_speed(0)), errc::param_fail);
  EXPECT_EQ(x4step::check(homing(h).phase1_speed(0).phase1(false)), errc::ok);  // phase 1 unused
  EXPECT_EQ(x4step::check(homing(h).phase2_speed(0).phase2(false)), errc::ok);  // phase 2 unused
  EXPECT_EQ(x4step::check(homing(h).phase2_speed(0)), errc::param_fail);
  EXPECT_EQ(x4step::check(homing(h).phase1_speed(100001)), errc::param_fail);
  EXPECT_EQ(x4step::check(homing(h).phase2_speed(-100001)), errc::param_fail);
  EXPECT_EQ(x4step::check(homing(h).max_travel(0)), errc::param_fail);
  EXPECT_EQ(x4step::check(homing(h).max_travel(2147483648UL)), errc::param_fail);
  EXPECT_EQ(x4step::check(homing(h).phase1(false).phase2(false)), errc::param_fail);
}

TEST(CppApi, AxesStatusPrints) {
  x4step::axes_status s;
  s.axis[0].position = -1200;
  s.axis[0].synced = true;
  s.axis[1].running = true;
  s.axis[1].velocity = 850;
  s.axis[1].accelerating = true;
  s.axis[3].error = x4step::axis_error::limit_pos | x4step::axis_error::ambiguous;
  s.inputs = 0x1f;
  s.switches_active = 0x3;
  std::ostringstream o;
  o << s;
  EXPECT_EQ(o.str(),
            "1: -1200 synced | 2: 0 running 850/s accel | 3: 0 | 4: 0 error 0xa | inputs 0x1f switches 0x3");
}

TEST(CApi, PositioningBeforeInit) {
  long pos = 7;
  int state = 7, error = 7;
  EXPECT_EQ(X4SetProfile(1, 0, 0, 1000, 1000, 1000), X4ErrInitNotDone);
  EXPECT_EQ(X4SetProfile(9, -1, 0, 0, 0, 0), X4ErrInitNotDone);  // state first
  EXPECT_EQ(X4MoveTo(1, 100), X4ErrInitNotDone);
  EXPECT_EQ(X4MoveBy(1, -100), X4ErrInitNotDone);
  EXPECT_EQ(X4Home(1, -1000, 100, 100000, X4HOME_AUTO), X4ErrInitNotDone);
  EXPECT_EQ(X4SetPosition(1, 0), X4ErrInitNotDone);
  EXPECT_EQ(X4GetPosition(1, &pos), X4ErrInitNotDone);
  EXPECT_EQ(X4GetAxisState(1, &state, &error), X4ErrInitNotDone);
  EXPECT_EQ(X4SetSwitches(1, 1, 2, 3), X4ErrInitNotDone);
  EXPECT_EQ(X4SetSwitchPolarity(0x3), X4ErrInitNotDone);
  EXPECT_EQ(X4BrakeAxis(1), X4ErrInitNotDone);
  EXPECT_EQ(X4StopAxis(1), X4ErrInitNotDone);
  EXPECT_EQ(pos, 7);
  EXPECT_EQ(state, 7);
  EXPECT_EQ(error, 7);
}

TEST(CApi, PositioningConstantsAsTheKernels) {
  EXPECT_EQ(X4HOME_AUTO, 3);
  EXPECT_EQ(X4AX_RUN, 1);
  EXPECT_EQ(X4AX_SYNC, 2);
  EXPECT_EQ(X4AX_ERROR, 4);
  EXPECT_EQ(X4AX_REF1, 8);
  EXPECT_EQ(X4AX_REF2, 16);
  EXPECT_EQ(X4AX_ACCEL, 0x100);
  EXPECT_EQ(X4AX_CRUISE, 0x200);
  EXPECT_EQ(X4AX_DECEL, 0x400);
  EXPECT_EQ(X4AXERR_REF_TRAVEL, 1);
  EXPECT_EQ(X4AXERR_LIMIT_POS, 2);
  EXPECT_EQ(X4AXERR_LIMIT_NEG, 4);
  EXPECT_EQ(X4AXERR_AMBIGUOUS, 8);
}

// ---- the library against a fake kernel ---------------------------------------------
//
// ioctl() is interposed: on a descriptor of /dev/zero it is answered by
// fake_kernel (GET_INFO says ABI 2, the rest as a test wishes), so that
// the library's own checks, the structures it passes, its errno mapping
// and wait_axes can be tested without the module. poll() on /dev/zero
// says POLLIN at once.

struct fake_kernel {
  std::vector<unsigned long> calls;  // every ioctl but GET_INFO, in order
  std::function<int(unsigned long cmd, void *arg)> answer = [](unsigned long, void *) { return 0; };

  static fake_kernel &get() {
    static fake_kernel k;
    return k;
  }
};

bool is_fake(int fd) {
  struct stat fs {
  }, zs{};
  return ::fstat(fd, &fs) == 0 && ::stat("/dev/zero", &zs) == 0 && S_ISCHR(fs.st_mode) &&
         fs.st_rdev == zs.st_rdev;
}

extern "C" int ioctl(int fd, unsigned long cmd, ...) noexcept {
  va_list ap;
  va_start(ap, cmd);
  void *arg = va_arg(ap, void *);
  va_end(ap);
  if (!is_fake(fd)) return static_cast<int>(::syscall(SYS_ioctl, fd, cmd, arg));
  if (cmd == X4STEP_GET_INFO) {
    auto *info = static_cast<x4step_info *>(arg);
    *info = {};
    info->abi_version = X4STEP_ABI_VERSION;
    info->axes = X4STEP_AXES;
    return 0;
  }
  fake_kernel &k = fake_kernel::get();
  k.calls.push_back(cmd);
  return k.answer(cmd, arg);
}

class FakeKernel : public ::testing::Test {
 protected:
  void SetUp() override { k = fake_kernel{}; }
  void TearDown() override { k = fake_kernel{}; }
  // Answers cmd with the errno err (and a result, for the ioctls that have one).
  void refuse(unsigned long cmd, int err, int result = 0) {
    k.answer = [=](unsigned long c, void *arg) {
      if (c != cmd) return 0;
      if (c == X4STEP_GOTO) static_cast<x4step_goto *>(arg)->result = result;
      if (c == X4STEP_HOME) static_cast<x4step_home *>(arg)->result = result;
      errno = err;
      return -1;
    };
  }
  fake_kernel &k = fake_kernel::get();
};

TEST_F(FakeKernel, BadArgumentsNeverReachTheKernel) {
  using x4step::errc;
  x4step::controller c("/dev/zero");
  k.calls.clear();
  using x4step::axis;
  const std::array<long, 4> t{};
  EXPECT_EQ(thrown([&] { c.set_profile(axis::x, x4step::profile{}.start_speed(2000)); }), errc::param_fail);
  EXPECT_EQ(thrown([&] { c.move_to(axis::x, 2147483648L); }), errc::param_fail);
  EXPECT_EQ(thrown([&] { c.move_by(axis::a, -2147483649L); }), errc::param_fail);
  EXPECT_EQ(thrown([&] { c.move_to(x4step::axis_set(), t); }), errc::param_fail);
  EXPECT_EQ(thrown([&] { c.move_to(axis::y, {0, 1L << 40, 0, 0}); }), errc::param_fail);
  EXPECT_EQ(thrown([&] { c.home(axis::x, x4step::homing{}.phase1_speed(0)); }), errc::param_fail);
  EXPECT_EQ(thrown([&] { c.halt(x4step::axis_set(), x4step::halt_mode::brake); }), errc::param_fail);
  EXPECT_EQ(thrown([&] { c.set_position(axis::x, 1L << 31); }), errc::param_fail);
  x4step::switches s;
  s.ref[2] = 6;
  EXPECT_EQ(thrown([&] { c.set_switches(s); }), errc::param_fail);
  s.ref[2] = 0;
  s.minus[0] = -1;
  EXPECT_EQ(thrown([&] { c.set_switches(s); }), errc::param_fail);
  s.minus[0] = 0;
  s.nc = 0x20;
  EXPECT_EQ(thrown([&] { c.set_switches(s); }), errc::param_fail);
  EXPECT_EQ(thrown([&] { c.wait_axes(x4step::axis_set()); }), errc::param_fail);
  EXPECT_TRUE(k.calls.empty());
}

TEST_F(FakeKernel, ArgumentsAsTheKernelWantsThem) {
  x4step::controller c("/dev/zero");
  std::vector<std::vector<unsigned char>> args;  // a copy of each argument
  k.answer = [&](unsigned long cmd, void *arg) {
    args.emplace_back(static_cast<unsigned char *>(arg), static_cast<unsigned char *>(arg) + _IOC_SIZE(cmd));
    return 0;
  };
  auto last = [&](auto type) {
    decltype(type) v{};
    EXPECT_EQ(args.back().size(), sizeof v);
    std::memcpy(&v, args.back().data(), sizeof v);
    return v;
  };
  using x4step::axis;
  c.set_profile(axis::y,
                x4step::profile{}.start_speed(10).end_speed(20).top_speed(3000).accel(4000).decel(5000));
  const auto p = last(x4step_profile{});
  EXPECT_EQ(k.calls.back(), X4STEP_SET_PROFILE);
  EXPECT_EQ(p.axis, 2u);
  EXPECT_EQ(std::vector<unsigned>({p.v0, p.ve, p.vm, p.a0, p.ae}),
            std::vector<unsigned>({10, 20, 3000, 4000, 5000}));

  c.move_to(axis::z, -2147483648L);
  auto g = last(x4step_goto{});
  EXPECT_EQ(k.calls.back(), X4STEP_GOTO);
  EXPECT_EQ(g.axes, 0x4u);
  EXPECT_EQ(g.flags, 0u);
  EXPECT_EQ(g.target[2], INT32_MIN);
  c.move_by(axis::x, -5);
  g = last(x4step_goto{});
  EXPECT_EQ(g.axes, 0x1u);
  EXPECT_EQ(g.flags, unsigned(X4STEP_GOTO_RELATIVE));
  EXPECT_EQ(g.target[0], -5);
  c.move_to(axis::x | axis::a, {100, 1L << 40, 0, -300});  // axes outside the set are not looked at
  g = last(x4step_goto{});
  EXPECT_EQ(g.axes, 0x9u);
  EXPECT_EQ(g.target[0], 100);
  EXPECT_EQ(g.target[1], 0);
  EXPECT_EQ(g.target[3], -300);

  c.home(axis::a, x4step::homing{}.phase1_speed(-500).phase2_speed(50).max_travel(7000).phase1(false));
  const auto h = last(x4step_home{});
  EXPECT_EQ(h.axis, 4u);
  EXPECT_EQ(h.phases, unsigned(X4STEP_HOME_PHASE2));
  EXPECT_EQ(h.vref1, -500);
  EXPECT_EQ(h.vref2, 50);
  EXPECT_EQ(h.sref, 7000u);

  c.halt(axis::y | axis::z, x4step::halt_mode::stop);
  const auto hl = last(x4step_halt{});
  EXPECT_EQ(hl.axes, 0x6u);
  EXPECT_EQ(hl.how, unsigned(X4STEP_HALT_STOP));

  c.zero(axis::y);
  auto pos = last(x4step_position{});
  EXPECT_EQ(pos.axes, 0x2u);
  EXPECT_EQ(pos.position[1], 0);
  c.set_position(axis::a, -77);
  pos = last(x4step_position{});
  EXPECT_EQ(pos.axes, 0x8u);
  EXPECT_EQ(pos.position[3], -77);

  x4step::switches s;
  s.ref = {1, 0, 0, 5};
  s.plus = {2, 2, 0, 0};
  s.minus = {3, 3, 0, 4};
  s.nc = 0x1f;
  c.set_switches(s);
  const auto ks = last(x4step_switches{});
  EXPECT_EQ(ks.ref[3], 5);
  EXPECT_EQ(ks.plus[1], 2);
  EXPECT_EQ(ks.minus[3], 4);
  EXPECT_EQ(ks.nc, 0x1f);
  k.calls.clear();
  c.close();  // brakes every axis
  ASSERT_FALSE(k.calls.empty());
  EXPECT_EQ(k.calls.front(), X4STEP_HALT);
  EXPECT_EQ(last(x4step_halt{}).axes, 0xfu);
  EXPECT_EQ(last(x4step_halt{}).how, unsigned(X4STEP_HALT_BRAKE));
}

TEST_F(FakeKernel, ReadsAxesAndSwitches) {
  x4step::controller c("/dev/zero");
  k.answer = [](unsigned long cmd, void *arg) {
    if (cmd == X4STEP_GET_AXES) {
      auto *a = static_cast<x4step_axes *>(arg);
      a->axis[0] = {-5, X4STEP_AX_RUN | X4STEP_AX_DECEL, 0, 321};
      a->axis[2] = {INT32_MAX, X4STEP_AX_SYNC | X4STEP_AX_ERROR | X4STEP_AX_REF2, X4STEP_AXERR_LIMIT_NEG, 0};
      a->inputs = 0x15;
      a->switches = 0x4;
    } else if (cmd == X4STEP_GET_SWITCHES) {
      auto *s = static_cast<x4step_switches *>(arg);
      s->ref[1] = 3;
      s->plus[3] = 5;
      s->minus[0] = 1;
      s->nc = 0x11;
    } else if (cmd == X4STEP_GET_PROFILE) {
      auto *p = static_cast<x4step_profile *>(arg);
      if (p->axis != 3) return errno = EINVAL, -1;
      p->vm = 2500;
      p->a0 = 7;
    }
    return 0;
  };
  const x4step::axes_status s = c.get_axes();
  EXPECT_EQ(s.axis[0].position, -5);
  EXPECT_TRUE(s.axis[0].running);
  EXPECT_TRUE(s.axis[0].decelerating);
  EXPECT_FALSE(s.axis[0].accelerating || s.axis[0].cruising || s.axis[0].synced);
  EXPECT_EQ(s.axis[0].velocity, 321u);
  using x4step::axis;
  EXPECT_EQ(c.get_axis(axis::z).position, INT32_MAX);
  EXPECT_TRUE(c.get_axis(axis::z).synced);
  EXPECT_TRUE(c.get_axis(axis::z).ref2);
  EXPECT_FALSE(c.get_axis(axis::z).running);
  EXPECT_EQ(c.get_axis(axis::z).error, x4step::axis_error::limit_neg);
  EXPECT_EQ(s[axis::x].velocity, 321u);
  EXPECT_EQ(s.inputs, 0x15u);
  EXPECT_EQ(s.switches_active, 0x4u);
  const x4step::switches sw = c.get_switches();
  EXPECT_EQ(sw.ref, (std::array<int, 4>{0, 3, 0, 0}));
  EXPECT_EQ(sw.plus, (std::array<int, 4>{0, 0, 0, 5}));
  EXPECT_EQ(sw.minus, (std::array<int, 4>{1, 0, 0, 0}));
  EXPECT_EQ(sw.nc, 0x11u);
  const x4step::profile p = c.get_profile(axis::z);
  EXPECT_EQ(p.top_speed(), 2500u);
  EXPECT_EQ(p.accel(), 7u);
  EXPECT_EQ(thrown([&] { c.get_profile(axis::y); }), x4step::errc::param_fail);
}

// The errnos of the UAPI become the X4 codes, as for the older ioctls.
TEST_F(FakeKernel, ErrnosBecomeX4Codes) {
  using x4step::errc;
  x4step::controller c("/dev/zero");
  refuse(X4STEP_GOTO, EINVAL, X4ErrParamFail);
  using x4step::axis;
  EXPECT_EQ(thrown([&] { c.move_to(axis::x, 10); }), errc::param_fail);
  refuse(X4STEP_GOTO, EINVAL, X4ErrFreqTooHigh);  // e.g. vm beyond the step timing
  EXPECT_EQ(thrown([&] { c.move_to(axis::x, 10); }), errc::freq_too_high);
  refuse(X4STEP_GOTO, EBUSY);
  EXPECT_EQ(thrown([&] { c.move_by(axis::x, 10); }), errc::is_active);
  refuse(X4STEP_HOME, EINVAL, X4ErrParamFail);  // no REF input
  EXPECT_EQ(thrown([&] { c.home(axis::x, {}); }), errc::param_fail);
  refuse(X4STEP_HOME, EBUSY);
  EXPECT_EQ(thrown([&] { c.home(axis::x, {}); }), errc::is_active);
  refuse(X4STEP_HALT, ESRCH);
  EXPECT_EQ(thrown([&] { c.halt(axis::x, x4step::halt_mode::brake); }), errc::not_active);
  refuse(X4STEP_SET_SWITCHES, EBUSY);
  EXPECT_EQ(thrown([&] { c.set_switches({}); }), errc::is_active);
  refuse(X4STEP_SET_PROFILE, EBUSY);
  EXPECT_EQ(thrown([&] { c.set_profile(axis::x, {}); }), errc::is_active);
  refuse(X4STEP_SET_POSITION, ENODEV);
  EXPECT_EQ(thrown([&] { c.zero(axis::x); }), errc::lpt_not_found);
  refuse(X4STEP_GET_AXES, EFAULT);
  try {
    c.get_axes();
    FAIL() << "no throw";
  } catch (const x4step::error &e) {
    EXPECT_EQ(e.code(), std::error_code(EFAULT, std::system_category()));
  }
  refuse(X4STEP_HALT, ESRCH);  // the destructor's brake finds nothing running
}

TEST_F(FakeKernel, WaitAxesLooksAtTheAxesOnly) {
  x4step::controller c("/dev/zero");
  int reads = 0;
  // Axis 2 runs for 3 reads, axis 4 for ever.
  k.answer = [&](unsigned long cmd, void *arg) {
    if (cmd == X4STEP_GET_AXES) {
      auto *a = static_cast<x4step_axes *>(arg);
      a->axis[1].state = ++reads <= 3 ? X4STEP_AX_RUN : 0;
      a->axis[3].state = X4STEP_AX_RUN;
    }
    return 0;
  };
  using x4step::axis;
  EXPECT_TRUE(c.wait_axes(axis::y, 1000ms));
  EXPECT_EQ(reads, 4);
  EXPECT_TRUE(c.wait_axes(axis::x));  // never ran
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_FALSE(c.wait_axes(axis::y | axis::a, 30ms));
  const auto took = std::chrono::steady_clock::now() - t0;
  EXPECT_GE(took, 30ms);
  EXPECT_LT(took, 1000ms);
  EXPECT_FALSE(c.wait_axes(axis::a, 0ms));
  x4step::monitor m("/dev/zero");
  EXPECT_TRUE(m.wait_axes(axis::y, 0ms));
  EXPECT_FALSE(m.wait_axes(axis::a, 10ms));
  EXPECT_TRUE(m.get_axes().axis[3].running);
}

TEST_F(FakeKernel, ClosedControllerSaysInitNotDone) {
  x4step::controller c("/dev/zero");
  c.close();
  k.calls.clear();
  // State before arguments: even bad ones.
  using x4step::axis;
  EXPECT_EQ(thrown([&] { c.move_to(axis::x, 1L << 40); }), x4step::errc::init_not_done);
  EXPECT_EQ(thrown([&] { c.move_by(axis::a, 1); }), x4step::errc::init_not_done);
  EXPECT_EQ(thrown([&] { c.set_profile(axis::x, x4step::profile{}.top_speed(0)); }),
            x4step::errc::init_not_done);
  EXPECT_EQ(thrown([&] { c.get_axes(); }), x4step::errc::init_not_done);
  EXPECT_EQ(thrown([&] { c.wait_axes(x4step::axis_set()); }), x4step::errc::init_not_done);
  EXPECT_EQ(thrown([&] { c.zero(axis::x); }), x4step::errc::init_not_done);
  EXPECT_TRUE(k.calls.empty());
}

// ---- the C API against the fake kernel -------------------------------------------------
//
// open() is interposed too: while x4step_is_fake is set, /dev/x4stepN
// opens /dev/zero (or fails with open_errno), so that X4Init reaches the
// fake kernel.

bool x4step_is_fake = false;
int open_errno = 0;

extern "C" int open(const char *path, int flags, ...) {
  mode_t mode = 0;
  if (flags & (O_CREAT | O_TMPFILE)) {
    va_list ap;
    va_start(ap, flags);
    mode = va_arg(ap, mode_t);
    va_end(ap);
  }
  if (x4step_is_fake && std::strncmp(path, "/dev/x4step", 11) == 0) {
    if (open_errno) {
      errno = open_errno;
      return -1;
    }
    path = "/dev/zero";
  }
  return static_cast<int>(::syscall(SYS_openat, AT_FDCWD, path, flags, mode));
}

class FakeCApi : public FakeKernel {
 protected:
  void SetUp() override {
    FakeKernel::SetUp();
    x4step_is_fake = true;
    open_errno = 0;
  }
  void TearDown() override {
    X4ReInit();
    x4step_is_fake = false;
    FakeKernel::TearDown();
  }
  // GET_STATUS answers with these flags; other ioctls succeed and are logged.
  void status_flags(uint32_t flags) {
    k.answer = [flags](unsigned long cmd, void *arg) {
      if (cmd == X4STEP_GET_STATUS) static_cast<x4step_status *>(arg)->flags = flags;
      return 0;
    };
  }
  bool called(unsigned long cmd) const { return std::count(k.calls.begin(), k.calls.end(), cmd) > 0; }
};

TEST_F(FakeCApi, X4InitStartsFromTheDosState) {
  // Whatever an earlier controller configured (x4ctl mode, limits, ...).
  std::vector<x4step_config> cfg;
  std::vector<x4step_step_timing> timing;
  std::vector<x4step_brake_codes> codes;
  std::vector<x4step_switches> sw;
  std::vector<x4step_profile> prof;
  k.answer = [&](unsigned long cmd, void *arg) {
    if (cmd == X4STEP_SET_CONFIG) cfg.push_back(*static_cast<x4step_config *>(arg));
    if (cmd == X4STEP_SET_STEP_TIMING) timing.push_back(*static_cast<x4step_step_timing *>(arg));
    if (cmd == X4STEP_SET_BRAKE_CODES) codes.push_back(*static_cast<x4step_brake_codes *>(arg));
    if (cmd == X4STEP_SET_SWITCHES) sw.push_back(*static_cast<x4step_switches *>(arg));
    if (cmd == X4STEP_SET_PROFILE) prof.push_back(*static_cast<x4step_profile *>(arg));
    return 0;
  };
  ASSERT_EQ(X4Init(LPT4), X4NoErr);
  ASSERT_EQ(cfg.size(), 1u);
  EXPECT_EQ(cfg[0].clock_invert | cfg[0].dir_invert | cfg[0].flags, 0u);
  EXPECT_EQ(cfg[0].output_mode, uint32_t(X4STEP_MODE_CLOCK_DIR));
  ASSERT_EQ(timing.size(), 1u);  // the module's defaults; none loaded here: X4Step's
  EXPECT_EQ(timing[0].pulse_ns, 0u);
  EXPECT_EQ(timing[0].dir_setup_ns, 100000u);
  ASSERT_EQ(codes.size(), 1u);
  EXPECT_EQ(codes[0].count, 0u) << "only ESC";
  ASSERT_EQ(sw.size(), 1u);
  const x4step_switches none{};
  EXPECT_EQ(std::memcmp(&sw[0], &none, sizeof none), 0) << "no switches";
  ASSERT_EQ(prof.size(), 4u);
  for (uint32_t a = 0; a < 4; a++) {
    EXPECT_EQ(prof[a].axis, a + 1);
    EXPECT_EQ(prof[a].vm, 1000u);
    EXPECT_EQ(prof[a].a0 + prof[a].ae + prof[a].v0 + prof[a].ve, 2000u);
  }
}

TEST_F(FakeCApi, X4StartAndEndlessMovesOneAtATime) {
  ASSERT_EQ(X4Init(LPT4), X4NoErr);
  // Manual 4.1: while any axis runs (a positioning move too), X4Start and
  // X4MovePos/Neg are X4ErrIsActive; nothing reaches the kernel.
  status_flags(X4STEP_ST_ACTIVE | X4STEP_ST_LOADED);
  k.calls.clear();
  EXPECT_EQ(X4Start(), X4ErrIsActive);
  EXPECT_FALSE(called(X4STEP_START));
  status_flags(X4STEP_ST_ACTIVE);
  EXPECT_EQ(X4MovePos(2, 1000, 50), X4ErrIsActive);
  EXPECT_EQ(X4MoveNeg(2, 1000, 50), X4ErrIsActive);
  EXPECT_FALSE(called(X4STEP_MOVE_ENDLESS));
  EXPECT_EQ(X4Start(), X4ErrNotLoaded) << "nothing loaded comes first";
  // Arguments before state, as documented.
  EXPECT_EQ(X4MovePos(5, 1000, 50), X4ErrParamFail);
  EXPECT_EQ(X4MovePos(1, 20001, 50), X4ErrFreqTooHigh);
  EXPECT_EQ(X4MoveNeg(1, 1000, 1001), X4ErrRampTooHigh);
  status_flags(X4STEP_ST_ACTIVE | X4STEP_ST_LOADED);
  EXPECT_EQ(X4MovePos(1, 1000, 50), X4ErrIsLoaded);
  // Idle: they go through.
  status_flags(X4STEP_ST_LOADED);
  EXPECT_EQ(X4Start(), X4NoErr);
  EXPECT_TRUE(called(X4STEP_START));
  status_flags(0);
  EXPECT_EQ(X4MovePos(1, 1000, 50), X4NoErr);
  EXPECT_TRUE(called(X4STEP_MOVE_ENDLESS));
  EXPECT_EQ(X4Start(), X4ErrNotLoaded);
}

TEST_F(FakeCApi, ErrnosTheManualHasNoCodeFor) {
  // Not in group lp: the port is not to be had, not a bad parameter.
  open_errno = EACCES;
  EXPECT_EQ(X4Init(LPT2), X4ErrLPTNotFound);
  EXPECT_EQ(X4Start(), X4ErrInitNotDone) << "a failed X4Init leaves no port";
  try {
    x4step::controller c(2);
    FAIL() << "no throw";
  } catch (const x4step::error &e) {
    EXPECT_EQ(e.code(), x4step::errc::lpt_not_found);
    EXPECT_NE(std::string(e.what()).find("group lp"), std::string::npos) << e.what();
  }
  open_errno = 0;
  ASSERT_EQ(X4Init(LPT2), X4NoErr);
  // Failures without an X4 code: errno says which; the port-level ones
  // are X4ErrLPTNotFound, the rest X4ErrParamFail.
  errno = 0;
  refuse(X4STEP_BRAKE, EIO);
  EXPECT_EQ(X4Brake(), X4ErrLPTNotFound);
  EXPECT_EQ(errno, EIO);
  refuse(X4STEP_STOP, ENOMEM);
  EXPECT_EQ(X4Stop(), X4ErrParamFail);
  EXPECT_EQ(errno, ENOMEM);
  refuse(X4STEP_SET_OUTPUTS, EFAULT);
  EXPECT_EQ(X4SetOut(SIGNAL1ON), X4ErrParamFail);
  EXPECT_EQ(errno, EFAULT);
  k.answer = [](unsigned long, void *) { return 0; };
}

TEST_F(FakeKernel, DescriptorsForEventLoops) {
  x4step::monitor m(std::filesystem::path("/dev/zero"));
  ASSERT_TRUE(m);
  EXPECT_EQ(m.path(), "/dev/zero");
  ASSERT_GE(m.fd(), 0);
  pollfd p{m.fd(), POLLIN, 0};
  EXPECT_EQ(::poll(&p, 1, 0), 1) << "an event loop polls it";
  m.close();
  EXPECT_FALSE(m);
  EXPECT_EQ(m.fd(), -1);
  EXPECT_EQ(m.path(), "");
  EXPECT_EQ(thrown([&] { m.get_status(); }), x4step::errc::init_not_done);
  m.close();  // idempotent
  x4step::controller c(std::filesystem::path("/dev/zero"));
  EXPECT_GE(c.fd(), 0);
  refuse(X4STEP_BRAKE, ESRCH);  // close() brakes what runs: nothing
  c.close();
  EXPECT_EQ(c.fd(), -1);
}

TEST(CppApi, VersionIsMajorMinorPatch) {
  EXPECT_TRUE(std::regex_match(x4step::version(), std::regex("[0-9]+\\.[0-9]+\\.[0-9]+")))
      << x4step::version();
}

TEST(CppApi, EveryEndReasonPrints) {
  x4step::event e;
  e.type = x4step::event_type::move_ended;
  e.axes = x4step::axis::x;
  for (unsigned how = 1; how <= static_cast<unsigned>(x4step::end_reason::ref_passed); how++) {
    e.how = how;
    std::ostringstream os;
    os << e;
    EXPECT_EQ(os.str().find("axes 1, at 0"), std::string::npos)
        << "no text for end reason " << how << ": " << os.str();
  }
  e.how = static_cast<unsigned>(x4step::end_reason::ref_passed);
  std::ostringstream os;
  os << e;
  EXPECT_NE(os.str().find("braked off the reference switch"), std::string::npos) << os.str();
}

// ---- why an open was refused (EACCES): the message names the fix ----------------------

TEST(AccessDenied, NamesTheFix) {
  using x4step::detail::access_denied_text;
  using x4step::detail::access_facts_of;
  const std::string group = "root:x:0:\nlp:x:7:anna,otto\nusers:x:100:\n";
  const std::string passwd =
      "root:x:0:0::/root:/bin/sh\nanna:x:1000:100::/home/anna:/bin/sh\n"
      "bert:x:1001:100::/home/bert:/bin/sh\ncarl:x:1002:7::/home/carl:/bin/sh\n";
  auto text = [&](gid_t gid, uid_t uid, std::vector<gid_t> session) {
    return access_denied_text("/dev/x4step0", access_facts_of(gid, group, passwd, uid, session));
  };
  EXPECT_EQ(
      text(7, 1001, {100}),
      "/dev/x4step0: permission denied: you are not in group lp, which may use the motors: sudo usermod "
      "-aG lp $USER, then log in again");
  // Added to lp (a member, or lp as the primary group), not yet in this session.
  for (uid_t uid : {1000u, 1002u})
    EXPECT_EQ(
        text(7, uid, {100}),
        "/dev/x4step0: permission denied: you are in group lp, but this login session started before you "
        "were added: log in again (or run 'newgrp lp')")
        << uid;
  EXPECT_NE(text(7, 1000, {100, 7}).find("this session has group lp, yet the node refuses it"),
            std::string::npos);
  // No udev rule: the node is root's.
  EXPECT_EQ(text(0, 1000, {100}),
            "/dev/x4step0: permission denied: the node belongs to group root, not lp: install the udev rule "
            "60-x4step.rules (make install), then 'sudo udevadm trigger'");
}
