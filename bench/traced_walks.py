#!/usr/bin/python3
"""Walks traced by hand on a library's map: the skating of `motionmap synth` along each take's
own map trajectory, drawn as a hand draws it, beside the captured take.

    PYTHONPATH=build/python /usr/bin/python3 bench/traced_walks.py \
        [--motionmap build/apps/cli/motionmap] [--data DIR]

The library is the Bandai Namco takes of ../shared/data/bandai but the proud walk (the take
bench/inbetween_lafan.py holds out): 11 takes of walks, runs, bows, a dash and a punch, mapped
together by isomap with the default options (`motionmap map --save`). For the old, tired and
feminine walks and the normal run, the take's own map points at its own timing are written as a
path four ways: exact; every point off by seeded noise (σ a quarter of the map's median step
per axis, as a hand traces); off by half a step varying over about a second (a steady hand); and
sketched, a point every third of a second (three a gait cycle: a stroke drawn through the
take's region rather than round each loop of its curve; linear between them). `motionmap synth
--map` makes each raw (`--no-clean-feet`) and cleaned (the default) and `motionmap info --skating
--json` measures it: the skating ratio and the ankles' mean speed in contact (docs/synthesis.md,
"Clean feet"). For the captures and the sketches, also how far the motion turns (the direction
the root travels over the last third of the motion against the first third's; the captured
takes walk straight) and, cleaned, how long a foot stays up at most (`a foot up`).
"""
import argparse
import glob
import json
import os
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
HELD_OUT = "dataset-1_walk_proud_001.bvh"
TRACED = ("walk_old", "walk_tired", "walk_feminine", "run_normal")


def run(cmd):
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(" ".join(cmd) + "\n" + out.stderr)
    return out.stdout


def skating(mm, bvh):
    return json.loads(run([mm, "info", bvh, "--skating", "--json"]))["skating"]


def cell(s):
    return "%.3f / %.0f" % (s["ratio"], s["contact_speed_cm_s"])


def turn_degrees(bvh):
    """How far the root's direction of travel over the last third of the motion turns from the
    first third's."""
    import motionmap
    clip = motionmap.load(bvh)
    joints = np.asarray(clip.positions())
    # The motion root: of the first joints, the one that travels (Bandai's joint_Root stands still).
    root = joints[:, max(range(3), key=lambda j: np.linalg.norm(joints[-1, j] - joints[0, j]))]
    third = len(root) // 3
    a, b = root[third] - root[0], root[-1] - root[-1 - third]
    return abs(np.degrees(np.arctan2(a[0] * b[2] - a[2] * b[0], a[0] * b[0] + a[2] * b[2])))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--motionmap", default=os.path.join(ROOT, "build/apps/cli/motionmap"))
    parser.add_argument("--data", default=os.path.join(ROOT, "..", "shared", "data"))
    args = parser.parse_args()
    mm = args.motionmap
    takes = sorted(f for f in glob.glob(os.path.join(args.data, "bandai", "*.bvh"))
                   if os.path.basename(f) != HELD_OUT)
    with tempfile.TemporaryDirectory() as work:
        lib = os.path.join(work, "lib.mmap.h5")
        csv = os.path.join(work, "lib.csv")
        run([mm, "map", *takes, "--save", lib, "-o", csv, "-q"])
        rows = np.array([[float(v) for v in line.split(",")] for line in open(csv)
                         if line[0].isdigit() or line[0] == "-"])
        clips = [rows[rows[:, 0] == c] for c in range(len(takes))]
        step = np.median(np.concatenate([np.linalg.norm(np.diff(c[:, 2:4], axis=0), axis=1)
                                         for c in clips]))
        print("| take | captured | traced exactly, raw / cleaned | by hand, raw / cleaned "
              "| by a steady hand, raw / cleaned | sketched, raw / cleaned |")
        print("|---|---|---|---|---|---|")
        for name in TRACED:
            c = next(i for i, t in enumerate(takes) if f"_{name}_" in os.path.basename(t))
            fps = json.loads(run([mm, "info", takes[c], "--json"]))["fps"]
            t = clips[c][:, 1] / fps
            p = clips[c][:, 2:4]
            random = np.random.default_rng(7)
            every = np.unique(np.r_[np.arange(0, len(t), round(fps / 3)), len(t) - 1])
            drawn = {"exact": (t, p),
                     "hand": (t, p + random.normal(0.0, 0.25 * step, p.shape)),
                     "steady": (t, p + 0.5 * step * np.c_[np.sin(5 * t), np.cos(3 * t)]),
                     "sketched": (t[every], p[every])}
            cells = [cell(skating(mm, takes[c])) + f", turns {turn_degrees(takes[c]):.0f}°"]
            for label, (times, q) in drawn.items():
                path = os.path.join(work, f"{name}_{label}.csv")
                np.savetxt(path, np.c_[times, q], delimiter=",", header="t,x,y", comments="")
                pair = []
                for clean in (["--no-clean-feet"], []):
                    out = os.path.join(work, f"{name}_{label}.bvh")
                    run([mm, "synth", "--map", lib, "--path", path, "-o", out, "-q", *clean])
                    measured = skating(mm, out)
                    pair.append(cell(measured))
                if label == "sketched":
                    pair[-1] += f", turns {turn_degrees(out):.0f}°, a foot up " \
                                f"{measured['longest_raised_s']:.2f} s"
                cells.append(" → ".join(pair))
            print(f"| {name} | " + " | ".join(cells) + " |")
        print("\n(skating ratio / ankle speed in contact, cm/s)")


if __name__ == "__main__":
    main()
