#!/usr/bin/env python3
"""Checks of the standalone's live tests (stdlib only).

- `breaths --input IN.wav --output OUT.wav`: the output holds inserted breaths: stretches of at
  least 100 ms where the input is silent (< -55 dBFS in 20 ms windows) and the output is not
  (> -55 dBFS); at least --min-breaths of them.
- `screenshot --ppm SHOT.ppm`: the screenshot is not blank (many colours), shows the timeline
  (its background colour) and inserted breaths in the breath colour of the editor's timeline
  (`BREATH_COLOUR`, 255 140 26).
"""

import argparse
import array
import json
import math
import sys
import wave

BREATH_RGB = (255, 140, 26)
TIMELINE_BG_RGB = (24, 26, 30)


def load(path):
    with wave.open(path) as w:
        if w.getsampwidth() != 2:
            sys.exit(f"{path}: 16-bit WAV expected")
        pcm = array.array("h", w.readframes(w.getnframes()))
        ch = w.getnchannels()
        return [pcm[i] / 32768.0 for i in range(0, len(pcm), ch)], w.getframerate()


def levels_db(x, win):
    out = []
    for i in range(0, len(x) - win + 1, win):
        e = sum(v * v for v in x[i:i + win]) / win
        out.append(10 * math.log10(e + 1e-20))
    return out


def breaths(args):
    x, rate = load(args.input)
    y, rate_y = load(args.output)
    if rate != rate_y:
        sys.exit(f"rates differ: {rate} vs {rate_y}")
    win = int(0.02 * rate)
    ex, ey = levels_db(x, win), levels_db(y, win)
    found, run = [], 0
    for i, (a, b) in enumerate(zip(ex, ey)):
        if a < -55 and b > -55:
            run += 1
            continue
        if run >= 5:
            found.append(round((i - run) * 0.02, 2))
        run = 0
    print(json.dumps({"breaths_at_s": found, "output_peak_db": round(max(ey), 1)}))
    if len(found) < args.min_breaths:
        print(f"only {len(found)} breaths in the output, {args.min_breaths} expected", file=sys.stderr)
        return 1
    return 0


def read_ppm(path):
    with open(path, "rb") as f:
        data = f.read()
    parts, pos = [], 0
    while len(parts) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.index(b"\n", pos)
            continue
        end = pos
        while not data[end:end + 1].isspace():
            end += 1
        parts.append(data[pos:end])
        pos = end
    if parts[0] != b"P6" or int(parts[3]) != 255:
        sys.exit(f"{path}: binary 8-bit PPM (P6) expected")
    w, h = int(parts[1]), int(parts[2])
    return w, h, data[pos + 1:pos + 1 + w * h * 3]


def near(px, rgb, tol):
    return all(abs(a - b) <= tol for a, b in zip(px, rgb))


def screenshot(args):
    w, h, pix = read_ppm(args.ppm)
    colours = set()
    breath = background = 0
    for i in range(0, len(pix), 3):
        px = (pix[i], pix[i + 1], pix[i + 2])
        colours.add(px)
        if near(px, BREATH_RGB, 8):
            breath += 1
        elif near(px, TIMELINE_BG_RGB, 2):
            background += 1
    total = w * h
    report = {"size": [w, h], "colours": len(colours), "breath_pixels": breath,
              "timeline_background_pixels": background}
    print(json.dumps(report))
    errors = []
    if len(colours) < 50:
        errors.append("the screenshot is blank or nearly so")
    if background < total * 0.05:
        errors.append("no timeline (its background colour covers < 5% of the screen)")
    if breath < args.min_breath_pixels:
        errors.append(f"{breath} pixels of the breath colour, {args.min_breath_pixels} expected")
    for e in errors:
        print(e, file=sys.stderr)
    return 1 if errors else 0


def main():
    ap = argparse.ArgumentParser()
    sub = ap.add_subparsers(dest="cmd", required=True)
    b = sub.add_parser("breaths")
    b.add_argument("--input", required=True)
    b.add_argument("--output", required=True)
    b.add_argument("--min-breaths", type=int, default=2)
    s = sub.add_parser("screenshot")
    s.add_argument("--ppm", required=True)
    s.add_argument("--min-breath-pixels", type=int, default=300)
    args = ap.parse_args()
    return breaths(args) if args.cmd == "breaths" else screenshot(args)


if __name__ == "__main__":
    sys.exit(main())
