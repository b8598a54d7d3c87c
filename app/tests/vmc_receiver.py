#!/usr/bin/env python3
"""Receives Pneuma's VMC output with third-party code and checks it.

python-osc parses the UDP datagrams (OSC 1.0 bundles); vmcp (the VMC protocol package) turns
each message into its events, which refuses unknown bone names and argument shapes. Checked:
- every datagram is one bundle, and every bundle is one frame: `/VMC/Ext/OK` (model loaded) and
  `/VMC/Ext/T` (the frame's time) once each, bones Chest, Neck, Head (Unity HumanBodyBones
  names), blendshape values, then `/VMC/Ext/Blend/Apply` exactly once, last;
- blendshape names: `A` is a VRM preset (mouth open), the others are named custom clips;
- time tags increase by one send period, and the `/VMC/Ext/T` times by one frame period of the
  stream (one bundle per frame, none repeated; the two differ when the sender paces faster than
  real time);
- with --expect-head PITCH,YAW,ROLL (degrees, Pneuma's right-handed convention: pitch + = chin
  up, yaw + = looking to the character's left, roll + = head tilted to its left): the Head
  quaternion (x, y, z, w) read in Unity's left-handed frame (Y up, the avatar facing +Z, X to
  its right) looks up / to the avatar's left (-X) / tilts its top to -X as the signs say, and
  its Unity Euler angles (Quaternion.eulerAngles, Z then X then Y) are (-pitch, -yaw, roll).

Prints a JSON summary; exits 1 with the reasons when a check fails.
"""

import argparse
import json
import math
import socket
import sys
import time

from pythonosc.osc_bundle import OscBundle
from pythonosc.osc_message import OscMessage
from vmcp.events import (
    BlendShapeApplyEvent, BlendShapeEvent, BoneTransformEvent, RelativeTimeEvent, StateEvent,
)
from vmcp.typing import Bone, ModelState

VRM0_PRESETS = {
    "Neutral", "A", "I", "U", "E", "O", "Blink", "Joy", "Angry", "Sorrow", "Fun",
    "LookUp", "LookDown", "LookLeft", "LookRight", "Blink_L", "Blink_R",
}
BONES = ["Chest", "Neck", "Head"]


def unity_matrix(x, y, z, w):
    """Rotation matrix of a unit quaternion (the same numbers in Unity's left-handed frame)."""
    return [
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ]


def unity_euler_deg(m):
    """Unity's eulerAngles convention (R = Ry * Rx * Rz), as signed degrees."""
    ex = math.degrees(math.asin(max(-1.0, min(1.0, -m[1][2]))))
    ey = math.degrees(math.atan2(m[0][2], m[2][2]))
    ez = math.degrees(math.atan2(m[1][0], m[1][1]))
    return ex, ey, ez


