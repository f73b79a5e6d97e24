// SPDX-License-Identifier: LGPL-2.1-or-later
// libx4step: the port as the x4step module's /dev/x4stepN (port_io.hpp):
// each request is the syscall on the device's descriptor.
#include <fcntl.h>
#include <linux/x4step.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <unistd.h>

#include <cerrno>
#include <fstream>

#include "detail.hpp"
#include "port_io.hpp"
#include "x4step_access.hpp"

namespace x4step::detail {
namespace {

// A controller's open refused with EBUSY: say who holds the port. The
// parport core names the device that has claimed parportN (the device's
// minor) in /proc/sys/dev/parport/parportN/devices/active: "x4step" (a
// controller, or the module still braking the moves of one that closed),
// "ppdev0" (a program using /dev/parport0), "lp", ..., or "none".
[[noreturn]] void fail_busy(const std::string &path) {
  std::string why = "port busy: another x4step controller, or another driver (lp, ppdev), has it";
  struct stat sb {};
  if (::stat(path.c_str(), &sb) == 0 && S_ISCHR(sb.st_mode)) {
    const std::string port = "parport" + std::to_string(minor(sb.st_rdev));
    std::ifstream active("/proc/sys/dev/parport/" + port + "/devices/active");
    std::string holder;
    if (!(active >> holder)) {
      // No parport sysctl: keep the general text.
    } else if (holder == "x4step") {
      why = "port busy: another x4step controller has " + port +
            ", or the module is still braking the motors of one that closed";
    } else if (holder == "none") {
      why = "port busy: " + port + " was busy and is free now: try again";
    } else {
      why = "port busy: " + port + " is claimed by " + holder + " (another parport driver" +
            (holder.rfind("ppdev", 0) == 0 ? ", for a program using /dev/" + port + ": end it"
             : holder == "lp"              ? ", the printer driver: wait for the print job, or unload it: "
                                             "sudo modprobe -r lp"
                                           : std::string()) +
            ")";
    }
  }
  throw error(make_error_code(errc::lpt_not_found), path + ": " + why);
}

int open_device(const std::string &path, int flags) {
  // Non-blocking: read_event() polls, and its read must not outlast the
  // wait (another descriptor of the same open file may take the event).
  const int fd = ::open(path.c_str(), flags | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) {
    if (errno == EBUSY) fail_busy(path);
    if (errno == ENOENT || errno == ENODEV || errno == ENXIO) fail(errc::lpt_not_found);
    if (errno == EACCES || errno == EPERM)
      throw error(make_error_code(errc::lpt_not_found), detail::access_denied_text(path));
    fail_errno(errno, "open " + path);
  }
  x4step_info info{};
  // Versions only add: any module of this version or newer will do.
  if (::ioctl(fd, X4STEP_GET_INFO, &info)) {
    ::close(fd);
    fail(errc::lpt_not_found);
  }
  if (info.abi_version < X4STEP_ABI_VERSION) {
    ::close(fd);
    throw error(make_error_code(errc::lpt_not_found),
                path + ": the x4step module speaks interface version " + std::to_string(info.abi_version) +
                    ", this library needs " + std::to_string(X4STEP_ABI_VERSION) + ": update x4step.ko");
  }
  return fd;
}

class kernel_io final : public port_io {
 public:
  kernel_io(const std::string &path, int flags) : fd_(open_device(path, flags)) {}
  kernel_io(const kernel_io &) = delete;
  kernel_io &operator=(const kernel_io &) = delete;
  ~kernel_io() override { ::close(fd_); }

  int fd() const noexcept override { return fd_; }
  int ioctl(unsigned long cmd, void *arg) override { return ::ioctl(fd_, cmd, arg); }
  ssize_t read(void *buf, size_t n) override { return ::read(fd_, buf, n); }
  ssize_t write(const void *buf, size_t n) override { return ::write(fd_, buf, n); }
  int poll(short events, int timeout_ms, short *revents) override {
    pollfd p{fd_, events, 0};
    const int n = ::poll(&p, 1, timeout_ms);
    *revents = p.revents;
    return n;
  }
  time_point now() const override { return std::chrono::steady_clock::now(); }

 private:
  int fd_;
};

}  // namespace

std::unique_ptr<port_io> open_kernel_port(const std::string &path, int flags) {
  return std::make_unique<kernel_io>(path, flags);
}

}  // namespace x4step::detail
