#!/usr/bin/python3
"""Key poses and the route between them on a map: docs/keys.png.

    /usr/bin/python3 bench/keys_figure.py                   # writes docs/keys.png
    /usr/bin/python3 bench/keys_figure.py --png /tmp/keys.png --motionmap build/apps/cli/motionmap

The CMU golf swings 64_08 and 64_09 are mapped together (isomap, the default); `motionmap
inbetween` makes a motion from frame 60 of 64_08 (the address) through frame 250 of 64_09 to frame
330 of 64_08, 60 frames between keys, and writes the map point of every frame (`--route-csv`). The
picture shows the swings' trajectories, the valid region (within the blender's reach of a frame:
synth::reach_radius, 3 median steps or 5 % of the map's size), the route and the keys.
"""
import argparse
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


def run(cmd):
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(" ".join(cmd) + "\n" + out.stderr)
    return out.stdout + out.stderr


def numbers(path):
    return np.array([[float(v) for v in line.split(",")] for line in open(path)
                     if line[0].isdigit() or line[0] == "-"])


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--motionmap", default=os.path.join(ROOT, "build/apps/cli/motionmap"))
    parser.add_argument("--data", default=os.path.join(ROOT, "..", "shared", "data"))
    parser.add_argument("--png", default=os.path.join(ROOT, "docs", "keys.png"))
    args = parser.parse_args()
    cmu = os.path.join(args.data, "cmu")
    files = [os.path.join(cmu, "64_08.bvh"), os.path.join(cmu, "64_09.bvh")]
    keys = f"{files[0]}:60,{files[1]}:250,{files[0]}:330"
    mm = args.motionmap
    with tempfile.TemporaryDirectory() as work:
        csv, route_csv = os.path.join(work, "map.csv"), os.path.join(work, "route.csv")
        run([mm, "map", *files, "-o", csv, "-q"])
        said = run([mm, "inbetween", *files, "--keys", keys, "--frames-between", "60",
                    "-o", os.path.join(work, "inbetween.bvh"), "--route-csv", route_csv, "-q"])
        rows, route = numbers(csv), numbers(route_csv)
    print(said.strip())

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7.5, 4.6))
    points = rows[:, 2:4]
    # The valid region: synth::reach_radius over the map (docs/synthesis.md, "Outside the data").
    steps = [np.linalg.norm(points[i + 1] - points[i]) for i in range(len(points) - 1)
             if rows[i, 0] == rows[i + 1, 0]]
    steps = sorted(s for s in steps if s > 0)
    size = (points.max(axis=0) - points.min(axis=0)).max()
    reach = max(3 * steps[len(steps) // 2], 0.05 * size)
    lo, hi = points.min(axis=0) - reach, points.max(axis=0) + reach
    gx, gy = np.meshgrid(np.linspace(lo[0], hi[0], 300), np.linspace(lo[1], hi[1], 200))
    grid = np.stack([gx.ravel(), gy.ravel()], axis=1)
    nearest = np.full(len(grid), np.inf)
    for p in points:
        nearest = np.minimum(nearest, np.hypot(grid[:, 0] - p[0], grid[:, 1] - p[1]))
    ax.contourf(gx, gy, (nearest <= reach).reshape(gx.shape), levels=[0.5, 1.5],
                colors=["#c8ebd2"])
    for c, (name, colour) in enumerate((("64_08", "tab:green"), ("64_09", "tab:purple"))):
        xy = rows[rows[:, 0] == c][:, 2:4]
        ax.plot(xy[:, 0], xy[:, 1], color=colour, lw=1.0, alpha=0.8, label=name)
    ax.plot([], [], color="#c8ebd2", lw=8, label="valid: within reach of a frame")
    ax.plot(route[:, 1], route[:, 2], color="tab:orange", lw=2.5, label="the in-between's route")
    for k, frame in enumerate((0, 61, 122)):
        x, y = route[frame, 1], route[frame, 2]
        ax.plot(x, y, "o", ms=16, mfc="white", mec="saddlebrown", mew=1.5)
        ax.annotate(str(k + 1), (x, y), ha="center", va="center", fontsize=10, weight="bold",
                    color="saddlebrown")
    ax.set_title("Key poses (1–3: frames of two golf swings) and the route between them",
                 fontsize=10)
    ax.set_xticks([])
    ax.set_yticks([])
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    fig.savefig(args.png, dpi=110)
    print(f"wrote {args.png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
