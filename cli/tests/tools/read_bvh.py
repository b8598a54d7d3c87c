"""Reads a BVH file with the PyPI `bvh` package (an independent parser) and prints what the
tests check: `frames frame_time_s height`, the height being the Y offsets of the one chain
from the root to the head's end site added up; then the joint names.
Usage: python read_bvh.py FILE.bvh
"""
import sys

from bvh import Bvh

with open(sys.argv[1]) as f:
    mocap = Bvh(f.read())
height = sum(float(node.value[2]) for node in mocap.search("OFFSET"))
rows = mocap.frames
assert all(len(r) == len(rows[0]) for r in rows), "motion rows of different lengths"
print(mocap.nframes, mocap.frame_time, round(height, 6), len(rows))
print(" ".join(mocap.get_joints_names()))
