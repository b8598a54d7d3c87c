"""Reads a BVH file with the PyPI `bvh` package (an independent parser) and prints what the
tests check: `frames frame_time_s height rows`, the height being the root's Y position in the
first frame plus the Y offsets of the one chain from the root to the head's end site; then the
joint names.
Usage: python read_bvh.py FILE.bvh
"""
import sys

from bvh import Bvh

with open(sys.argv[1]) as f:
    mocap = Bvh(f.read())
root = mocap.get_joints_names()[0]
height = sum(float(node.value[2]) for node in mocap.search("OFFSET"))
height += float(mocap.frame_joint_channel(0, root, "Yposition"))
rows = mocap.frames
assert all(len(r) == len(rows[0]) for r in rows), "motion rows of different lengths"
print(mocap.nframes, mocap.frame_time, round(height, 6), len(rows))
print(" ".join(mocap.get_joints_names()))
