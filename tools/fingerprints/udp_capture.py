#!/usr/bin/python3
"""Writes every UDP datagram sent to some local ports, in arrival order, one hex line each, a file per port:
what tools/output_fingerprints.sh keeps of the live outputs (VMC, VRChat, OSC) a character would receive.

  udp_capture.py READY_FILE PORT:FILE [PORT:FILE ...]

It touches READY_FILE once every port is bound, and ends after 3 s without a datagram (once one has come) or
after 120 s."""
import pathlib
import select
import socket
import sys
import time


def main():
    if len(sys.argv) < 3:
        sys.exit("usage: udp_capture.py READY_FILE PORT:FILE [PORT:FILE ...]")
    sockets = {}
    for spec in sys.argv[2:]:
        port, path = spec.split(":", 1)
        sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 16 << 20)  # a burst of frames is not dropped
        sock.bind(("127.0.0.1", int(port)))
        sockets[sock] = open(path, "w")
    pathlib.Path(sys.argv[1]).touch()
    started = time.monotonic()
    last = None
    while time.monotonic() - started < 120:
        readable, _, _ = select.select(list(sockets), [], [], 0.2)
        for sock in readable:
            sockets[sock].write(sock.recv(65536).hex() + "\n")
            last = time.monotonic()
        if last is not None and time.monotonic() - last > 3:
            break
    for out in sockets.values():
        out.close()


main()
