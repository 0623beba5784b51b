#!/usr/bin/env python3
"""Maps of a labelled library (issue 24, "A map that keeps a library apart"): time, peak memory
and label accuracy of every method, of umap-learn and of the feature space itself.

Makes (or reuses) a seeded synthetic library from the 12 Bandai takes of ../shared/data/bandai
with motionmap-make-library (time-warped, mirrored, noised segments; bench/README.md), and labels
every frame with the action and style of the take its segment was cut from, read from the
take's file name `dataset-1_{action}_{style}_{take}.bvh` through the library's manifest; the
labels are written as per-frame intervals `clip,start,end,action,style` (end exclusive) to
LIBRARY-labels.csv beside the library. Then:

  * for each method, `motionmap map LIBRARY/clip_*.bvh -m METHOD -o MAP.csv -q --verbose` in a
    fresh child (the tool's defaults for large inputs: the points path, landmarks for mds and
    isomap, a 100 000-frame sample for le and lle; umap on every frame), its wall time and peak
    resident memory (the child's own ru_maxrss, from wait4);
  * umap-learn (Debian's python3-umap) in a fresh child on the same points MotionMap's maps are
    made from (the heading-local point clouds, written by motionmap-points; Euclidean distances of
    those rows are MotionMap's pose distance D), with the same n_neighbors (15, the frame itself
    counted, as both count it), min_dist 0.1, 2 components, n_jobs=-1 (all cores; umap-learn runs
    its layout on one thread when given a random_state, so it gets none); its time is the whole
    child (import, numba compilation, nearest-neighbour descent, spectral start, layout), with
    the fit alone beside it;
  * the label accuracy of each map and of the points: for a seeded sample of query frames
    (--queries, default 5000), the 10 nearest frames *of other clips* (scikit-learn's exact
    NearestNeighbors, Euclidean) vote on the query's label, ties going to the label whose voter
    is nearest; the fraction of right votes, for the action and for the take (action and style).

Prints a header (date, load average, machine), the Markdown table and the load at the end.

    /usr/bin/python3 bench/library_labels_table.py                    # 300 000 frames, all
    /usr/bin/python3 bench/library_labels_table.py --frames 30000 --methods pca umap
"""
import argparse
import datetime
import glob
import os
import re
import subprocess
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from peer_blas import GET_OPENBLAS, openblas_dir, openblas_env, peer_blas  # noqa: E402
from scale_table import run_measured  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
METHODS = ["pca", "svd", "mds", "isomap", "le", "lle", "umap"]
NAME = re.compile(r"dataset-1_(?P<action>[a-z]+)_(?P<style>[a-z]+)_(?P<take>\d+)")


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter,
                                epilog="See bench/README.md.")
    p.add_argument("--frames", type=int, default=300000, help="library frames (default 300000)")
    p.add_argument("--clip-frames", type=int, default=150,
                   help="frames per library clip (default 150: ~2 000 clips at 300 000 frames, "
                        "about the clip length of the 2 902-clip library of issue 24)")
    p.add_argument("--seed", type=int, default=1, help="library seed (default 1)")
    p.add_argument("--methods", nargs="+", default=METHODS, choices=METHODS)
    p.add_argument("--no-umap-learn", action="store_true", help="leave umap-learn out")
    p.add_argument("--openblas", metavar="DIR",
                   help="umap-learn's BLAS: OpenBLAS from DIR (default: bench/peer_blas.py's "
                        "OPENBLAS_DIRS); 'system': the system's BLAS")
    p.add_argument("--k", type=int, default=15, help="umap's n_neighbors for both (default 15)")
    p.add_argument("--queries", type=int, default=5000, help="query frames (default 5000)")
    p.add_argument("--voters", type=int, default=10, help="neighbours that vote (default 10)")
    p.add_argument("--timeout", type=float, default=1800, help="seconds per run (default 1800)")
    p.add_argument("--source", default=os.path.join(ROOT, "..", "shared", "data", "bandai"),
                   help="the labelled takes (default ../shared/data/bandai)")
    p.add_argument("--library-dir", default=os.path.join(tempfile.gettempdir(),
                                                         "motionmap-label-libraries"),
                   help="where libraries are made and kept (default: %(default)s)")
    p.add_argument("--build", default=os.path.join(ROOT, "build"),
                   help="build folder (default: build)")
    p.add_argument("--keep", help="folder to keep the maps (CSV) and points in")
    p.add_argument("--umap-learn-result", nargs=2, metavar=("NPY", "TIME_LOG"),
                   help="instead of running umap-learn, take its map from NPY (written by this "
                        "script's umap-learn child on the same points) and its figures from "
                        "TIME_LOG, the child's stderr under /usr/bin/time -f '%%e s wall %%U user "
                        "%%S sys %%M KB'")
    p.add_argument("--umap-learn-child", nargs=3, metavar=("POINTS", "OUT", "K"),
                   help=argparse.SUPPRESS)
    return p.parse_args()


