// SPDX-License-Identifier: GPL-2.0
// x4grbl: a GRBL 1.1 controller for G-code senders, on an x4step machine.
// One thread: poll() over the signals, the pseudo-terminal, the TCP
// listener, the client and the port; the bridge does the rest.
#include <poll.h>
#include <signal.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bridge.hpp"
#include "link.hpp"

namespace {

const char *const usage_text =
    "usage: x4grbl [--machine FILE] [--sim] [-p N | -d DEVICE] [--link PATH] [--tcp [ADDRESS:]PORT]\n"
    "\n"
    "A GRBL 1.1 controller on an x4step machine, for G-code senders (CNCjs, UGS,\n"
    "bCNC, gSender, LightBurn, OpenBuilds CONTROL): the machine file's axes,\n"
    "limits and homing, the same interpreter and planner as 'x4ctl gcode'.\n"
    "\n"
    "  --machine FILE   the machine file (else $X4STEP_MACHINE, /etc/x4step/machine.ini)\n"
    "  --link PATH      a pseudo-terminal, reached at PATH (a symlink): the port a\n"
    "                   sender opens as a serial port (any baud rate)\n"
    "  --tcp [ADDRESS:]PORT\n"
    "                   a TCP port (raw, as grblHAL's telnet): socket://HOST:PORT in\n"
    "                   UGS and bCNC. Loopback (127.0.0.1) unless ADDRESS is given:\n"
    "                   whoever connects to it can move the machine, so listen on\n"
    "                   another address only on a network you trust\n"
    "  --sim            the simulated port (X4STEP_SIM_MACHINE for its switches):\n"
    "                   a machine to rehearse a job on, kept while x4grbl runs\n"
    "  -p N, -d DEVICE  the port, if not the machine file's PORT\n"
    "\n"
    "One sender at a time: a second is refused (TCP: a [MSG:] line, then closed;\n"
    "the pseudo-terminal: its open fails, device busy). The port is opened when a\n"
    "sender connects and released when it leaves (its motion held along the path\n"
    "and flushed), so x4ctl can use the machine between. SIGTERM, SIGINT: the same,\n"
    "then x4grbl ends. Documentation: docs/grbl.md, man x4grbl.\n";

struct options {
  x4ctl::config machine;
  std::string link;
  std::optional<std::pair<std::string, std::string>> tcp;  // address, port
};

[[noreturn]] void usage_failure(const std::string &why) {
  std::cerr << "x4grbl: " << why << "\n(x4grbl --help shows the options)\n";
  std::exit(2);
}

options parse(int argc, char **argv) {
  options o;
  for (int i = 1; i < argc; i++) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage_failure(a + " needs a value");
      return argv[++i];
    };
    if (a == "--help" || a == "-h") {
      std::cout << usage_text;
      std::exit(0);
    } else if (a == "--machine") {
      o.machine.machine = value();
    } else if (a == "--sim") {
      o.machine.sim = true;
    } else if (a == "-p") {
      const std::string v = value();
      if (v.size() != 1 || v[0] < '1' || v[0] > '4') usage_failure("-p " + v + ": give 1..4");
      o.machine.lpt = v[0] - '0';
    } else if (a == "-d") {
      o.machine.device = value();
    } else if (a == "--link") {
      o.link = value();
    } else if (a == "--tcp") {
      const std::string v = value();
      const size_t colon = v.rfind(':');
      o.tcp = colon == std::string::npos ? std::make_pair(std::string("127.0.0.1"), v)
                                         : std::make_pair(v.substr(0, colon), v.substr(colon + 1));
      if (o.tcp->first.size() > 2 && o.tcp->first.front() == '[' && o.tcp->first.back() == ']')
        o.tcp->first = o.tcp->first.substr(1, o.tcp->first.size() - 2);
    } else {
      usage_failure("unknown option " + a);
    }
  }
  if (o.link.empty() && !o.tcp) usage_failure("give --link PATH (a pseudo-terminal) or --tcp PORT, or both");
  return o;
}

bool is_loopback(const std::string &address) {
  return address == "127.0.0.1" || address == "localhost" || address == "::1";
}

}  // namespace

