// SPDX-License-Identifier: GPL-2.0
// Host tests of the simulated port: the environment each test starts from.
// The tests set the variables they need; none comes in from the shell that
// runs them (a machine file, a key script, X4STEP_SIM_KEYS=tty) or from
// the test before.
#ifndef X4STEP_TESTS_SIM_ENV_HPP
#define X4STEP_TESTS_SIM_ENV_HPP

#include <gtest/gtest.h>
#include <stdlib.h>

/// Every variable of the simulated port (README, "Try it without a
/// parallel port").
inline constexpr const char *sim_variables[] = {"X4STEP_SIM",      "X4STEP_SIM_TIME",    "X4STEP_SIM_VCD",
                                                "X4STEP_SIM_KEYS", "X4STEP_SIM_MACHINE", "X4STEP_SIM_INPUTS"};

inline void clear_sim_environment() {
  for (const char *v : sim_variables) unsetenv(v);
}

/// A test of the simulated port: it starts in virtual time with no other
/// variable set, and leaves none set.
class SimEnv : public ::testing::Test {
 protected:
  void SetUp() override {
    clear_sim_environment();
    setenv("X4STEP_SIM_TIME", "virtual", 1);
  }
  void TearDown() override { clear_sim_environment(); }
};

#endif  // X4STEP_TESTS_SIM_ENV_HPP