def load_average():
    with open("/proc/loadavg") as f:
        return ", ".join(f.read().split()[:3])


def library(args):
    """The library's folder, made unless one with the same options is there."""
    name = f"bandai-frames{args.frames}-clip{args.clip_frames}-seed{args.seed}"
    folder = os.path.join(args.library_dir, name)
    manifest = os.path.join(folder, "manifest.txt")
    want = f"frames={args.frames} clip_frames={args.clip_frames} seed={args.seed} "
    if os.path.exists(manifest):
        with open(manifest) as f:
            if want in f.readline():
                return folder
    cmd = [os.path.join(args.build, "bench", "library", "motionmap-make-library"),
           "--frames", str(args.frames), "--clip-frames", str(args.clip_frames),
           "--seed", str(args.seed), "--source", args.source, "--out", folder, "--force", "-q"]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"library_labels_table: the generator failed: {p.stderr.strip()}")
    return folder


def labels_of(folder):
    """Per-frame intervals (clip, start, end, action, style) from the manifest's segments."""
    rows = []
    with open(os.path.join(folder, "manifest.txt")) as f:
        for line in f:
            if line.startswith("#"):
                continue
            name, first, frames, source = line.split()[:4]
            m = NAME.search(source)
            if not m:
                sys.exit(f"library_labels_table: '{source}' is not dataset-1_ACTION_STYLE_TAKE")
            rows.append((name, int(first), int(first) + int(frames), m["action"], m["style"]))
    with open(folder.rstrip("/") + "-labels.csv", "w") as f:
        f.write("clip,start,end,action,style\n")
        for r in rows:
            f.write(",".join(str(v) for v in r) + "\n")
    return rows


def run(cmd, timeout, env=None):
    """Runs cmd in a fresh child: (rc or None on timeout, wall s, CPU s, peak MiB, stderr)."""
    return run_measured(cmd, timeout, env=env)


def read_points(path):
    with open(path, "rb") as f:
        rows, cols = (int(v) for v in f.readline().split())
        return np.fromfile(f, dtype="<f8", count=rows * cols).reshape(rows, cols)


def read_map(path):
    """(clip numbers, frames, coordinates) of a `motionmap map` CSV (clips numbered in the order
    of the files given)."""
    clips, frames, coords = [], [], []
    header = None
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                continue
            cells = line.rstrip("\n").split(",")
            if header is None:
                header = cells
                ci, fi = header.index("clip"), header.index("frame")
                xi = [i for i, h in enumerate(header) if re.fullmatch(r"x|y|z|dim\d+|d\d+", h)]
                continue
            clips.append(int(cells[ci]))
            frames.append(int(cells[fi]))
            coords.append([float(cells[i]) for i in xi])
    return clips, np.array(frames), np.array(coords)


def frame_labels(rows, files, clips, frames):
    """Action, take and clip of each map row."""
    by_clip = {}
    for name, start, end, action, style in rows:
        by_clip.setdefault(os.path.splitext(name)[0], []).append((start, end, action, style))
    action, take = [], []
    for c, f in zip(clips, frames):
        base = os.path.splitext(os.path.basename(files[c]))[0]
        for start, end, a, s in by_clip[base]:
            if start <= f < end:
                action.append(a)
                take.append(a + "_" + s)
                break
        else:
            sys.exit(f"library_labels_table: no label for {base} frame {f}")
    return np.array(action), np.array(take), np.asarray(clips)


