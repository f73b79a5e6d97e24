// SPDX-License-Identifier: GPL-2.0
// Unit test of x4_req_access() (kmod/engine/x4_req.c): who may make each
// request of linux/x4step.h. The module's x4step_ioctl() and the
// simulated port both ask it: the reading requests and ESTOP on any
// descriptor, every request that changes something on the controller's
// only (EBADF elsewhere), anything else ENOTTY.
// The simulated port asking it: sim_access_test.cpp.
#include <gtest/gtest.h>
#include <linux/ioctl.h>

extern "C" {
#include "x4_req.h"
}

namespace {

struct request {
  unsigned int cmd;
  const char *name;
};

#define REQ(c) \
  { c, #c }

// linux/x4step.h, ABI 1 to 5.
const request kAny[] = {
    REQ(X4STEP_GET_INFO),      REQ(X4STEP_GET_STATUS),      REQ(X4STEP_GET_CONFIG),  REQ(X4STEP_GET_TIMING),
    REQ(X4STEP_GET_TIMING_V2), REQ(X4STEP_GET_STEP_TIMING), REQ(X4STEP_GET_PROFILE), REQ(X4STEP_GET_SWITCHES),
    REQ(X4STEP_GET_AXES),      REQ(X4STEP_GET_PATH_CONFIG), REQ(X4STEP_GET_PATH),    REQ(X4STEP_ESTOP),
};
const request kController[] = {
    REQ(X4STEP_LOAD),
    REQ(X4STEP_START),
    REQ(X4STEP_BRAKE),
    REQ(X4STEP_STOP),
    REQ(X4STEP_MOVE_ENDLESS),
    REQ(X4STEP_SET_OUTPUT),
    REQ(X4STEP_SET_OUTPUTS),
    REQ(X4STEP_SET_BRAKE_CODES),
    REQ(X4STEP_SET_CONFIG),
    REQ(X4STEP_SET_STEP_TIMING),
    REQ(X4STEP_SET_PROFILE),
    REQ(X4STEP_GOTO),
    REQ(X4STEP_HOME),
    REQ(X4STEP_HALT),
    REQ(X4STEP_SET_POSITION),
    REQ(X4STEP_SET_SWITCHES),
    REQ(X4STEP_SET_PATH_CONFIG),
    REQ(X4STEP_PATH_CTL),
};

TEST(ReqAccess, ReadingRequestsAndEstopOnAnyDescriptor) {
  for (const request &r : kAny) EXPECT_EQ(x4_req_access(r.cmd), X4_REQ_ANY) << r.name;
}

TEST(ReqAccess, EveryChangeOnTheControllersDescriptorOnly) {
  EXPECT_EQ(sizeof kController / sizeof kController[0], 18u);
  for (const request &r : kController) EXPECT_EQ(x4_req_access(r.cmd), X4_REQ_CONTROLLER) << r.name;
}

// A request is its whole number: direction, size, type and number. Each
// known one with another size or direction, and the numbers around them,
// is no request.
TEST(ReqAccess, AnythingElseUnknown) {
  EXPECT_EQ(x4_req_access(0), X4_REQ_UNKNOWN);
  EXPECT_EQ(x4_req_access(~0u), X4_REQ_UNKNOWN);
  for (unsigned int nr = 0; nr < 0x100; nr++) {
    const unsigned int plain = _IO(X4STEP_IOC_MAGIC, nr);
    if (plain != X4STEP_START && plain != X4STEP_BRAKE && plain != X4STEP_STOP) {
      EXPECT_EQ(x4_req_access(plain), X4_REQ_UNKNOWN) << std::hex << plain;
    }
    EXPECT_EQ(x4_req_access(_IO('T', nr)), X4_REQ_UNKNOWN) << std::hex << nr;  // a tty's
  }
  const auto others_unknown = [](const request &r) {
    const unsigned int other_size = r.cmd + (1u << _IOC_SIZESHIFT);
    const unsigned int other_type = (r.cmd & ~(_IOC_TYPEMASK << _IOC_TYPESHIFT)) | ('T' << _IOC_TYPESHIFT);
    EXPECT_EQ(x4_req_access(other_size), X4_REQ_UNKNOWN) << r.name;
    EXPECT_EQ(x4_req_access(other_type), X4_REQ_UNKNOWN) << r.name;
    // The other direction: SET_CONFIG's number read, GET_CONFIG's written.
    const unsigned int dir = _IOC_DIR(r.cmd);
    if (dir == _IOC_READ || dir == _IOC_WRITE) {
      const unsigned int other_dir = r.cmd ^ ((_IOC_READ | _IOC_WRITE) << _IOC_DIRSHIFT);
      EXPECT_EQ(x4_req_access(other_dir), X4_REQ_UNKNOWN) << r.name;
    }
  };
  for (const request &r : kAny) others_unknown(r);
  for (const request &r : kController) others_unknown(r);
}

}  // namespace
