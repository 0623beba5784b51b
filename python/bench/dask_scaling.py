#!/usr/bin/env python3
"""Measures motionmap.dask.map_library on a LocalCluster of 1 and of 2 worker processes (one thread
each, MOTIONMAP_THREADS=1 so a worker uses one core), and the per-stage throughput of one core,
for docs/distributed.md.

usage: PYTHONPATH=build/python python3 python/bench/dask_scaling.py LIBRARY_DIR [--sample N]
LIBRARY_DIR: a folder of .bvh clips of one skeleton (bench/library's motionmap-make-library
writes one: --frames 96000 --clip-frames 2000).
"""
import argparse
import glob
import os
import time

os.environ["MOTIONMAP_THREADS"] = "1"  # before the library starts its pool (and for the workers)

import distributed  # noqa: E402

import motionmap  # noqa: E402
import motionmap.dask  # noqa: E402


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("library")
    parser.add_argument("--sample", type=int, default=4)
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--clips", type=int, default=0, help="use the first N clips (0: all)")
    parser.add_argument("--path", default="landmarks",
                        help="the map's path: landmarks (placement by the landmark "
                             "triangulation) or auto/dense (a dense Isomap places every frame "
                             "by Dijkstra over the sample graph, much slower)")
    args = parser.parse_args()
    paths = sorted(glob.glob(os.path.join(args.library, "*.bvh")))
    if args.clips:
        paths = paths[:args.clips]
    frames = sum(motionmap.load(p).num_frames for p in paths[:1]) * len(paths)

    # One core, one process: the stages of a worker's task.
    est = motionmap.Isomap(path=args.path)
    sample = motionmap.dask.choose_sample(paths, args.sample)
    t = time.perf_counter()
    est.fit(sample)
    fit_s = time.perf_counter() - t
    t = time.perf_counter()
    for p in paths[:8]:
        motionmap.load(p)
    load_s = (time.perf_counter() - t) / 8
    t = time.perf_counter()
    for p in paths[:8]:
        est.transform(p)
    place_s = (time.perf_counter() - t) / 8  # load + features + placement of one clip
    per_clip = frames / len(paths)
    print(f"library: {len(paths)} clips, about {frames} frames; sample {len(sample)} clips "
          f"({est.embedding_.shape[0]} frames)")
    print(f"one core: fit {fit_s:.2f} s; per clip of {per_clip:.0f} frames: load {load_s:.3f} s, "
          f"load+features+place {place_s:.3f} s ({per_clip / place_s:.0f} frames/s)")

    for n in args.workers:
        cluster = distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                           dashboard_address=None, silence_logs=40)
        with distributed.Client(cluster) as client:
            client.run(lambda: None)  # workers up
            t = time.perf_counter()
            result = motionmap.dask.map_library(paths, client, motionmap.Isomap(path=args.path),
                                                sample=args.sample)
            total = time.perf_counter() - t
        cluster.close()
        placed = sum(len(c) for c in result.coordinates)
        print(f"{n} worker(s): {total:.2f} s for {placed} frames "
              f"({placed / total:.0f} frames/s)")


if __name__ == "__main__":
    main()
