"""Speech baselines for `pneuma eval podcast`: Silero VAD (onnxruntime) and Praat's pitch (for
styletalk's reference voicing).

A worker: it reads one job per line on standard input,

    <job>\t<input.f32>\t<output.txt>

where <input.f32> is raw little-endian float32 mono audio at 16 kHz, writes its answer to
<output.txt> and answers one line on standard output: `ok` or `error: <why>`. It runs until
standard input closes, so the model loads once. Run with one argument (`silero IN OUT` or
`praat IN OUT` as three arguments) it does one job and exits.

- `silero`: the model `silero_vad_op18_ifless.onnx` of the PyPI package silero-vad (6.2.3,
  installed without dependencies: torch is not needed) in onnxruntime on one thread, 512-sample
  chunks (chunk i = samples [512 i, 512 i + 512), the last one padded with zeros) with the
  previous 64 samples in front and the state carried, as the package's OnnxWrapper does. One
  probability per line (9 significant digits).
- `praat`: Praat's autocorrelation pitch (parselmouth `to_pitch_ac`, time step 10 ms, floor
  75 Hz, ceiling 500 Hz, Praat's other defaults); `time_s,f0_hz` rows, 0 when unvoiced.

Install: `python3 -m venv target/venv-speech && target/venv-speech/bin/pip install
onnxruntime==1.32.0 numpy==2.4.6 praat-parselmouth==0.4.7 && target/venv-speech/bin/pip install
--no-deps silero-vad==6.2.3` (`.ci/run` does this).
"""

import sys

RATE = 16000
CHUNK = 512
CONTEXT = 64


def main() -> int:
    import numpy as np

    models = {}

    def silero(x):
        if "silero" not in models:
            import importlib.util
            import os

            import onnxruntime as ort

            # The package's folder, without importing it (its __init__ imports torch).
            package = importlib.util.find_spec("silero_vad").submodule_search_locations[0]
            path = os.path.join(package, "data", "silero_vad_op18_ifless.onnx")
            o = ort.SessionOptions()
            o.intra_op_num_threads = 1
            o.inter_op_num_threads = 1
            o.log_severity_level = 3
            models["silero"] = ort.InferenceSession(
                path, sess_options=o, providers=["CPUExecutionProvider"]
            )
        sess = models["silero"]
        n = (len(x) + CHUNK - 1) // CHUNK
        padded = np.zeros(n * CHUNK, np.float32)
        padded[: len(x)] = x
        state = np.zeros((2, 1, 128), np.float32)
        context = np.zeros(CONTEXT, np.float32)
        sr = np.array(RATE, dtype=np.int64)
        out = []
        for i in range(n):
            inp = np.concatenate([context, padded[i * CHUNK : (i + 1) * CHUNK]])[None, :]
            p, state = sess.run(None, {"input": inp, "state": state, "sr": sr})
            out.append(f"{float(p[0, 0]):.9g}")
            context = inp[0, -CONTEXT:]
        return "\n".join(out) + "\n"

    def praat(x):
        import parselmouth

        pitch = parselmouth.Sound(x.astype(np.float64), RATE).to_pitch_ac(
            time_step=0.01, pitch_floor=75.0, pitch_ceiling=500.0
        )
        f0 = pitch.selected_array["frequency"]
        return "".join(f"{t:.6f},{v:.3f}\n" for t, v in zip(pitch.xs(), f0))

    jobs = {"silero": silero, "praat": praat}

    def run(job, src, dst):
        if job not in jobs:
            raise ValueError(f"unknown job {job!r}: use silero or praat")
        x = np.fromfile(src, dtype="<f4")
        text = jobs[job](x)
        with open(dst, "w") as f:
            f.write(text)

    if len(sys.argv) == 4:
        run(*sys.argv[1:])
        return 0
    for line in sys.stdin:
        line = line.rstrip("\n")
        if not line:
            continue
        try:
            run(*line.split("\t"))
            print("ok", flush=True)
        except Exception as e:  # the eval reports it and stops
            print(f"error: {type(e).__name__}: {e}".replace("\n", " "), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
