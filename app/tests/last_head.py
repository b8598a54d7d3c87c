#!/usr/bin/env python3
"""Receives VMC bundles until the sender falls silent and reports the last Head rotation.

Used while the app is told to quit (Ctrl+C, SIGTERM): its last frame must be the rest pose, a
Head quaternion (x, y, z, w) of (0, 0, 0, 1). python-osc parses the bundles; the first bundle
may take up to --timeout-s, and the sender counts as silent after --quiet-s without a datagram.
With --require-motion, a head away from the rest pose (over 0.5 degrees) must come first: the
quit came while the avatar moved, so the last frame is the quit's own.

Prints a JSON summary; exits 1 when no bundle came, the last head is not the rest pose, or
(--require-motion) no head before it moved.
"""

import argparse
import json
import socket
import sys
import time

from pythonosc.osc_bundle import OscBundle
from pythonosc.osc_message import OscMessage


def head_of(bundle):
    for item in bundle:
        if isinstance(item, OscMessage) and item.address == "/VMC/Ext/Bone/Pos":
            if item.params and item.params[0] == "Head":
                return [float(v) for v in item.params[4:8]]
    return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--port", type=int, required=True)
    ap.add_argument("--timeout-s", type=float, default=30.0)
    ap.add_argument("--quiet-s", type=float, default=2.0)
    ap.add_argument("--ready-file", default=None)
    ap.add_argument("--require-motion", action="store_true")
    args = ap.parse_args()
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.bind(("127.0.0.1", args.port))
    sock.settimeout(0.1)
    if args.ready_file:
        with open(args.ready_file, "w") as f:
            f.write("ready\n")
    bundles, last_head, last_at, moved = 0, None, None, False
    deadline = time.time() + args.timeout_s
    while time.time() < deadline:
        if last_at is not None and time.time() - last_at > args.quiet_s:
            break
        try:
            data, _ = sock.recvfrom(65536)
        except socket.timeout:
            continue
        if OscBundle.dgram_is_bundle(data):
            head = head_of(OscBundle(data))
            if head is not None:
                bundles += 1
                # sin(0.25 degrees): the vector part of a quaternion 0.5 degrees from rest.
                moved = moved or (last_head is not None and max(map(abs, last_head[:3])) > 0.0044)
                last_head = head
                last_at = time.time()
    rest = last_head is not None and all(
        abs(a - b) < 1e-4 for a, b in zip(last_head, (0.0, 0.0, 0.0, 1.0)))
    print(json.dumps({"bundles": bundles, "last_head_xyzw": last_head, "rest": rest,
                      "moved_before": moved}))
    return 0 if rest and (moved or not args.require_motion) else 1


if __name__ == "__main__":
    sys.exit(main())