def accuracy(Y, clip, labels, queries, voters):
    """Fraction of the queries whose `voters` nearest frames of other clips vote their label."""
    from sklearn.neighbors import NearestNeighbors
    # Exact either way: a k-d tree in the maps' 2 or 3 dimensions, BLAS distances in the points'.
    nn = NearestNeighbors(algorithm="kd_tree" if Y.shape[1] <= 3 else "brute").fit(Y)
    want = 4 * voters
    found = {}
    todo = np.asarray(queries)
    while len(todo):
        want = min(want, len(Y))
        dist, idx = nn.kneighbors(Y[todo], n_neighbors=want)
        again = []
        for q, row in zip(todo, idx):
            other = row[clip[row] != clip[q]][:voters]
            if len(other) == voters or want == len(Y):
                found[q] = other
            else:
                again.append(q)
        todo = np.array(again, dtype=int)
        want *= 8
    right = {name: 0 for name in labels}
    for q, other in found.items():
        for name, lab in labels.items():
            votes = {}
            for o in other:
                votes[lab[o]] = votes.get(lab[o], 0) + 1
            best = max(votes.values())
            winner = next(lab[o] for o in other if votes[lab[o]] == best)
            right[name] += winner == lab[q]
    return {name: right[name] / len(found) for name in labels}


def umap_learn_child(points, out, k):
    start = time.monotonic()
    import umap  # noqa: imported here, so the child's time holds the import
    P = read_points(points)
    for line in peer_blas()[0]:
        print(f"peer {line}", file=sys.stderr)
    fit_start = time.monotonic()
    Y = umap.UMAP(n_neighbors=k, n_components=2, min_dist=0.1, n_jobs=-1).fit_transform(P)
    fit = time.monotonic() - fit_start
    np.save(out, np.asarray(Y, dtype=np.float64))
    print(f"fit {fit:.2f} s, import and load {fit_start - start:.2f} s", file=sys.stderr)


