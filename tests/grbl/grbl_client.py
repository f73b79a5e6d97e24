# SPDX-License-Identifier: GPL-2.0
"""A GRBL 1.1 client for the bridge's tests: x4grbl started on the
simulated port with the test mill (tests/x4ctl/test-mill.ini and its
switches), a connection by TCP or by the pseudo-terminal, lines sent with
GRBL's character counting, replies and status reports read apart."""
import os
import re
import select
import shutil
import socket
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
MILL = os.path.join(HERE, "..", "x4ctl", "test-mill.ini")
MILL_SIM = os.path.join(HERE, "..", "x4ctl", "test-mill.sim")
RX_BUFFER = 128
_failed = False


def check(name, ok, detail=""):
    global _failed
    print(("PASS " if ok else "FAIL ") + name + ("" if ok else "\n" + str(detail)))
    sys.stdout.flush()
    _failed |= not ok


def exit_status():
    return 1 if _failed else 0


class Bridge:
    """x4grbl --sim in a directory of its own, with a copy of the test
    mill that keeps its offsets in mill.var."""

    def __init__(self, x4grbl, link=False, extra_ini="", replace=(), sim_machine=None, machine_text=None):
        """machine_text: another machine than the test mill (no switches, no
        probe); sim_machine: another simulated machine for the test mill."""
        self.dir = tempfile.mkdtemp(prefix="x4grbl-test.")
        self.machine = os.path.join(self.dir, "mill.ini")
        with open(MILL) as f:
            text = f.read() if machine_text is None else machine_text
        text = text.replace("[X4STEP]\n", "[RS274NGC]\nPARAMETER_FILE = mill.var\n[X4STEP]\n" + extra_ini, 1)
        for old, new in replace:  # the test mill written another way
            text = text.replace(old, new)
        if machine_text is None:
            # A touch probe on input 4 (pin 10), active at Z motor step -2000 and below.
            text = text.replace("[X4STEP]\n", "[X4STEP]\nPROBE_INPUT = 4\n", 1)
            if sim_machine is None:
                sim_machine = os.path.join(self.dir, "mill.sim")
                with open(MILL_SIM) as f:
                    sim = f.read() + "probe 3 below -2000 pin10 no\n"
                with open(sim_machine, "w") as f:
                    f.write(sim)
        with open(self.machine, "w") as f:
            f.write(text)
        self.link = os.path.join(self.dir, "ttyGRBL0") if link else None
        args = [x4grbl, "--sim", "--machine", self.machine, "--tcp", "127.0.0.1:0"]
        if self.link:
            args += ["--link", self.link]
        env = dict(os.environ)
        if machine_text is None:
            env["X4STEP_SIM_MACHINE"] = sim_machine
        else:
            env.pop("X4STEP_SIM_MACHINE", None)
        env.pop("X4STEP_SIM_TIME", None)
        self.log = open(os.path.join(self.dir, "log"), "w+")
        self.proc = subprocess.Popen(args, stderr=self.log, env=env)
        self.port = None
        deadline = time.time() + 20
        while time.time() < deadline and self.port is None:
            time.sleep(0.05)
            self.log.seek(0)
            m = re.search(r"GRBL on tcp 127.0.0.1:(\d+)", self.log.read())
            if m:
                self.port = int(m.group(1))
        if self.port is None:
            raise RuntimeError("x4grbl did not start: " + self.log_text())

    def log_text(self):
        self.log.seek(0)
        return self.log.read()

    def connect(self, greeting=True):
        """A client; greeting: its welcome read (and what follows it at once)."""
        s = socket.create_connection(("127.0.0.1", self.port))
        # A '?' right after a line must not wait for the line's ACK (Nagle).
        s.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        c = Client(s)
        if greeting:
            c.greet()
        return c

    def stop(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(20)
            except subprocess.TimeoutExpired:
                self.proc.kill()
        shutil.rmtree(self.dir, ignore_errors=True)


class Client:
    """One sender. Lines are read whole; status reports go to `reports`,
    everything else to `lines`."""

    def __init__(self, sock=None, fd=None):
        self.sock = sock
        self.fd = fd if fd is not None else sock.fileno()
        self.buf = b""
        self.lines = []
        self.reports = []
        self.inflight = []  # lengths of the lines not yet answered (character counting)

    def close(self):
        if self.sock:
            self.sock.close()
        else:
            os.close(self.fd)

    def send(self, data):
        if isinstance(data, str):
            data = data.encode("latin-1")
        while data:
            n = os.write(self.fd, data)
            data = data[n:]

    def _read(self, timeout):
        r, _, _ = select.select([self.fd], [], [], timeout)
        if not r:
            return False
        try:
            d = os.read(self.fd, 65536)
        except OSError:
            d = b""
        if not d:
            raise EOFError("the bridge closed the connection")
        self.buf += d
        while b"\n" in self.buf:
            line, self.buf = self.buf.split(b"\n", 1)
            line = line.rstrip(b"\r").decode("latin-1")
            if line.startswith("<"):
                self.reports.append(line)
            elif line:
                self.lines.append(line)
        return True

    def greet(self):
        """Reads the welcome and the lines that come with it; returns them."""
        while True:
            line = self.next_line()
            if line.startswith("Grbl "):
                break
        self.pump(0.3)
        got = [line] + self.lines
        self.lines = []
        return got

    def pump(self, timeout=0.0):
        end = time.time() + timeout
        while True:
            if not self._read(max(0.0, end - time.time())):
                return

    def next_line(self, timeout=10.0):
        end = time.time() + timeout
        while not self.lines:
            if time.time() > end or (not self._read(end - time.time()) and time.time() > end):
                raise TimeoutError("no line from the bridge; had: %r" % self.reports[-3:])
        return self.lines.pop(0)

    def command(self, line, timeout=10.0):
        """Sends a line, returns every line until its ok or error:N (included)."""
        self.send(line + "\n")
        got = []
        while True:
            l = self.next_line(timeout)
            got.append(l)
            if l == "ok" or l.startswith("error:"):
                return got

    def status(self, timeout=5.0):
        n = len(self.reports)
        self.send("?")
        end = time.time() + timeout
        while len(self.reports) == n:
            if time.time() > end:
                raise TimeoutError("no status report")
            self._read(end - time.time())
        return self.reports[-1]

    def wait_state(self, states, timeout=60.0):
        end = time.time() + timeout
        while time.time() < end:
            s = self.status()
            if state_of(s) in states:
                return s
            time.sleep(0.05)
        raise TimeoutError("state never in %s: last %s" % (states, s))

    def stream(self, lines, timeout=120.0, on_ack=None, on_wait=None):
        """Streams lines with character counting (at most 128 bytes not
        yet answered); returns the replies in order. on_ack(client, reply)
        after each reply, on_wait(client) while waiting for one."""
        replies = []
        pending = list(lines)
        end = time.time() + timeout
        while pending or self.inflight:
            while pending and sum(self.inflight) + len(pending[0]) + 1 <= RX_BUFFER:
                l = pending.pop(0)
                self.send(l + "\n")
                self.inflight.append(len(l) + 1)
            if time.time() > end:
                raise TimeoutError("stream stuck: %d lines left" % len(pending))
            self._read(0.01 if on_wait else 0.5)
            if on_wait:
                on_wait(self)
            while self.lines:
                l = self.lines.pop(0)
                if l == "ok" or l.startswith("error:"):
                    self.inflight.pop(0)
                    replies.append(l)
                    if on_ack:
                        on_ack(self, l)
                elif l.startswith("ALARM"):
                    replies.append(l)
                    return replies
        return replies


def state_of(report):
    return report[1:].split("|")[0]


def field(report, name):
    for f in report[1:-1].split("|")[1:]:
        if f.startswith(name + ":"):
            return f[len(name) + 1:]
    return None


def mpos(report):
    return [float(v) for v in field(report, "MPos").split(",")]
