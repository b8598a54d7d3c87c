#!/usr/bin/env python3
"""Mic-to-pose latency of pneuma-app: from a sound entering its JACK input to the first OSC
bundle that shows it arriving on UDP (input block + analysis + send).

A JACK client plays tone bursts (200 Hz, -12 dBFS, 0.5 s, after 1.5 s of silence) into
`pneuma:input_1`; it notes the monotonic time at the start of the JACK cycle that carries each
burst's first sample (plus that sample's offset in the cycle). A UDP thread receives the app's
`/pneuma` bundles and notes when the first bundle with `/pneuma/rms` above -40 dBFS arrives
after each onset. Start the app first with `--osc-format pneuma --osc-port PORT` on the same
JACK server. Prints each latency and the median and maximum, in ms.
"""

import argparse
import array
import math
import socket
import statistics
import sys
import threading
import time

import jack
from pythonosc.osc_bundle import OscBundle


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--port", type=int, required=True)
    ap.add_argument("--bursts", type=int, default=10)
    ap.add_argument("--to", default="pneuma:input_1")
    args = ap.parse_args()

    arrivals = []  # (monotonic time, rms dB)
    stop = threading.Event()
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    sock.bind(("127.0.0.1", args.port))
    sock.settimeout(0.2)

    def receive():
        while not stop.is_set():
            try:
                data, _ = sock.recvfrom(65536)
            except socket.timeout:
                continue
            now = time.monotonic()
            if not OscBundle.dgram_is_bundle(data):
                continue
            for m in OscBundle(data):
                if getattr(m, "address", "") == "/pneuma/rms":
                    arrivals.append((now, m.params[0]))

    rx = threading.Thread(target=receive, daemon=True)
    rx.start()

    client = jack.Client("pneuma_latency", no_start_server=True)
    rate = client.samplerate
    period = client.blocksize
    silence, burst = int(1.5 * rate), int(0.5 * rate)
    cycle = silence + burst
    total = cycle * args.bursts
    pos = [0]
    onsets = []
    port = client.outports.register("bursts")
    amp = 10 ** (-12 / 20)

    @client.set_process_callback
    def process(frames):
        t_cycle = time.monotonic()
        start = pos[0]
        out = array.array("f", [0.0] * frames)
        for i in range(frames):
            n = start + i
            k = n % cycle
            if n < total and k >= silence:
                out[i] = amp * math.sin(2 * math.pi * 200 * (k - silence) / rate)
                if k == silence:
                    onsets.append(t_cycle + i / rate)
        port.get_buffer()[:] = out.tobytes()
        pos[0] = start + frames

    with client:
        client.connect(port, args.to)
        time.sleep(total / rate + 1.0)
    stop.set()
    rx.join()

    latencies = []
    for t0 in onsets:
        hit = next((t for t, rms in arrivals if t >= t0 and rms > -40), None)
        if hit is not None and hit - t0 < 0.5:
            latencies.append((hit - t0) * 1000)
    if not latencies:
        sys.exit("no bundle showed the bursts: is the app running with --osc-format pneuma "
                 f"--osc-port {args.port} on this JACK server?")
    print(f"JACK {rate} Hz, period {period} samples ({period / rate * 1000:.1f} ms)")
    print("latencies ms:", " ".join(f"{v:.1f}" for v in latencies))
    print(f"mic-to-pose latency: median {statistics.median(latencies):.1f} ms, "
          f"max {max(latencies):.1f} ms over {len(latencies)} onsets")


if __name__ == "__main__":
    main()
