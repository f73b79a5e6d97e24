// SPDX-License-Identifier: LGPL-2.1-or-later
// libx4step: a descriptor of a simulated port, behind the library's seam
// (port_io.hpp). fd() is an eventfd that is readable while the module's
// descriptor would poll readable or with POLLPRI: no move runs, or an
// event is there to read.
#include <fcntl.h>

#include <cerrno>

#include "../port_io.hpp"
#include "port.hpp"
#include "sim.hpp"

namespace x4step::sim {
namespace {

class sim_io final : public detail::port_io {
 public:
  sim_io(std::shared_ptr<port> p, bool controller) : port_(std::move(p)) { port_->open(file_, controller); }
  sim_io(const sim_io &) = delete;
  sim_io &operator=(const sim_io &) = delete;
  ~sim_io() override { port_->close(file_); }

  int fd() const noexcept override { return file_.efd; }
  int ioctl(unsigned long cmd, void *arg) override { return port_->ioctl(file_, cmd, arg); }
  ssize_t read(void *buf, size_t n) override { return port_->read(file_, buf, n); }
  ssize_t write(const void *buf, size_t n) override { return port_->write(file_, buf, n); }
  int poll(short events, int timeout_ms, short *revents) override {
    return port_->poll(file_, events, timeout_ms, revents);
  }
  time_point now() const override { return port_->now(); }
  void let_time_pass() override { port_->let_time_pass(); }
  bool virtual_time() const override { return port_->settings().time == time_mode::virtual_; }
  void pass(std::chrono::nanoseconds d) override {
    if (virtual_time() && d.count() > 0)
      port_->run_until(port_->engine_now() + static_cast<std::uint64_t>(d.count()));
  }

 private:
  std::shared_ptr<port> port_;
  file file_;
};

}  // namespace

std::unique_ptr<detail::port_io> open(const std::string &name, int flags) {
  const int n = port_number(name);
  const options o = options_from_env();
  return std::make_unique<sim_io>(port::get(n, o), (flags & O_ACCMODE) != O_RDONLY);
}

}  // namespace x4step::sim
