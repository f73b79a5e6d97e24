// SPDX-License-Identifier: GPL-2.0
// The simulated port decides who may make a request with x4_req_access()
// (kmod/engine/x4_req.c, req_access_test.cpp), as the module does: on a
// monitor (read-only) descriptor every controller request is EBADF, the
// reading requests and ESTOP are served, anything else is ENOTTY.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/ioctl.h>
#include <linux/x4step.h>

#include <algorithm>
#include <cerrno>
#include <iterator>

#include "sim/sim.hpp"

namespace {

const unsigned int kAny[] = {
    X4STEP_GET_INFO,      X4STEP_GET_STATUS,      X4STEP_GET_CONFIG,  X4STEP_GET_TIMING,
    X4STEP_GET_TIMING_V2, X4STEP_GET_STEP_TIMING, X4STEP_GET_PROFILE, X4STEP_GET_SWITCHES,
    X4STEP_GET_AXES,      X4STEP_GET_PATH_CONFIG, X4STEP_GET_PATH,    X4STEP_ESTOP,
};
const unsigned int kController[] = {
    X4STEP_LOAD,
    X4STEP_START,
    X4STEP_BRAKE,
    X4STEP_STOP,
    X4STEP_MOVE_ENDLESS,
    X4STEP_SET_OUTPUT,
    X4STEP_SET_OUTPUTS,
    X4STEP_SET_BRAKE_CODES,
    X4STEP_SET_CONFIG,
    X4STEP_SET_STEP_TIMING,
    X4STEP_SET_PROFILE,
    X4STEP_GOTO,
    X4STEP_HOME,
    X4STEP_HALT,
    X4STEP_SET_POSITION,
    X4STEP_SET_SWITCHES,
    X4STEP_SET_PATH_CONFIG,
    X4STEP_PATH_CTL,
};

TEST(SimAccess, MonitorsReadControllersChange) {
  auto ctl = x4step::sim::open("sim", O_RDWR);
  auto mon = x4step::sim::open("sim", O_RDONLY);
  alignas(8) unsigned char buf[4096] = {};
  for (const unsigned int cmd : kController) {
    errno = 0;
    EXPECT_EQ(mon->ioctl(cmd, buf), -1) << std::hex << cmd;
    EXPECT_EQ(errno, EBADF) << std::hex << cmd;
  }
  for (const unsigned int cmd : kAny) {
    std::fill(std::begin(buf), std::end(buf), 0);
    if (cmd == X4STEP_GET_PROFILE) buf[0] = 1;  // axis 1
    errno = 0;
    const int ret = mon->ioctl(cmd, buf);
    EXPECT_TRUE(ret == 0 || (errno != EBADF && errno != ENOTTY))
        << std::hex << cmd << ": " << std::dec << errno;
  }
  for (auto *io : {ctl.get(), mon.get()}) {
    errno = 0;
    EXPECT_EQ(io->ioctl(_IO(X4STEP_IOC_MAGIC, 0x7f), buf), -1);
    EXPECT_EQ(errno, ENOTTY);
    errno = 0;
    EXPECT_EQ(io->ioctl(X4STEP_GET_STATUS + (1u << _IOC_SIZESHIFT), buf), -1);
    EXPECT_EQ(errno, ENOTTY);
  }
}

}  // namespace
