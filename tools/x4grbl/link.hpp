// SPDX-License-Identifier: GPL-2.0
// x4grbl: where senders connect. A pseudo-terminal behind a stable symlink
// (CNCjs, LightBurn, OpenBuilds CONTROL open it as a serial port) and a
// TCP port (UGS, gSender, bCNC: socket://host:port), one client at a time.
#ifndef X4GRBL_LINK_HPP
#define X4GRBL_LINK_HPP

#include <string>

namespace x4grbl {

/// A descriptor, closed however the scope ends.
class unique_fd {
 public:
  unique_fd() = default;
  explicit unique_fd(int fd) : fd_(fd) {}
  unique_fd(unique_fd &&o) noexcept : fd_(o.release()) {}
  unique_fd &operator=(unique_fd &&o) noexcept;
  ~unique_fd();
  int get() const noexcept { return fd_; }
  int release() noexcept {
    const int f = fd_;
    fd_ = -1;
    return f;
  }
  explicit operator bool() const noexcept { return fd_ >= 0; }

 private:
  int fd_ = -1;
};

/// The pseudo-terminal: its master, and the symlink to its slave.
class pty_link {
 public:
  /// Creates the pair (raw, no echo) and the symlink `link` (replaced if
  /// it is a symlink; refused if it is anything else). Throws
  /// std::runtime_error saying what to fix.
  explicit pty_link(std::string link);
  ~pty_link();
  pty_link(const pty_link &) = delete;
  pty_link &operator=(const pty_link &) = delete;

  int fd() const noexcept { return master_.get(); }
  const std::string &slave() const noexcept { return slave_; }
  const std::string &link() const noexcept { return link_; }
  /// Whether a client has the slave open (the master is not hung up).
  bool client_present() const;
  /// The client that has the slave open is the only one: TIOCEXCL on
  /// it, so that a second sender's open fails with EBUSY ("device busy").
  void exclusive();
  /// While a TCP client is in: the slave held open by us, exclusive, so
  /// that no sender opens it meanwhile.
  void reserve(bool on);

 private:
  unique_fd master_;
  unique_fd guard_;  // the slave, held open with TIOCEXCL while a TCP client is in
  std::string slave_, link_;
};

/// The TCP listener: loopback unless an address is given.
class tcp_listener {
 public:
  /// address: "127.0.0.1", "::1", "0.0.0.0", a host name ...; throws
  /// std::runtime_error naming the address and why.
  tcp_listener(const std::string &address, const std::string &port);
  int fd() const noexcept { return fd_.get(); }
  /// The port listened on (port 0 asks the kernel for a free one).
  int port() const;
  /// A new connection (non-blocking, TCP_NODELAY), and its peer as text.
  unique_fd accept(std::string &peer) const;

 private:
  unique_fd fd_;
};

/// Writes what it can now; false if the peer is gone.
bool write_some(int fd, std::string &pending);

}  // namespace x4grbl

#endif  // X4GRBL_LINK_HPP
