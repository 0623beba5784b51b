#!/usr/bin/python3
"""In-betweens of random key pairs: how often they skate more than the keys' clips, and whether
they say why. The figures of docs/synthesis.md ("Key poses and in-betweening", free roots).

    /usr/bin/python3 bench/inbetween_pairs.py                       # 70 pairs, seed 1
    /usr/bin/python3 bench/inbetween_pairs.py --pairs 200 --seed 7 --motionmap build/apps/cli/motionmap

The 12 Bandai Namco takes of one performer (walks, runs, a dash, bows, a punch; captured in
different places) are mapped with the defaults and saved (`motionmap map --save`). For each pair
(seeded): two keys, each a random frame (5 frames away from its clip's ends) of a random take,
in-betweened untimed or with 15, 30 or 60 frames between (`motionmap inbetween --map`), with each
key's root where it stood in its clip (the default) and with `--free-roots`. `motionmap info
--skating --json` measures each result and each take: an in-between skates more than its keys'
clips when its skating ratio exceeds the larger of theirs by 0.02, or its ankles' mean speed in
contact theirs by 2 cm/s. Over a few frames the measure spreads far (half the takes' own windows
of 16 transitions skate more than their whole take by that rule), so each in-between is also
judged against its keys' clips over as many frames as it has, from the first key on in its clip
and up to the second key in its clip (a clip shorter than that: all of it), measured the same
way. Printed: per pair the figures, the notes it printed (glide: the keys stand further apart
than the clips walk in the time, or the clips carry the root elsewhere and it glides, or leave
the body facing away from the later key and it turns as it walks; step: the time given is out of
step with the keys' gait, the legs stepping over 1.5 times as fast or slow as the clips) and the
skating of the captured frames about its keys (as many as the free-roots in-between has), then
the counts, and how many in-betweens with a note skate no more than their clips, and the counts
per timing.
"""
import argparse
import json
import os
import random
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
TAKES = ["bow_normal", "bow_old", "dash_normal", "punch_normal", "run_angry", "run_normal",
         "run_old", "walk_angry", "walk_feminine", "walk_old", "walk_proud", "walk_tired"]


def run(cmd):
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit(" ".join(cmd) + "\n" + out.stderr)
    return out


def skating(mm, path):
    k = json.loads(run([mm, "info", path, "--skating", "--json"]).stdout)["skating"]
    return k["ratio"], k["contact_speed_cm_s"] or 0.0  # null: never in contact


def frames(mm, path):
    return json.loads(run([mm, "info", path, "--json"]).stdout)["frames"]


def bvh_frames(path):
    """A BVH file's lines up to its frame count, its frame time line and its frame lines."""
    lines = open(path).read().splitlines()
    at = next(i for i, line in enumerate(lines) if line.strip().startswith("Frame Time"))
    return lines[:at - 1], lines[at], [line for line in lines[at + 1:] if line.strip()]


