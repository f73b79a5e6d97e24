// SPDX-License-Identifier: GPL-2.0
// x4grbl: the pseudo-terminal and the TCP listener (link.hpp).
#include "link.hpp"

#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace x4grbl {

namespace {
std::runtime_error sys_failure(const std::string &what) {
  return std::runtime_error(what + ": " + std::strerror(errno));
}
}  // namespace

unique_fd &unique_fd::operator=(unique_fd &&o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = o.release();
  }
  return *this;
}

unique_fd::~unique_fd() {
  if (fd_ >= 0) ::close(fd_);
}

pty_link::pty_link(std::string link) : link_(std::move(link)) {
  master_ = unique_fd(::posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC | O_NONBLOCK));
  if (!master_ || ::grantpt(master_.get()) < 0 || ::unlockpt(master_.get()) < 0)
    throw sys_failure("cannot create a pseudo-terminal");
  char name[128];
  if (::ptsname_r(master_.get(), name, sizeof name) != 0)
    throw sys_failure("cannot name the pseudo-terminal");
  slave_ = name;
  // Raw both ways, before any client: the welcome line goes out as it is.
  {
    const unique_fd s(::open(slave_.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC));
    termios t{};
    if (!s || ::tcgetattr(s.get(), &t) < 0) throw sys_failure("cannot open " + slave_);
    ::cfmakeraw(&t);
    ::cfsetspeed(&t, B115200);
    if (::tcsetattr(s.get(), TCSANOW, &t) < 0) throw sys_failure("cannot set " + slave_ + " raw");
  }
  struct stat st {};
  if (::lstat(link_.c_str(), &st) == 0 && !S_ISLNK(st.st_mode))
    throw std::runtime_error(link_ + " exists and is no symlink: give --link another path, or remove it");
  const std::string tmp = link_ + ".new";
  ::unlink(tmp.c_str());
  if (::symlink(slave_.c_str(), tmp.c_str()) < 0 || ::rename(tmp.c_str(), link_.c_str()) < 0)
    throw sys_failure("cannot create the link " + link_ +
                      " (does its directory exist and may you write it?)");
}

pty_link::~pty_link() {
  // Only our own link: another x4grbl may have taken the path meanwhile.
  char target[256];
  const ssize_t n = ::readlink(link_.c_str(), target, sizeof target - 1);
  if (n > 0 && std::string(target, size_t(n)) == slave_) ::unlink(link_.c_str());
}

bool pty_link::client_present() const {
  if (guard_) return false;
  pollfd p{master_.get(), POLLIN, 0};
  return ::poll(&p, 1, 0) >= 0 && !(p.revents & POLLHUP);
}

void pty_link::exclusive() {
  // The client holds the slave; ours is opened only to set the flag on it
  // (it stays on the terminal while any process has it open).
  const unique_fd s(::open(slave_.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC | O_NONBLOCK));
  if (s) ::ioctl(s.get(), TIOCEXCL);
}

void pty_link::reserve(bool on) {
  guard_ = unique_fd();
  if (!on) return;
  guard_ = unique_fd(::open(slave_.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC | O_NONBLOCK));
  if (guard_) ::ioctl(guard_.get(), TIOCEXCL);
}

tcp_listener::tcp_listener(const std::string &address, const std::string &port) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo *res = nullptr;
  if (const int e = ::getaddrinfo(address.c_str(), port.c_str(), &hints, &res); e != 0)
    throw std::runtime_error("--tcp " + address + ":" + port + ": " + ::gai_strerror(e));
  std::string why = "no address";
  for (addrinfo *a = res; a; a = a->ai_next) {
    unique_fd s(::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC | SOCK_NONBLOCK, a->ai_protocol));
    if (!s) continue;
    const int one = 1;
    ::setsockopt(s.get(), SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    if (::bind(s.get(), a->ai_addr, a->ai_addrlen) == 0 && ::listen(s.get(), 4) == 0) {
      fd_ = std::move(s);
      break;
    }
    why = std::strerror(errno);
  }
  ::freeaddrinfo(res);
  if (!fd_) throw std::runtime_error("--tcp " + address + ":" + port + ": cannot listen: " + why);
}

int tcp_listener::port() const {
  sockaddr_storage sa{};
  socklen_t len = sizeof sa;
  if (::getsockname(fd_.get(), reinterpret_cast<sockaddr *>(&sa), &len) < 0) return -1;
  return ntohs(sa.ss_family == AF_INET6 ? reinterpret_cast<sockaddr_in6 *>(&sa)->sin6_port
                                        : reinterpret_cast<sockaddr_in *>(&sa)->sin_port);
}

unique_fd tcp_listener::accept(std::string &peer) const {
  sockaddr_storage sa{};
  socklen_t len = sizeof sa;
  unique_fd c(::accept4(fd_.get(), reinterpret_cast<sockaddr *>(&sa), &len, SOCK_CLOEXEC | SOCK_NONBLOCK));
  if (!c) return c;
  const int one = 1;
  ::setsockopt(c.get(), IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  char host[NI_MAXHOST], serv[NI_MAXSERV];
  if (::getnameinfo(reinterpret_cast<sockaddr *>(&sa), len, host, sizeof host, serv, sizeof serv,
                    NI_NUMERICHOST | NI_NUMERICSERV) == 0)
    peer = std::string(host) + ":" + serv;
  return c;
}

bool write_some(int fd, std::string &pending) {
  while (!pending.empty()) {
    const ssize_t n = ::write(fd, pending.data(), pending.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return errno == EAGAIN || errno == EWOULDBLOCK;
    pending.erase(0, size_t(n));
  }
  return true;
}

}  // namespace x4grbl
