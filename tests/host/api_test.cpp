// SPDX-License-Identifier: LGPL-2.1-or-later
// libx4step on the host, without the kernel module: every error the
// library decides itself.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "x4step.h"
#include "x4step.hpp"
#include "x4step_ext.h"

using namespace std::chrono_literals;

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
  EXPECT_EQ(x4step::check_endless(0, 1000, 0ms), errc::param_fail);
  EXPECT_EQ(x4step::check_endless(4, 1000, 0ms), errc::ok);
  EXPECT_EQ(x4step::check_endless(1, 20, 50ms), errc::ramp_freq);
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