def window(mm, bvh, first, count, out):
    """The skating of `count` frames of a clip from frame `first` (within the clip)."""
    head, frame_time, rows = bvh
    first = max(0, min(first, len(rows) - count))
    rows = rows[first:first + count]
    with open(out, "w") as f:
        f.write("\n".join(head + [f"Frames: {len(rows)}", frame_time] + rows) + "\n")
    return skating(mm, out)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--motionmap", default=os.path.join(ROOT, "build/apps/cli/motionmap"))
    parser.add_argument("--data", default=os.path.join(ROOT, "..", "shared", "data"))
    parser.add_argument("--pairs", type=int, default=70)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    mm = args.motionmap
    paths = {t: os.path.join(args.data, "bandai", f"dataset-1_{t}_001.bvh") for t in TAKES}
    missing = [p for p in paths.values() if not os.path.exists(p)]
    if missing:
        print(f"skipped: {missing[0]} is absent")
        return 77
    with tempfile.TemporaryDirectory() as tmp:
        lib = os.path.join(tmp, "lib.mmap.h5")
        run([mm, "map", *paths.values(), "--save", lib, "-o", os.path.join(tmp, "lib.csv"), "-q"])
        own = {t: skating(mm, p) for t, p in paths.items()}
        length = {t: frames(mm, p) for t, p in paths.items()}
        bvh = {t: bvh_frames(p) for t, p in paths.items()}
        rng = random.Random(args.seed)
        # Per kind (free roots or not): skating more with a note, without; not skating
        # more, with one.
        counts = {False: [0, 0, 0], True: [0, 0, 0]}
        # Per kind: skating more than the clips and than their frames about the keys.
        beyond = {False: 0, True: 0}
        # Per timing: pairs, and how many skate more with roots at every key and with free roots,
        # and with free roots than the clips' frames about the keys too.
        timings = {t: [0, 0, 0, 0] for t in ("untimed", 15, 30, 60)}
        print("| keys | frames between | clips' skating | skating, roots at every key (note) "
              "| skating, free roots (note) | captured frames about the keys |")
        print("|---|---|---|---|---|---|")
        for _ in range(args.pairs):
            a, b = rng.choice(TAKES), rng.choice(TAKES)
            fa, fb = rng.randrange(5, length[a] - 5), rng.randrange(5, length[b] - 5)
            between = rng.choice([None, 15, 30, 60])
            worst = (max(own[a][0], own[b][0]), max(own[a][1], own[b][1]))
            cells = []
            timing = timings["untimed" if between is None else between]
            timing[0] += 1
            for free in (False, True):
                out = os.path.join(tmp, "out.bvh")
                cmd = [mm, "inbetween", "--map", lib, "--keys",
                       f"{paths[a]}:{fa},{paths[b]}:{fb}", "-o", out, "-q"]
                if between is not None:
                    cmd += ["--frames-between", str(between)]
                if free:
                    cmd.append("--free-roots")
                notes = run(cmd).stderr
                glide = any(s in notes for s in ("apart (each where it stood", "glides that in",
                                                 "turns that in"))
                step = "out of step" in notes
                ratio, speed = skating(mm, out)
                more = ratio > worst[0] + 0.02 or speed > worst[1] + 2.0
                # The keys' clips over as many frames as the in-between has, after the first key
                # and up to the second.
                n = frames(mm, out)
                near = [window(mm, bvh[a], fa, n, os.path.join(tmp, "a.bvh")),
                        window(mm, bvh[b], fb - n + 1, n, os.path.join(tmp, "b.bvh"))]
                local = (max(worst[0], *(r for r, _ in near)), max(worst[1], *(v for _, v in near)))
                if ratio > local[0] + 0.02 or speed > local[1] + 2.0:
                    beyond[free] += 1
                    timing[3] += free
                if more:
                    counts[free][0 if glide or step else 1] += 1
                    timing[2 if free else 1] += 1
                elif glide or step:
                    counts[free][2] += 1
                cells.append(f"{ratio:.3f}, {speed:.0f} cm/s{' more' if more else ''}"
                             f"{' (glide)' if glide else ''}{' (step)' if step else ''}")
            cells.append(", ".join(f"{r:.3f} {v:.0f} cm/s" for r, v in near))
            print(f"| {a}:{fa} → {b}:{fb} | {'untimed' if between is None else between} "
                  f"| {worst[0]:.3f}, {worst[1]:.0f} cm/s | {' | '.join(cells)} |")
        for free in (False, True):
            noted, silent, spared = counts[free]
            print(f"{'free roots' if free else 'roots at every key'}: {noted + silent} of "
                  f"{args.pairs} skate more than their keys' clips, {noted} of them with a note, "
                  f"{silent} without; {spared} with a note skate no more; "
                  f"{beyond[free]} skate more than the clips' frames about their keys too")
        print("skating more by timing (roots at every key, free roots, and in brackets free roots "
              "than the clips' frames about the keys too): " + "; ".join(
                  f"{t if t == 'untimed' else f'{t} frames between'} {more} and {free} ({near}) "
                  f"of {n}" for t, (n, more, free, near) in timings.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
