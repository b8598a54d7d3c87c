#!/usr/bin/env python3
"""A lookahead change in the middle of an offline export, under pedalboard (which processes
offline): is the bounce the same on every run, and where does the new engine take over?

Usage:
    python tests/vst3/offline_export.py --vst3 target/bundled/Pneuma.vst3 \
        --voice assets/examples/voice.wav [--runs 5] [--chunk-s 2.5] [--block 512]

The voice (its first 15 s, repeated to 48 kHz) goes through the plugin in chunks of --chunk-s
seconds (`reset=False` after the first, pedalboard cutting each into blocks of --block samples);
`lookahead_s` goes from 0.5 to 1.0 s before the chunk at 7.5 s. Each run is compared with the
first and with an export without the change. Exits 1 when the runs differ.
"""

import argparse
import sys

import numpy as np
import pedalboard
from pedalboard.io import AudioFile

CHANGE_S = 7.5


def export(path, audio, rate, chunk_s, block, lookahead_s):
    """The plugin's output for `audio`, `lookahead_s` set before the chunk at CHANGE_S."""
    plugin = pedalboard.load_plugin(path)
    chunk = int(rate * chunk_s)
    out = []
    for i, start in enumerate(range(0, audio.shape[1], chunk)):
        if start == int(rate * CHANGE_S):
            plugin.lookahead_s = lookahead_s
        piece = audio[:, start : start + chunk]
        out.append(plugin.process(piece, rate, buffer_size=block, reset=(i == 0)))
    return np.concatenate(out, axis=1)


def first_difference_s(out, ref, rate):
    """The first output time where `out` leaves `ref`, seconds (None: nowhere)."""
    n = min(out.shape[1], ref.shape[1])
    diff = np.nonzero(np.any(out[:, :n] != ref[:, :n], axis=0))[0]
    return diff[0] / rate if len(diff) else None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--vst3", required=True)
    ap.add_argument("--voice", required=True)
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--chunk-s", type=float, default=2.5)
    ap.add_argument("--block", type=int, default=512)
    args = ap.parse_args()

    with AudioFile(args.voice) as f:
        audio = f.read(f.frames).astype(np.float32)
        rate = f.samplerate
    audio = np.repeat(audio[:, : int(rate * 15)], 3, axis=1)
    rate *= 3

    def run(lookahead_s):
        return export(args.vst3, audio, rate, args.chunk_s, args.block, lookahead_s)

    unchanged = run(0.5)
    runs = [run(1.0) for _ in range(args.runs)]
    for k, r in enumerate(runs):
        print(
            f"run {k}: the change shows from {first_difference_s(r, unchanged, rate)} s; "
            f"same as run 0: {np.array_equal(r, runs[0])}"
        )
    same = all(np.array_equal(r, runs[0]) for r in runs)
    print("all runs identical:", same)
    sys.exit(0 if same else 1)


if __name__ == "__main__":
    main()
