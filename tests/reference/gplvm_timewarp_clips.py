#!/usr/bin/python3
"""Longer inputs for the sparse GP-LVM's timing (docs/methods/gplvm.md): the Bandai walks
(../shared/data/bandai/dataset-1_walk_*.bvh, 1 283 frames in all) time-warped, each resampled to
`stretch` times its frame count by linear interpolation of its channels (rotations along the
shorter way round), one file per clip and stretch, written to OUT.

    /usr/bin/python3 tests/reference/gplvm_timewarp_clips.py OUT STRETCH...

e.g. `... /tmp/warp2k 0.7 0.85` (about 2 000 frames) or
`... /tmp/warp10k 0.6 0.8 1.0 1.2 1.4 1.6 1.8` (about 10 300). Not used by the tests.
"""
import glob
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.path.join(HERE, "..", "..", "..", "shared", "data", "bandai")


def read(path):
    with open(path) as f:
        text = f.read()
    head, motion = text.split("MOTION", 1)
    lines = motion.strip().splitlines()
    frame_time = lines[1]
    values = np.array([[float(v) for v in line.split()] for line in lines[2:] if line.strip()])
    # Rotation channels: the header's channel names, in order.
    channels = []
    for line in head.splitlines():
        words = line.split()
        if words and words[0] == "CHANNELS":
            channels += words[2:]
    rotation = np.array(["rotation" in c for c in channels])
    return head, frame_time, values, rotation


def warp(values, rotation, stretch):
    n = values.shape[0]
    m = max(2, int(round(n * stretch)))
    u = np.linspace(0, n - 1, m)
    i0 = np.minimum(np.floor(u).astype(int), n - 2)
    w = (u - i0)[:, None]
    a, b = values[i0], values[i0 + 1]
    d = b - a
    d[:, rotation] = (d[:, rotation] + 180.0) % 360.0 - 180.0
    return a + w * d


def main():
    out = sys.argv[1]
    stretches = [float(s) for s in sys.argv[2:]]
    os.makedirs(out, exist_ok=True)
    total = 0
    for path in sorted(glob.glob(os.path.join(DATA, "dataset-1_walk_*.bvh"))):
        head, frame_time, values, rotation = read(path)
        for s in stretches:
            v = warp(values, rotation, s)
            total += v.shape[0]
            name = os.path.basename(path)[:-4] + "_x%.2f.bvh" % s
            with open(os.path.join(out, name), "w") as f:
                f.write(head + "MOTION\nFrames: %d\n%s\n" % (v.shape[0], frame_time))
                for row in v:
                    f.write(" ".join("%.6f" % x for x in row) + "\n")
    print(total, "frames")


if __name__ == "__main__":
    main()
