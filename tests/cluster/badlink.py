#!/usr/bin/env python3
"""badlink.py TAP_A TAP_B DELAY_MS JITTER_MS LOSS_PCT - a bad cable in user space.

Creates two tap devices in the current network namespace and relays every
Ethernet frame between them, each one delayed by DELAY_MS plus a uniform
jitter of +-JITTER_MS and dropped with probability LOSS_PCT %, in both
directions (frames may overtake each other, as with netem's jitter).
cluster.sh uses it on kernels without the netem qdisc. Prints "ready" once
both taps exist; runs until killed.
"""
import fcntl
import heapq
import os
import random
import select
import struct
import sys
import time

TUNSETIFF = 0x400454CA
IFF_TAP = 0x0002
IFF_NO_PI = 0x1000


def open_tap(name):
    fd = os.open("/dev/net/tun", os.O_RDWR)
    fcntl.ioctl(fd, TUNSETIFF, struct.pack("16sH", name.encode(), IFF_TAP | IFF_NO_PI))
    os.set_blocking(fd, False)
    return fd


def main():
    if len(sys.argv) != 6:
        sys.exit(__doc__.splitlines()[0])
    a, b = open_tap(sys.argv[1]), open_tap(sys.argv[2])
    delay, jitter, loss = float(sys.argv[3]) / 1e3, float(sys.argv[4]) / 1e3, float(sys.argv[5]) / 100
    other = {a: b, b: a}
    rng = random.Random(25)
    queue = []  # (due time, sequence number, destination fd, frame)
    seq = passed = dropped = 0
    last_report = time.monotonic()
    print("ready", flush=True)
    while True:
        timeout = max(0.0, queue[0][0] - time.monotonic()) if queue else None
        readable, _, _ = select.select([a, b], [], [], timeout)
        for fd in readable:
            while True:
                try:
                    frame = os.read(fd, 65536)
                except BlockingIOError:
                    break
                except OSError:  # the tap went down (e.g. its namespace was deleted)
                    return
                if rng.random() < loss:
                    dropped += 1
                    continue
                seq += 1
                due = time.monotonic() + max(0.0, delay + rng.uniform(-jitter, jitter))
                heapq.heappush(queue, (due, seq, other[fd], frame))
        now = time.monotonic()
        while queue and queue[0][0] <= now:
            _, _, dest, frame = heapq.heappop(queue)
            try:
                os.write(dest, frame)
                passed += 1
            except OSError:  # the other side is not up (yet): the frame is lost
                dropped += 1
        if now - last_report >= 1.0:
            print(f"frames passed {passed}, dropped {dropped}", flush=True)
            last_report = now


if __name__ == "__main__":
    main()
