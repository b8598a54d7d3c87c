"""Pitch baselines for `cargo xtask eval-pitch`: swift-f0 (ONNX CNN) and pYIN (librosa).

A worker: it reads one job per line on standard input,

    <tracker>\t<input.wav>\t<output.csv>\t<frame period, seconds>

with <tracker> `swift-f0` or `pyin`, writes `time_s,f0_hz` rows (0 for unvoiced frames, each
frame at its own time) to <output.csv>, and answers one line on standard output: `ok` or
`error: <why>`. It runs until standard input closes, so the models load once.

- swift-f0: as shipped (`SwiftF0().detect`, its own 16 ms frames, voiced when its confidence is
  at least 0.5, 46.875–2093.75 Hz); the frame period is not used.
- pYIN: `librosa.pyin` on the audio resampled to 16 kHz, 50–600 Hz (Praat's range in the eval),
  frames of 1024 samples (64 ms) centred on multiples of the frame period rounded to whole
  samples; its own voicing decision.

Install: `python3 -m venv V && V/bin/pip install swift-f0==0.3.0 soundfile==0.14.0 soxr==1.1.0 librosa==0.11.0` (librosa only for pYIN).
"""

import sys


def main() -> int:
    import numpy as np
    import soundfile as sf

    trackers = {}

    def swift(audio, rate, _period):
        if "swift" not in trackers:
            from swift_f0 import SwiftF0

            trackers["swift"] = SwiftF0(threads=1, spin=False)
        r = trackers["swift"].detect(audio, sample_rate=rate)
        voiced = np.asarray(r.confidence) >= 0.5
        return np.asarray(r.timestamps), np.where(voiced, np.asarray(r.pitch_hz), 0.0)

    def pyin(audio, rate, period):
        import librosa

        sr = 16000
        y = librosa.resample(audio, orig_sr=rate, target_sr=sr) if rate != sr else audio
        hop = max(1, round(period * sr))
        f0, voiced, _ = librosa.pyin(
            y, fmin=50.0, fmax=600.0, sr=sr, frame_length=1024, hop_length=hop, center=True
        )
        times = np.arange(len(f0)) * hop / sr
        return times, np.where(voiced & np.isfinite(f0), f0, 0.0)

    run = {"swift-f0": swift, "pyin": pyin}
    for line in sys.stdin:
        line = line.rstrip("\n")
        if not line:
            continue
        try:
            tracker, wav, out, period = line.split("\t")
            if tracker not in run:
                raise ValueError(f"unknown tracker {tracker!r}: use swift-f0 or pyin")
            audio, rate = sf.read(wav, dtype="float32", always_2d=True)
            times, f0 = run[tracker](audio.mean(axis=1), rate, float(period))
            with open(out, "w") as f:
                for t, v in zip(times, f0):
                    f.write(f"{t:.6f},{v:.3f}\n")
            print("ok", flush=True)
        except Exception as e:  # the eval reports it and goes on without this tracker
            print(f"error: {type(e).__name__}: {e}".replace("\n", " "), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