int main(int argc, char **argv) {
  const options o = parse(argc, argv);
  // Signals arrive as readable data, between two steps of the loop.
  sigset_t mask;
  sigemptyset(&mask);
  for (int s : {SIGTERM, SIGINT, SIGHUP}) sigaddset(&mask, s);
  sigprocmask(SIG_BLOCK, &mask, nullptr);
  const x4grbl::unique_fd sig(::signalfd(-1, &mask, SFD_CLOEXEC | SFD_NONBLOCK));
  ::signal(SIGPIPE, SIG_IGN);

  std::unique_ptr<x4grbl::bridge> b;
  std::unique_ptr<x4grbl::pty_link> pty;
  std::unique_ptr<x4grbl::tcp_listener> tcp;
  try {
    b = std::make_unique<x4grbl::bridge>(o.machine, x4ctl::sim_wanted(o.machine));
    if (!o.link.empty()) pty = std::make_unique<x4grbl::pty_link>(o.link);
    if (o.tcp) tcp = std::make_unique<x4grbl::tcp_listener>(o.tcp->first, o.tcp->second);
  } catch (const std::exception &e) {
    std::cerr << "x4grbl: " << e.what() << "\n";
    return 1;
  }
  if (pty) std::cerr << "x4grbl: GRBL on " << pty->link() << " (" << pty->slave() << ")\n";
  if (tcp) {
    std::cerr << "x4grbl: GRBL on tcp " << o.tcp->first << ":" << tcp->port() << "\n";
    if (!is_loopback(o.tcp->first))
      std::cerr << "x4grbl: warning: listening on " << o.tcp->first
                << ": whoever reaches this address can move the machine\n";
  }

  enum class client_kind { none, pty, tcp };
  client_kind kind = client_kind::none;
  x4grbl::unique_fd tcp_client;
  std::string pending;  // output not yet taken by the client
  auto client_fd = [&] { return kind == client_kind::pty ? pty->fd() : tcp_client.get(); };
  auto log = [&] {
    for (const std::string l = b->take_log(); !l.empty();) {
      std::cerr << "x4grbl: " << l;
      break;
    }
  };
  auto drop_client = [&] {
    b->disconnect();
    if (kind == client_kind::tcp) {
      tcp_client = x4grbl::unique_fd();
      if (pty) pty->reserve(false);
    }
    kind = client_kind::none;
    pending.clear();
    log();
  };
  auto flush = [&] {
    pending += b->take_output();
    if (kind == client_kind::none) {
      pending.clear();
      return;
    }
    // A client that stops reading is dropped before its backlog grows without bound.
    if (!x4grbl::write_some(client_fd(), pending) || pending.size() > (1u << 20)) drop_client();
  };
  // Reads what the client sent; false once it is gone.
  // At most 64 KiB a pass: a client that never stops sending cannot keep
  // the loop from feeding the path.
  auto read_client = [&] {
    char buf[4096];
    for (int pass = 0; pass < 16; pass++) {
      const ssize_t n = ::read(client_fd(), buf, sizeof buf);
      if (n > 0) {
        b->receive(std::string_view(buf, size_t(n)));
        continue;
      }
      if (n < 0 && errno == EINTR) continue;
      if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return true;
      return false;  // 0: the TCP peer closed; EIO: the pty's last client closed
    }
    return true;
  };
  // SIGTERM, SIGINT, SIGHUP: true once one came (it is consumed).
  auto signalled = [&] {
    signalfd_siginfo si{};
    if (::read(sig.get(), &si, sizeof si) <= 0) return false;
    std::cerr << "x4grbl: " << strsignal(int(si.ssi_signo)) << ": motion held, port released\n";
    return true;
  };
  bool stopping = false;
  // A blocking operation (homing) serves the client and the signals
  // meanwhile: a signal brakes it as a reset does, then the loop ends.
  b->on_serve([&](int ms) {
    pollfd p[2] = {{sig.get(), POLLIN, 0}, {kind == client_kind::none ? -1 : client_fd(), POLLIN, 0}};
    if (::poll(p, 2, ms) > 0) {
      if ((p[0].revents & POLLIN) && signalled()) {
        stopping = true;
        b->receive("\x18");
      }
      if ((p[1].revents & (POLLIN | POLLHUP | POLLERR)) && !read_client()) drop_client();
    }
    // Always: a '?' that came with the line that started this is answered now.
    flush();
  });

  while (!stopping) {
    if (pty && kind == client_kind::none && pty->client_present()) {
      kind = client_kind::pty;
      pty->exclusive();
      b->connect();
      log();
    }
    std::vector<pollfd> fds;
    fds.push_back({sig.get(), POLLIN, 0});
    if (tcp) fds.push_back({tcp->fd(), POLLIN, 0});
    if (kind != client_kind::none)
      fds.push_back({client_fd(), short(POLLIN | (pending.empty() ? 0 : POLLOUT)), 0});
    const int timeout = b->busy() ? 5 : kind == client_kind::none && pty ? 50 : 100;
    if (::poll(fds.data(), fds.size(), timeout) < 0 && errno != EINTR) {
      std::cerr << "x4grbl: poll: " << std::strerror(errno) << "\n";
      break;
    }
    if ((fds[0].revents & POLLIN) && signalled()) break;
    // The client first: one that just left makes room for the one knocking.
    if (kind != client_kind::none) {
      const bool gone = kind == client_kind::pty ? !pty->client_present() : false;
      if (!read_client() || gone) drop_client();
    }
    if (tcp && (fds[1].revents & POLLIN)) {
      std::string peer;
      x4grbl::unique_fd c = tcp->accept(peer);
      if (c && kind != client_kind::none) {
        std::string refusal = "[MSG:x4grbl: another sender is connected; one at a time]\r\n";
        x4grbl::write_some(c.get(), refusal);
        std::cerr << "x4grbl: refused " << peer << ": another sender is connected\n";
      } else if (c) {
        tcp_client = std::move(c);
        kind = client_kind::tcp;
        if (pty) pty->reserve(true);
        std::cerr << "x4grbl: sender " << peer << " connected\n";
        b->connect();
        log();
      }
    }
    try {
      b->tick();
    } catch (const std::exception &e) {
      // The port failed under us (a status read, a clear): the client goes,
      // its motion held and flushed, rather than x4grbl.
      std::cerr << "x4grbl: " << e.what() << "\n";
      if (kind != client_kind::none) drop_client();
    }
    flush();
    log();
  }
  b->shutdown();
  log();
  return 0;
}
