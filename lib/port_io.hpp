// SPDX-License-Identifier: LGPL-2.1-or-later
// libx4step internals: the seam between the library and a port. Every
// request the library makes of a port goes through a port_io: the x4step
// module's /dev/x4stepN (kernel_io.cpp) or the simulated port (sim/).
// Both take the module's request structs (linux/x4step.h) and answer as
// the syscalls do (-1 and errno), so everything above is shared.
#ifndef X4STEP_PORT_IO_HPP
#define X4STEP_PORT_IO_HPP

#include <sys/types.h>

#include <chrono>
#include <memory>
#include <string>

namespace x4step::detail {

class port_io {
 public:
  using time_point = std::chrono::steady_clock::time_point;

  virtual ~port_io() = default;
  /// A descriptor for the user's event loops (controller::fd()).
  virtual int fd() const noexcept = 0;
  /// As ioctl(2), read(2), write(2) on the device: -1 and errno on error.
  virtual int ioctl(unsigned long cmd, void *arg) = 0;
  virtual ssize_t read(void *buf, size_t n) = 0;
  virtual ssize_t write(const void *buf, size_t n) = 0;
  /// As poll(2) of the device alone: 1 with *revents, 0 on timeout, -1.
  virtual int poll(short events, int timeout_ms, short *revents) = 0;
  /// The port's clock, which deadlines of waits count on (a simulated
  /// port in virtual time has its own).
  virtual time_point now() const = 0;
  /// A program polls without a request (X4GetTimer): a simulated port in
  /// virtual time lets a little time pass; the device does nothing.
  virtual void let_time_pass() {}
  /// A simulated port in virtual time: its clock moves only as the
  /// library lets time pass (waits, status reads, pass()).
  virtual bool virtual_time() const { return false; }
  /// Virtual time: lets d pass on the port's clock, running what is due
  /// meanwhile (a program's "wait 100 ms" with nothing to wait for); else
  /// nothing: the caller sleeps.
  virtual void pass(std::chrono::nanoseconds d) { (void)d; }
};

/// Open a port by name: a path such as /dev/x4step0, or a simulated port
/// ("sim", "sim:N"); flags O_RDWR (a controller) or O_RDONLY (a monitor).
/// Throws x4step::error as the constructors document.
std::unique_ptr<port_io> open_port(const std::string &name, int flags);

/// The kernel device at path (kernel_io.cpp).
std::unique_ptr<port_io> open_kernel_port(const std::string &path, int flags);

/// The name LPT1..4 opens: /dev/x4step0..3, or sim:0..3 when the
/// environment asks for the simulator (X4STEP_SIM).
std::string port_name(int lpt);

}  // namespace x4step::detail

#endif  // X4STEP_PORT_IO_HPP