def main():
    args = parse_args()
    if args.umap_learn_child:
        umap_learn_child(args.umap_learn_child[0], args.umap_learn_child[1],
                         int(args.umap_learn_child[2]))
        return
    cli = os.path.join(args.build, "apps", "cli", "motionmap")
    started = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    load_start = load_average()
    folder = library(args)
    rows = labels_of(folder)
    files = sorted(glob.glob(os.path.join(folder, "clip_*.bvh")))
    work = args.keep or tempfile.mkdtemp(prefix="motionmap-labels-")
    os.makedirs(work, exist_ok=True)
    print(f"{started} · load average {load_start} · nproc {os.cpu_count()} · "
          f"library {folder} ({args.frames} frames, {len(files)} clips, seed {args.seed}, "
          f"sources {os.path.abspath(args.source)}) · MOTIONMAP_THREADS "
          f"{os.environ.get('MOTIONMAP_THREADS', 'unset')}", flush=True)

    results = []  # (name, wall, cpu, peak, note, Y, clips, frames)
    for method in args.methods:
        out = os.path.join(work, f"{method}.csv")
        cmd = [cli, "map", *files, "-m", method, "-o", out, "-q", "--verbose"]
        rc, wall, cpu, peak, err = run(cmd, args.timeout)
        stages = "; ".join(f"{m[1]} {float(m[2]):.1f}" for m in re.finditer(
            r"verbose: ([^:]+): ([0-9.]+) s", err) if m[1] != "total")
        if rc != 0:
            tail = err.strip().splitlines()[-1] if err.strip() else ""
            results.append((method, wall, cpu, peak, f"failed ({rc}): {tail}", None, None, None))
            print(f"{method}: failed ({rc}) {tail}", flush=True)
            continue
        clips, frames, Y = read_map(out)
        results.append((method, wall, cpu, peak, stages, Y, clips, frames))
        print(f"{method}: {wall:.1f} s, CPU {cpu:.1f} s, {peak:.0f} MiB ({stages})", flush=True)

    points = os.path.join(work, "points.f64")
    tool = os.path.join(args.build, "bench", "library", "motionmap-points")
    p = subprocess.run([tool, points, *files], capture_output=True, text=True)
    if p.returncode != 0:
        sys.exit(f"library_labels_table: motionmap-points failed: {p.stderr.strip()}")
    P = read_points(points)
    # Rows of the points are the frames in the order `map` lays them out (the pca map's rows).
    ref = next((r for r in results if r[5] is not None), None)
    if ref is None or len(ref[5]) != len(P):
        sys.exit("library_labels_table: no map with one row per point to take the labels from")
    action, take, clip = frame_labels(rows, files, ref[6], ref[7])
    labels = {"action": action, "take": take}
    queries = np.random.default_rng(0).choice(len(P), size=min(args.queries, len(P)),
                                              replace=False)
    print(f"points {P.shape[0]} × {P.shape[1]}; {len(set(take))} takes, {len(set(action))} "
          f"actions; {len(queries)} queries, {args.voters} voters of other clips", flush=True)

    if args.umap_learn_result:
        npy, log = args.umap_learn_result
        with open(log) as f:
            text = f.read()
        t = re.search(r"([0-9.]+) s wall ([0-9.]+) user (?:([0-9.]+) sys )?([0-9]+) KB", text)
        fit = re.search(r"fit ([0-9.]+) s", text)
        results.append(("umap-learn (run apart)", float(t[1]), float(t[2]) + float(t[3] or 0),
                        int(t[4]) / 1024.0, f"fit {float(fit[1]):.1f}" if fit else "",
                        np.load(npy), None, None))
        print(f"umap-learn from {npy}, {log}", flush=True)
    elif not args.no_umap_learn:
        out = os.path.join(work, "umap-learn.npy")
        cmd = ["/usr/bin/python3", os.path.abspath(__file__), "--umap-learn-child", points, out,
               str(args.k)]
        blas = openblas_dir(args.openblas) if args.openblas != "system" else None
        if blas is None:
            print(f"WARNING: umap-learn runs on the system's BLAS (the reference BLAS on Debian: one "
                  f"core), not OpenBLAS as users run it. Get OpenBLAS: {GET_OPENBLAS}", flush=True)
        rc, wall, cpu, peak, err = run(cmd, args.timeout, openblas_env(blas) if blas else None)
        for line in err.splitlines():
            if line.startswith("peer "):
                print(f"umap-learn's {line}", flush=True)
        fit = re.search(r"fit ([0-9.]+) s", err)
        if rc == 0:
            Y = np.load(out)
            results.append(("umap-learn", wall, cpu, peak,
                            f"fit {float(fit[1]):.1f}" if fit else "", Y, None, None))
        else:
            tail = err.strip().splitlines()[-1] if err.strip() else ""
            results.append(("umap-learn", wall, cpu, peak,
                            "timeout" if rc is None else f"failed ({rc}): {tail}", None, None,
                            None))
        print(f"umap-learn: {wall:.1f} s, CPU {cpu:.1f} s, {peak:.0f} MiB ({results[-1][4]})",
              flush=True)

    start = time.monotonic()
    feature = accuracy(P, clip, labels, queries, args.voters)
    print(f"feature space accuracy in {time.monotonic() - start:.1f} s", flush=True)
    print()
    learn = next((r for r in results if r[0].startswith("umap-learn") and r[5] is not None), None)
    print("| map | wall s | CPU s | peak MiB | action accuracy | take accuracy | ÷ feature space "
          "(action, take) | umap-learn ÷ this (wall, CPU) | stages (s) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---|")
    for name, wall, cpu, peak, note, Y, clips, frames in results:
        if Y is None:
            print(f"| {name} | {wall:.1f} | {cpu:.1f} | {peak:.0f} | – | – | – | – | {note} |")
            continue
        if clips is not None and list(clips) != list(ref[6]):
            sys.exit(f"library_labels_table: {name}'s rows are not in the pca map's order")
        acc = accuracy(Y, clip, labels, queries, args.voters)
        ratio = (f"{learn[1] / wall:.1f}×, {learn[2] / cpu:.1f}×" if learn and name == "umap"
                 else "")
        print(f"| {name} | {wall:.1f} | {cpu:.1f} | {peak:.0f} | {acc['action']:.3f} | "
              f"{acc['take']:.3f} | {acc['action'] / feature['action']:.3f}, "
              f"{acc['take'] / feature['take']:.3f} | {ratio} | {note} |", flush=True)
    print(f"| feature space (the points, {P.shape[1]}-D) | | | | {feature['action']:.3f} | "
          f"{feature['take']:.3f} | 1, 1 | | |")
    print(f"\nload average at the end: {load_average()}")


if __name__ == "__main__":
    main()
