#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0
"""Send commands to a QEMU human monitor on a unix socket and print the replies.

Usage: tests/qemu/qemu-monitor.py SOCK COMMAND...   e.g.  qemu-monitor.py /tmp/mon "sendkey esc"

Standard library only. Waits up to 10 s for the socket to appear (QEMU creates
it at start-up), so it can be called right after launching run-guest.sh.
"""
import os
import socket
import sys
import time

PROMPT = b"(qemu) "


def read_until_prompt(sock, deadline):
    buf = b""
    while not buf.endswith(PROMPT):
        sock.settimeout(max(0.1, deadline - time.monotonic()))
        chunk = sock.recv(4096)
        if not chunk:
            break
        buf += chunk
    return buf


def main(argv):
    if len(argv) < 3:
        print(__doc__.strip().splitlines()[2], file=sys.stderr)
        return 2
    path, commands = argv[1], argv[2:]
    deadline = time.monotonic() + 10
    while not os.path.exists(path):
        if time.monotonic() > deadline:
            print(f"qemu-monitor: no socket {path}", file=sys.stderr)
            return 1
        time.sleep(0.05)
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as sock:
        sock.connect(path)
        read_until_prompt(sock, time.monotonic() + 10)  # banner
        for cmd in commands:
            sock.sendall(cmd.encode() + b"\n")
            reply = read_until_prompt(sock, time.monotonic() + 10)
            # The monitor echoes the command line (with terminal escapes) first.
            text = reply.decode(errors="replace").replace("\r", "")
            lines = [l for l in text.split("\n")[1:] if l and not l.startswith("(qemu)")]
            if lines:
                print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
