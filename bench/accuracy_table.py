#!/usr/bin/env python3
"""Accuracy of the points path against the dense one (issue 11): the same library maps both ways.

For each size, makes (or reuses, as bench/scale_table.py does) a seeded synthetic library with
motionmap-make-library, then for each method runs

    motionmap map LIBRARY/clip_*.bvh -m METHOD --exact        -o exact.csv  -q   (dense path)
    motionmap map LIBRARY/clip_*.bvh -m METHOD --landmarks 0  -o points.csv -q   (points path)

and compares the two maps: the Procrustes disparity (scipy.spatial.procrustes: both centred,
scaled to unit norm, the second rotated, reflected and scaled onto the first; 0 = the same shape),
and trustworthiness and continuity (k = 10, the tool's --metrics default) of each map, computed
here the same way for both on one seeded random sample of frames (sklearn.manifold.
trustworthiness on the points the maps were made from, written by motionmap-points;
continuity = trustworthiness with the roles of the spaces swapped), with their change. The
tool's own --metrics uses every frame on the dense path and a 2000-frame sample on the points
path, so its two numbers would not compare.

    /usr/bin/python3 bench/accuracy_table.py                       # sizes 10000 20000
    /usr/bin/python3 bench/accuracy_table.py --sizes 10000 --methods le lle

The dense path at 20 000 frames holds D (3.2 GB; Isomap 6.4 GB with its geodesic matrix).
"""
import argparse
import datetime
import os
import re
import subprocess
import sys
import tempfile
import time

import numpy as np
from scipy.spatial import procrustes
from sklearn.manifold import trustworthiness

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
METHODS = ["mds", "isomap", "le", "lle"]


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog="See bench/README.md.")
    p.add_argument("--sizes", type=int, nargs="+", default=[10000, 20000],
                   help="library sizes in frames (default: 10000 20000)")
    p.add_argument("--methods", nargs="+", default=METHODS, choices=METHODS + ["pca", "svd"],
                   help="methods (default: mds isomap le lle; pca and svd read X on both paths)")
    p.add_argument("--sample", type=int, default=2000,
                   help="frames trustworthiness and continuity are measured on (default 2000)")
    p.add_argument("--k", type=int, default=10,
                   help="neighbours of trustworthiness and continuity (default 10)")
    p.add_argument("--seed", type=int, default=1, help="library seed (default 1)")
    p.add_argument("--clip-frames", type=int, default=6000,
                   help="frames per library file (default 6000, as scale_table.py)")
    p.add_argument("--library-dir", default=os.path.join(tempfile.gettempdir(),
                                                         "motionmap-scale-libraries"),
                   help="where libraries are made and kept (default: %(default)s, shared with "
                        "scale_table.py)")
    p.add_argument("--build", default=os.path.join(ROOT, "build"),
                   help="the build folder (default: build/)")
    return p.parse_args()


def load_average():
    out = subprocess.run(["uptime"], capture_output=True, text=True).stdout
    m = re.search(r"load average:\s*(.+)$", out.strip())
    return m.group(1) if m else ", ".join(f"{x:.2f}" for x in os.getloadavg())


def library(args, frames):
    """The library of `frames` frames (as scale_table.py names and checks it)."""
    folder = os.path.join(args.library_dir,
                          f"frames{frames}-clip{args.clip_frames}-seed{args.seed}")
    manifest = os.path.join(folder, "manifest.txt")
    want = f"frames={frames} clip_frames={args.clip_frames} seed={args.seed} "
    if os.path.exists(manifest):
        with open(manifest) as f:
            if want in f.readline():
                return folder
    generator = os.path.join(args.build, "bench", "library", "motionmap-make-library")
    subprocess.run([generator, "--frames", str(frames), "--clip-frames", str(args.clip_frames),
                    "--seed", str(args.seed), "--out", folder, "--force", "-q"], check=True,
                   capture_output=True)
    return folder


def clips_of(folder):
    return sorted(os.path.join(folder, f) for f in os.listdir(folder)
                  if f.startswith("clip_") and f.endswith(".bvh"))


def points_of(args, clips, work):
    """The points the maps are made from (#frames by #values), via motionmap-points."""
    path = os.path.join(work, "points.f64")
    subprocess.run([os.path.join(args.build, "bench", "library", "motionmap-points"), path]
                   + clips, check=True, capture_output=True)
    with open(path, "rb") as f:
        rows, cols = (int(v) for v in f.readline().split())
        return np.frombuffer(f.read(), dtype="<f8").reshape(rows, cols)


def map_of(args, clips, method, path_option, out):
    """Runs one map; returns (coordinates #frames by 2, wall seconds)."""
    cli = os.path.join(args.build, "apps", "cli", "motionmap")
    start = time.monotonic()
    p = subprocess.run([cli, "map", *clips, "-m", method, *path_option, "-o", out, "-q"],
                       capture_output=True, text=True)
    wall = time.monotonic() - start
    if p.returncode != 0:
        sys.exit(f"accuracy_table: {method} {' '.join(path_option)} failed: {p.stderr.strip()}")
    rows = [line.split(",") for line in open(out) if line[0].isdigit() or line[0] == "-"]
    return np.array([[float(r[-2]), float(r[-1])] for r in rows]), wall


def quality(P, Y, k):
    """(trustworthiness, continuity) of map Y of points P (the same rows)."""
    return trustworthiness(P, Y, n_neighbors=k), trustworthiness(Y, P, n_neighbors=k)


def main():
    args = parse_args()
    started = datetime.datetime.now().astimezone()
    print(f"{started:%Y-%m-%d %H:%M %Z} · load average {load_average()} · nproc "
          f"{os.cpu_count()} · trustworthiness/continuity k = {args.k} on {args.sample} frames "
          f"(seeded), the same for both maps", file=sys.stderr)
    print("| frames | method | dense s | points s | Procrustes disparity | trustworthiness "
          "dense → points (Δ) | continuity dense → points (Δ) |")
    print("|---:|---|---:|---:|---:|---|---|")
    with tempfile.TemporaryDirectory(prefix="motionmap-accuracy-") as work:
        for frames in args.sizes:
            clips = clips_of(library(args, frames))
            P = points_of(args, clips, work)
            rng = np.random.default_rng(20061127)
            sample = np.sort(rng.choice(len(P), size=min(args.sample, len(P)), replace=False))
            for method in args.methods:
                exact, t_exact = map_of(args, clips, method, ["--exact"],
                                        os.path.join(work, "exact.csv"))
                points, t_points = map_of(args, clips, method, ["--landmarks", "0"],
                                          os.path.join(work, "points.csv"))
                if len(exact) != len(P) or len(points) != len(P):
                    sys.exit(f"accuracy_table: {method}: {len(exact)} and {len(points)} map rows "
                             f"for {len(P)} frames")
                disparity = procrustes(exact, points)[2]
                te, ce = quality(P[sample], exact[sample], args.k)
                tp, cp = quality(P[sample], points[sample], args.k)
                print(f"| {frames} | {method} | {t_exact:.2f} | {t_points:.2f} | {disparity:.2e} "
                      f"| {te:.4f} → {tp:.4f} ({tp - te:+.4f}) "
                      f"| {ce:.4f} → {cp:.4f} ({cp - ce:+.4f}) |", flush=True)
    print(f"load average at the end: {load_average()}", file=sys.stderr)


if __name__ == "__main__":
    main()
