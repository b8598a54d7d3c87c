"""Reads a Standard MIDI File with mido (an independent reader) and prints what the tests check.

First line: `type ticks_per_beat tempo_us tracks`; then one line per control change:
`time_s channel controller value`, times in seconds through the file's own tempo map.
Usage: python read_midi.py FILE.mid
"""
import sys

import mido

mid = mido.MidiFile(sys.argv[1])
tempo = next(
    (m.tempo for t in mid.tracks for m in t if m.type == "set_tempo"), -1
)
print(mid.type, mid.ticks_per_beat, tempo, len(mid.tracks))
now = 0.0
for msg in mid:  # merged tracks, msg.time = seconds since the previous message
    now += msg.time
    if msg.type == "control_change":
        print(f"{now:.6f} {msg.channel} {msg.control} {msg.value}")
