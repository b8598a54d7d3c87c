#!/usr/bin/env python3
"""Plays a 16-bit mono WAV into a JACK port and records another port, in one JACK client.

Used by the standalone's tests against a JACK dummy server: the example voice goes into
`pneuma:input_1` and `pneuma:output_1` is recorded (16-bit mono WAV at the server's rate; the
input must already be at that rate). Exits 1 with a message when a port is missing.
"""

import argparse
import array
import sys
import threading
import time
import wave

import jack


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--play", required=True)
    ap.add_argument("--record", required=True)
    ap.add_argument("--to", default="pneuma:input_1")
    ap.add_argument("--from-port", default="pneuma:output_1")
    ap.add_argument("--tail-s", type=float, default=1.0)
    args = ap.parse_args()

    with wave.open(args.play) as w:
        if w.getsampwidth() != 2 or w.getnchannels() != 1:
            sys.exit(f"{args.play}: a 16-bit mono WAV is needed")
        rate = w.getframerate()
        pcm = array.array("h", w.readframes(w.getnframes()))
    voice = [s / 32768.0 for s in pcm]

    client = jack.Client("pneuma_test_player", no_start_server=True)
    if client.samplerate != rate:
        sys.exit(f"the JACK server runs at {client.samplerate} Hz, the WAV is {rate} Hz")
    out_port = client.outports.register("voice")
    in_port = client.inports.register("capture")
    total = len(voice) + int(args.tail_s * rate)
    recorded = array.array("f")
    pos = [0]
    done = threading.Event()
    # Nothing plays or records until both connections stand (JACK runs the callback from
    # activation on): the voice starts at the app's input whole.
    connected = threading.Event()

    @client.set_process_callback
    def process(frames):
        if not connected.is_set():
            out_port.get_buffer()[:] = bytes(4 * frames)
            return
        start = pos[0]
        chunk = array.array("f", voice[start:start + frames])
        chunk.extend([0.0] * (frames - len(chunk)))
        out_port.get_buffer()[:] = chunk.tobytes()
        recorded.frombytes(bytes(in_port.get_buffer()))
        pos[0] = start + frames
        if pos[0] >= total:
            done.set()

    with client:
        # The app registers its ports before it activates its JACK client, and JACK refuses to
        # connect a client that is not active yet: retry for a while before giving up.
        connect_start = time.time()
        while True:
            try:
                if args.to not in [p.name for p in client.get_all_connections(out_port)]:
                    client.connect(out_port, args.to)
                if args.from_port not in [p.name for p in client.get_all_connections(in_port)]:
                    client.connect(args.from_port, in_port)
                break
            except jack.JackError as e:
                if time.time() - connect_start > 20:
                    sys.exit(f"cannot connect the test ports ({args.to}, {args.from_port}) within 20 s: {e}")
                time.sleep(0.1)
        print(f"connected after {time.time() - connect_start:.2f} s")
        connected.set()
        deadline = time.time() + total / rate * 3 + 10
        while not done.wait(0.2):
            if time.time() > deadline:
                sys.exit("the JACK server did not run the player in time")
    pcm = array.array("h", (max(-32767, min(32767, int(s * 32767))) for s in recorded[:total]))
    with wave.open(args.record, "wb") as w:
        w.setnchannels(1)
        w.setsampwidth(2)
        w.setframerate(rate)
        w.writeframes(pcm.tobytes())
    print(f"played {len(voice) / rate:.1f} s, recorded {len(pcm) / rate:.1f} s to {args.record}")


if __name__ == "__main__":
    main()