def flatten(bundle):
    out = []
    for item in bundle:
        if isinstance(item, OscBundle):
            out.append(("nested", item))
        else:
            out.append(("message", item))
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--port", type=int, required=True)
    ap.add_argument("--bundles", type=int, default=120, help="stop after this many bundles")
    ap.add_argument("--timeout-s", type=float, default=60.0)
    ap.add_argument("--frame-rate-hz", type=float, default=120.0,
                    help="bundles per second of the time tags")
    ap.add_argument("--stream-rate-hz", type=float, default=None,
                    help="frames per second of the stream's /VMC/Ext/T times (default: "
                         "--frame-rate-hz; they differ when the sender paces faster than real "
                         "time)")
    ap.add_argument("--expect-head", default=None)
    ap.add_argument("--ready-file", default=None, help="written once the socket listens")
    args = ap.parse_args()

    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.bind(("127.0.0.1", args.port))
    sock.settimeout(0.5)
    if args.ready_file:
        with open(args.ready_file, "w") as f:
            f.write("ready\n")
    errors = []
    tags = []
    times = []
    heads = []
    blend_names = set()
    deadline = time.time() + args.timeout_s
    while len(tags) < args.bundles and time.time() < deadline:
        try:
            data, _ = sock.recvfrom(65536)
        except socket.timeout:
            continue
        if not OscBundle.dgram_is_bundle(data):
            errors.append("a datagram is not a bundle")
            continue
        bundle = OscBundle(data)
        tags.append(bundle.timestamp)
        items = flatten(bundle)
        if any(kind == "nested" for kind, _ in items):
            errors.append("a bundle holds a nested bundle: one bundle per frame expected")
            continue
        msgs = [m for _, m in items]
        bones, applies, states, frame_times = [], 0, 0, 0
        for i, m in enumerate(msgs):
            a = tuple(m.params)
            try:
                if m.address == BoneTransformEvent.ADDRESS_PATTERN:
                    ev = BoneTransformEvent.from_message_data("pneuma", m.address, a)
                    if len(a) != 8 or not all(isinstance(v, float) for v in a[1:]):
                        errors.append(f"bone arguments are not s+7f: {a}")
                    bones.append(ev)
                elif m.address == BlendShapeEvent.ADDRESS_PATTERN:
                    ev = BlendShapeEvent.from_message_data("pneuma", m.address, a)
                    blend_names.add(ev.key)
                    if not 0.0 <= ev.value <= 1.0:
                        errors.append(f"blendshape {ev.key} = {ev.value} outside 0..1")
                elif m.address == StateEvent.ADDRESS_PATTERN:
                    ev = StateEvent.from_message_data("pneuma", m.address, a)
                    states += 1
                    if ev.model_state != ModelState.LOADED:
                        errors.append(f"/VMC/Ext/OK says {ev.model_state}, not loaded")
                elif m.address == RelativeTimeEvent.ADDRESS_PATTERN:
                    ev = RelativeTimeEvent.from_message_data("pneuma", m.address, a)
                    frame_times += 1
                    times.append(ev.delta)
                elif m.address == BlendShapeApplyEvent.ADDRESS_PATTERN:
                    BlendShapeApplyEvent.from_message_data("pneuma", m.address, a)
                    applies += 1
                    if i != len(msgs) - 1:
                        errors.append("/VMC/Ext/Blend/Apply is not the last message")
                else:
                    errors.append(f"unexpected address {m.address}")
            except ValueError as e:
                errors.append(f"vmcp refused {m.address} {a}: {e}")
        if applies != 1:
            errors.append(f"{applies} /VMC/Ext/Blend/Apply in one bundle (1 expected)")
        if (states, frame_times) != (1, 1):
            errors.append(f"{states} /VMC/Ext/OK and {frame_times} /VMC/Ext/T in one bundle "
                          "(1 each expected)")
        names = [b.joint.value for b in bones]
        if names != BONES:
            errors.append(f"bones {names}, expected {BONES}")
        for b in bones:
            q = b.rotation
            norm = math.sqrt(q.x ** 2 + q.y ** 2 + q.z ** 2 + q.w ** 2)
            if abs(norm - 1.0) > 1e-3:
                errors.append(f"{b.joint.value} quaternion (x, y, z, w) not unit: {norm}")
            if b.joint == Bone.HEAD:
                heads.append(q)

    if len(tags) < args.bundles:
        errors.append(f"only {len(tags)} bundles arrived in {args.timeout_s} s")
    if "A" not in blend_names or "A" not in VRM0_PRESETS:
        errors.append(f"no VRM preset 'A' among the blendshapes {sorted(blend_names)}")
    for n in blend_names:
        if not n or not n.isascii() or " " in n:
            errors.append(f"blendshape name {n!r} is not a clip name")
    # Time tags: strictly increasing by one frame period.
    def secs(t):
        return t.seconds + t.fraction / 2 ** 32 if hasattr(t, "seconds") else float(t)
    steps = [secs(b) - secs(a) for a, b in zip(tags, tags[1:])]
    period = 1.0 / args.frame_rate_hz
    if steps:
        if min(steps) <= 0:
            errors.append("time tags repeat or go back: more than one bundle for a frame")
        median = sorted(steps)[len(steps) // 2]
        if abs(median - period) > 0.1 * period:
            errors.append(f"median time-tag step {median * 1000:.2f} ms, frame period "
                          f"{period * 1000:.2f} ms: not one bundle per frame")
    time_steps = [b - a for a, b in zip(times, times[1:])]
    frame_s = 1.0 / (args.stream_rate_hz or args.frame_rate_hz)
    if time_steps:
        median = sorted(time_steps)[len(time_steps) // 2]
        if min(time_steps) <= 0 or abs(median - frame_s) > 0.1 * frame_s:
            errors.append(f"/VMC/Ext/T steps {min(time_steps) * 1000:.2f} ms at least, median "
                          f"{median * 1000:.2f} ms: not one frame period ({frame_s * 1000:.2f} ms)")
    summary = {
        "bundles": len(tags),
        "blendshapes": sorted(blend_names),
        "median_step_ms": (sorted(steps)[len(steps) // 2] * 1000) if steps else None,
    }
    if args.expect_head and heads:
        pitch, yaw, roll = (float(v) for v in args.expect_head.split(","))
        q = heads[-1]
        m = unity_matrix(q.x, q.y, q.z, q.w)
        forward = (m[0][2], m[1][2], m[2][2])
        up = (m[0][1], m[1][1], m[2][1])
        euler = unity_euler_deg(m)
        summary["head_unity_euler_deg"] = euler
        summary["forward"] = forward
        if pitch and (forward[1] > 0) != (pitch > 0):
            errors.append(f"pitch {pitch}: forward {forward} should look {'up' if pitch > 0 else 'down'}")
        if yaw and (forward[0] < 0) != (yaw > 0):
            errors.append(f"yaw {yaw}: forward {forward} should turn to the avatar's "
                          f"{'left (-X)' if yaw > 0 else 'right (+X)'}")
        if roll and (up[0] < 0) != (roll > 0):
            errors.append(f"roll {roll}: up {up} should tilt to the avatar's "
                          f"{'left (-X)' if roll > 0 else 'right (+X)'}")
        for got, want, name in zip(euler, (-pitch, -yaw, roll), ("x", "y", "z")):
            if abs(got - want) > 0.05:
                errors.append(f"Unity euler {name} = {got:.3f}, expected {want:.3f}")
    summary["errors"] = errors[:20]
    print(json.dumps(summary))
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
