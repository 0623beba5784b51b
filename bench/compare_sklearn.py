#!/usr/bin/python3
"""MotionMap's six maps side by side with scikit-learn / scipy, on the same inputs, in one run.

    /usr/bin/python3 bench/compare_sklearn.py                      # driver from build/bench
    /usr/bin/python3 bench/compare_sklearn.py --driver build-bench/bench/motionmap_compare
    /usr/bin/python3 bench/compare_sklearn.py --sizes 2000 --repeat 5 --no-real
    /usr/bin/python3 bench/compare_sklearn.py --openblas system    # the peer on the system's BLAS

For every case the C++ driver motionmap_compare (bench/motionmap_compare.cpp) builds X (joint
rotation quaternions) and D (point-cloud pose distances) with the library, writes them, times each
method's embed() call (best of --repeat runs, library time only) and writes the maps. This script
then reads the same inputs, times the scikit-learn / scipy counterpart of each method the same
way (best of --repeat runs) and prints, per case and method: both times, the ratio
(scikit-learn ÷ MotionMap) and the Procrustes disparity between the two maps
(scipy.spatial.procrustes: 0 = identical up to translation, rotation, reflection and scale).

All inputs come from the driver: X (joint-rotation quaternions, the default features), P and D.

Cases: CMU 64_08 (the reference swing, 364 frames without its T-pose), CMU 64_08 + 64_09
concatenated (816 frames, all the real swings of one skeleton there are), and the built-in
procedural swing at --sizes frames (default 2000 and 8000; the real clips cannot reach those sizes
without repeating frames, whose exact ties would make the graph methods degenerate).

The counterparts (k = 20 neighbours everywhere):
  pca     sklearn.decomposition.PCA(2) on X (default solver choice)
  svd     sklearn.decomposition.TruncatedSVD(2) on X (default: randomized, 5 iterations)
  mds     classical MDS: B = -1/2 J D^2 J in numpy, then scipy.linalg.eigh(B, subset_by_index=
          top 2) -- only up to --eigh-max frames (LAPACK tridiagonalises all of B: O(F^3));
  mds/eigsh  the same B with scipy.sparse.linalg.eigsh (ARPACK Lanczos, the fast scipy route)
  isomap  sklearn.manifold.Isomap(n_neighbors=20, metric='precomputed') on D
  le      sklearn.neighbors.kneighbors_graph(D, 20, metric='precomputed'), heat-kernel weights
          exp(-d^2/t) with t = the median squared k-NN distance (MotionMap's automatic heat),
          symmetrised as the union of the k-NN lists, then sklearn.manifold.SpectralEmbedding(2,
          affinity='precomputed') on those weights -- all of it timed, as MotionMap's le does the
          k-NN search and the weights too. Only up to --sk-le-max frames: SpectralEmbedding's
          shift-invert ARPACK (sigma=1 on -L, where the wanted eigenvalues of the long
          trajectory's Laplacian are tiny and clustered) took ~40 s at 2000 frames and had not
          finished after 8.5 CPU minutes at 8000; its lobpcg solver is fast but did not converge
          (disparity 0.87 at 2000)
  lle     sklearn.manifold.LocallyLinearEmbedding(n_neighbors=20, reg=1e-3) on P, the
          heading-local point clouds (MotionMap's --features positions). scikit-learn picks the
          neighbours from its feature matrix, MotionMap from D; D is exactly the Euclidean
          distance of P's rows, so both solve the same problem when MotionMap's lle gets (P, D).
          (With the quaternions X as features the neighbours would differ; on CMU 64_08 the
          flipping thumb quaternions even split X's k-NN graph.) scikit-learn's time includes
          its k-NN search on P, MotionMap's reads D, which the driver built beforehand.
          On the finely sampled generated swing the bottom eigenvalues of LLE's M are ~1e-13,
          near rounding level, so the map is ill-determined: scikit-learn's own dense and ARPACK
          solvers differ by a disparity of 7e-3 at 2000 frames. There the disparity measures
          that conditioning, not an error of either side.

The peer runs as users run it: on OpenBLAS, all cores. MotionMap runs on all cores (std::thread);
Debian's numpy/scipy load whatever libblas.so.3 / liblapack.so.3 the system's alternatives name,
by default the reference BLAS/LAPACK (one core, unblocked). So the script re-executes itself
with LD_LIBRARY_PATH=DIR in front, DIR = --openblas (default: the first of peer_blas.OPENBLAS_DIRS
that holds libblas.so.3 and liblapack.so.3), unless LD_LIBRARY_PATH already holds DIR: only this
process and its children see OpenBLAS; the C++ driver gets the caller's environment back. How to
get OpenBLAS without switching the system's BLAS: bench/peer_blas.py.

The re-executed process runs OpenBLAS's kernel for the processor's instruction set
(OPENBLAS_CORETYPE: peer_blas.cpu_kernel(), which says why). The output starts with the BLAS the
peer actually loaded, its threads and kernel (threadpoolctl).
Without OpenBLAS the script says so and goes on with the reference BLAS, every ratio marked.

Beside each ratio: MotionMap's distance to its physical bound. Once at the start the script
measures the streaming memory bandwidth (best of 5 threaded sums and copies of 256 MiB arrays) and
the peak double-precision rate (best of 3 square dgemm on the peer's BLAS, all threads). Each
MotionMap stage then gets the bytes it must move and the flops it must do at its size; its bound is
max(bytes / bandwidth, flops / peak), a method's the sum of its stages' (F frames, p = X's columns,
d = P's columns, k = 20, E = the symmetrised k-NN graph's non-zeros, doubles of 8 bytes):
  pca, svd   eigen: read X twice (the p x p Gram matrix, then the scores): 16·F·p bytes;
             F·p² + 4·F·p flops (the Gram matrix's lower triangle, the two score columns)
  mds        eigen: 12 Lanczos products and the squared column sums, each one pass over D's lower
             triangle: 13·4·F² bytes, 24·F² flops (dense solver for F <= 200: 8·F², 4/3·F³);
             stress: one more pass, 4·F² bytes, 4·F² flops
  isomap     neighbours: read D once, 8·F² bytes; shortest paths: write the F x F geodesic matrix,
             8·F² bytes, and relax every edge once per source, 2·F·E operations (an add and a min,
             counted at the dgemm peak: generous); then eigen and stress as mds
  le         neighbours as isomap; eigen: 12 shift-invert products, each a forward and a backward
             substitution through at least the Laplacian's lower triangle, 12·12·(E + F) bytes
  lle        neighbours as isomap; weights: gather each frame's k neighbours' rows, 8·F·k·d bytes,
             and solve its k x k system, F·(k²·d + k³/3) flops; eigen as le, with M = (I-W)ᵀ(I-W)
The bandwidth is DRAM's: at 2000 frames D (32 MB) may partly sit in cache, where a stage can beat
its "bound". A method more than 5× from its bound is marked: that is the next speed work, and
the stage times name the stage with the most time above its bound.

The load average is printed before and after: the machine may be shared.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from peer_blas import (CORETYPE_VARS, GET_OPENBLAS, OPENBLAS_DIRS,  # noqa: E402
                       on_path, openblas_dir, openblas_env, peer_blas)

SAVED_ENV = "COMPARE_SKLEARN_SAVED_ENV"  # the caller's values of what the re-execution changed


def reexec_on_openblas():
    """Runs this script again with OpenBLAS's folder first in LD_LIBRARY_PATH and without the
    CORETYPE variables, before numpy loads a BLAS; does nothing when it is there already or when
    there is no OpenBLAS (main says so)."""
    early = argparse.ArgumentParser(add_help=False)
    early.add_argument("--openblas")
    given = early.parse_known_args()[0].openblas
    folder = openblas_dir(given) if given != "system" else None
    if folder is None or on_path(folder):
        return
    env = openblas_env(folder)
    env[SAVED_ENV] = json.dumps({v: os.environ.get(v) for v in ("LD_LIBRARY_PATH", *CORETYPE_VARS)})
    os.execve(sys.executable, [sys.executable, os.path.abspath(__file__), *sys.argv[1:]], env)


if __name__ == "__main__":
    reexec_on_openblas()

import numpy as np  # noqa: E402 (after the re-execution: importing numpy loads the BLAS)
import scipy.linalg
import scipy.sparse.linalg
from scipy.spatial import procrustes
from sklearn.decomposition import PCA, TruncatedSVD
from sklearn.manifold import Isomap, LocallyLinearEmbedding, SpectralEmbedding
from sklearn.neighbors import kneighbors_graph

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SHARED = os.path.normpath(os.path.join(ROOT, "..", "shared", "data"))
K = 20
METHODS = ["pca", "svd", "mds", "isomap", "le", "lle"]
FAR = 5.0  # MotionMap more than this many times its bound: the next speed work


# ----------------------------------------------------------------------------------------------
# scikit-learn / scipy counterparts: each takes the driver's inputs (dict: X, P, D) and returns
# the F by 2 map.


def sk_pca(inputs):
    X = inputs["X"]
    return PCA(n_components=2).fit_transform(X)


def sk_svd(inputs):
    X = inputs["X"]
    return TruncatedSVD(n_components=2, random_state=0).fit_transform(X)


def double_centred(D):
    S = D * D
    r = S.mean(axis=1)
    B = S - r[:, None] - r[None, :] + r.mean()
    B *= -0.5
    return B


def mds_coordinates(w, V):
    order = np.argsort(w)[::-1]
    return V[:, order] * np.sqrt(np.maximum(w[order], 0.0))


def sk_mds_eigh(inputs):
    D = inputs["D"]
    n = D.shape[0]
    w, V = scipy.linalg.eigh(double_centred(D), subset_by_index=[n - 2, n - 1])
    return mds_coordinates(w, V)


def sk_mds_eigsh(inputs):
    D = inputs["D"]
    n = D.shape[0]
    v0 = np.random.default_rng(0).uniform(-1, 1, n)
    w, V = scipy.sparse.linalg.eigsh(double_centred(D), k=2, which="LA", v0=v0)
    return mds_coordinates(w, V)


def sk_isomap(inputs):
    D = inputs["D"]
    return Isomap(n_neighbors=K, n_components=2, metric="precomputed").fit_transform(D)


def sk_le(inputs):
    D = inputs["D"]
    G = kneighbors_graph(D, K, mode="distance", metric="precomputed", include_self=False)
    heat = np.median(G.data ** 2)
    # Weights before symmetrising, so a zero-length edge (weight 1) is never dropped as a zero.
    G.data = np.exp(-G.data ** 2 / heat)
    W = G.maximum(G.T)
    return SpectralEmbedding(n_components=2, affinity="precomputed",
                             random_state=0).fit_transform(W)


def sk_lle(inputs):
    return LocallyLinearEmbedding(n_neighbors=K, n_components=2, reg=1e-3,
                                  random_state=0).fit_transform(inputs["P"])


COUNTERPARTS = {
    "pca": [("pca", sk_pca)],
    "svd": [("svd", sk_svd)],
    "mds": [("mds", sk_mds_eigh), ("mds/eigsh", sk_mds_eigsh)],
    "isomap": [("isomap", sk_isomap)],
    "le": [("le", sk_le)],
    "lle": [("lle", sk_lle)],
}
METHOD_OF = {name: method for method, pairs in COUNTERPARTS.items() for name, _ in pairs}


def best_of(repeat, fn, *args):
    """Best seconds of up to `repeat` calls (fewer once 10 s are spent, as the driver does)."""
    times, spent, result = [], 0.0, None
    for r in range(repeat):
        if r > 0 and spent >= 10.0:
            break
        t0 = time.perf_counter()
        result = fn(*args)
        times.append(time.perf_counter() - t0)
        spent += times[-1]
    return min(times), result


# ----------------------------------------------------------------------------------------------
# The peer's BLAS, the machine's bounds, and each MotionMap stage's bound (the docstring's model).


def driver_env():
    """The caller's environment, as it was before the re-execution, for the C++ driver."""
    env = dict(os.environ)
    for name, value in json.loads(env.pop(SAVED_ENV, "{}")).items():
        if value is None:
            env.pop(name, None)
        else:
            env[name] = value
    return env


def measure_machine():
    """(streaming memory bandwidth in bytes/s, peak double-precision flop/s, whether the dgemm's
    result is right): threaded sums and copies of 256 MiB arrays, square dgemm on the peer's BLAS
    grown until a run takes 0.2 s (best of 3)."""
    threads = os.cpu_count()
    a, b = np.ones(1 << 25), np.empty(1 << 25)
    parts, outs = np.array_split(a, threads), np.array_split(b, threads)
    with ThreadPoolExecutor(threads) as pool:
        read = best_of(5, lambda: list(pool.map(np.sum, parts)))[0]
        copy = best_of(5, lambda: list(pool.map(np.copyto, outs, parts)))[0]
    bandwidth = max(a.nbytes / read, 2 * a.nbytes / copy)
    rng = np.random.default_rng(0)
    n = 512
    while True:
        A, B = rng.standard_normal((n, n)), rng.standard_normal((n, n))
        seconds, C = best_of(3, np.matmul, A, B)
        if seconds > 0.2 or n >= 4096:
            break
        n *= 2
    right = np.allclose(C[:2, :64], (A[:2, :, None] * B[None, :, :64]).sum(axis=1))
    return bandwidth, 2.0 * n ** 3 / seconds, right


def graph_sizes(D):
    """Non-zeros of the symmetrised k-NN graph of D, and of LLE's M = (I - W)ᵀ(I - W)."""
    G = kneighbors_graph(D, K, metric="precomputed")
    A = (G + scipy.sparse.identity(D.shape[0], format="csr")).tocsr()
    return (G + G.T).nnz, (A.T @ A).nnz


def stage_work(method, res, E, M):
    """{MotionMap stage: (bytes it must move, flops it must do)}; stages not named cost 0."""
    F, p, d, k = res["frames"], res["features"], res["points"], res["k"]
    tri = 4.0 * F * F  # bytes of an F x F matrix's lower triangle
    mds = {"eigen": (13 * tri, 24.0 * F * F) if F > 200 else (8.0 * F * F, 4 / 3 * F ** 3),
           "stress": (tri, 4.0 * F * F)}
    neighbours = {"neighbours": (8.0 * F * F, 1.0 * F * F)}
    if method in ("pca", "svd"):
        return {"eigen": (16.0 * F * p, F * p * p + 4.0 * F * p)}
    if method == "mds":
        return mds
    if method == "isomap":
        return {**neighbours, "shortest paths": (8.0 * F * F, 2.0 * F * E), **mds}
    if method == "le":
        return {**neighbours, "eigen": (144.0 * (E + F), 24.0 * (E + F))}
    return {**neighbours, "weights": (8.0 * F * k * d, F * (k * k * d + k ** 3 / 3)),
            "eigen": (144.0 * M, 24.0 * M)}


def stage_bounds(method, res, E, M, machine):
    """{stage: seconds it needs at least}: max(bytes / bandwidth, flops / peak)."""
    bandwidth, peak = machine[:2]
    return {stage: max(moved / bandwidth, flops / peak)
            for stage, (moved, flops) in stage_work(method, res, E, M).items()}


# ----------------------------------------------------------------------------------------------


def find_driver(given):
    if given:
        return given
    for build in ("build", "build-bench"):
        path = os.path.join(ROOT, build, "bench", "motionmap_compare")
        if os.access(path, os.X_OK):
            return path
    sys.exit("compare_sklearn.py: motionmap_compare not found in build/bench or build-bench/bench; "
             "build it (ninja -C build motionmap_compare) or pass --driver PATH")


def run_case(driver, label, driver_args, repeat, limits, workdir, machine):
    out = os.path.join(workdir, label.replace(" ", "_").replace("+", "_"))
    cmd = [driver, *driver_args, "--out", out, "--repeat", str(repeat)]
    proc = subprocess.run(cmd, capture_output=True, text=True, env=driver_env())
    if proc.returncode != 0:
        sys.exit(f"compare_sklearn.py: {' '.join(cmd)} failed:\n{proc.stderr}")
    with open(os.path.join(out, "result.json")) as f:
        res = json.load(f)
    n, p = res["frames"], res["features"]
    inputs = {"X": np.fromfile(os.path.join(out, "X.f64")).reshape(n, p),
              "P": np.fromfile(os.path.join(out, "P.f64")).reshape(n, res["points"]),
              "D": np.fromfile(os.path.join(out, "D.f64")).reshape(n, n)}
    E, M = graph_sizes(inputs["D"])
    res["bounds"] = {m: stage_bounds(m, res, E, M, machine) for m in METHODS}
    rows = []
    for method in METHODS:
        mm = res["methods"][method]
        Y = np.fromfile(os.path.join(out, f"Y_{method}.f64")).reshape(n, 2)
        for name, fn in COUNTERPARTS[method]:
            limit = limits.get(name)
            if limit is not None and n > limit[0]:
                rows.append((name, mm["best"], None, None, f"not run: F > {limit[1]} {limit[0]}"))
                continue
            sk_time, Y_sk = best_of(repeat, fn, inputs)
            disparity = procrustes(Y, Y_sk)[2]
            rows.append((name, mm["best"], sk_time, disparity, ""))
        print(f"  {label}: {method} done", file=sys.stderr, flush=True)
    return res, rows


def fmt_seconds(s):
    if s is None:
        return "–"
    return f"{s * 1000:.1f} ms" if s < 1.0 else f"{s:.2f} s"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--driver", help="path of motionmap_compare (default: build/bench, "
                                     "then build-bench/bench)")
    ap.add_argument("--sizes", type=int, nargs="*", default=[2000, 8000],
                    help="frames of the generated swing cases (default 2000 8000)")
    ap.add_argument("--repeat", type=int, default=3, help="runs per method and side; best counts")
    ap.add_argument("--eigh-max", type=int, default=3000,
                    help="largest F for the dense scipy.linalg.eigh MDS (O(F^3); default 3000)")
    ap.add_argument("--sk-le-max", type=int, default=2000,
                    help="largest F for scikit-learn's SpectralEmbedding (its shift-invert ARPACK "
                         "took 39 s at 2000 frames of the sample swing; default 2000)")
    ap.add_argument("--no-real", action="store_true", help="skip the CMU cases")
    ap.add_argument("--workdir", help="keep the driver's files here (default: a temporary folder)")
    ap.add_argument("--openblas", metavar="DIR",
                    help="OpenBLAS's libblas.so.3/liblapack.so.3 folder for the peer (default: the "
                         "first of " + ", ".join(OPENBLAS_DIRS) + " that has them); 'system': "
                         "the system's BLAS")
    args = ap.parse_args()
    driver = find_driver(args.driver)

    cases = []
    if not args.no_real:
        clips = [os.path.join(SHARED, "cmu", c) for c in ("64_08.bvh", "64_09.bvh")]
        if all(os.path.exists(c) for c in clips):
            cases.append(("CMU 64_08", clips[:1]))
            cases.append(("CMU 64_08+64_09", clips))
        else:
            print(f"note: {SHARED}/cmu/64_08.bvh or 64_09.bvh missing: real cases skipped")
    for f in args.sizes:
        cases.append((f"sample swing {f}", ["--generate", str(f)]))

    print(f"driver: {driver}")
    print(f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}  "
          f"(cores: {os.cpu_count()})")
    blas_lines, tuned = peer_blas()
    for line in blas_lines:
        print(f"peer {line}")
    saved = json.loads(os.environ.get(SAVED_ENV, "{}"))
    changed = [f"{v}={os.environ.get(v)} (was {saved.get(v)})" for v in CORETYPE_VARS
               if saved.get(v) != os.environ.get(v)]
    if changed and tuned:
        print(f"peer: for this process only: {', '.join(changed)}")
    if not tuned:
        where = ("--openblas system" if args.openblas == "system" else
                 f"no OpenBLAS in {args.openblas or ' or '.join(OPENBLAS_DIRS)}")
        warning = (f"WARNING: {where}: scikit-learn/scipy run on the reference BLAS, one core, "
                   "not as users run them; every ratio is marked (ref. BLAS). Get OpenBLAS "
                   f"without switching the system's BLAS: {GET_OPENBLAS}")
        print(warning)
        print(warning, file=sys.stderr)
    machine = measure_machine()
    print(f"machine: streaming memory bandwidth {machine[0] / 1e9:.1f} GB/s, peak "
          f"{machine[1] / 1e9:.1f} GFLOP/s (dgemm on the peer's BLAS"
          f"{'' if tuned else ': one core, below the machine’s peak'}"
          f"{'' if machine[2] else '; its result is WRONG'})")
    with tempfile.TemporaryDirectory() as tmp:
        workdir = args.workdir or tmp
        results = []
        for label, driver_args in cases:
            limits = {"mds": (args.eigh_max, "--eigh-max"), "le": (args.sk_le_max, "--sk-le-max")}
            results.append((label, *run_case(driver, label, driver_args, args.repeat, limits,
                                             workdir, machine)))

    print()
    print("| case | F | method | MotionMap | scikit-learn/scipy | ratio | bound "
          "| MotionMap / bound | Procrustes disparity |")
    print("|---|---:|---|---:|---:|---:|---:|---:|---:|")
    for label, res, rows in results:
        for name, mm, sk, disparity, note in rows:
            ratio = "–" if sk is None else f"{sk / mm:.1f}×" + ("" if tuned else " (ref. BLAS)")
            disp = f"{disparity:.1e}" if disparity is not None else note
            bound = sum(res["bounds"][METHOD_OF[name]].values())
            far = f"{mm / bound:.1f}×" + (" far" if mm / bound > FAR else "")
            print(f"| {label} | {res['frames']} | {name} | {fmt_seconds(mm)} | {fmt_seconds(sk)} "
                  f"| {ratio} | {fmt_seconds(bound)} | {far} | {disp} |")
    print()
    print("| case | F | MotionMap build_features (X, D) | motionmap_compare peak memory (VmHWM) |")
    print("|---|---:|---:|---:|")
    for label, res, rows in results:
        peak = max(res["peak_rss_mib"].values())
        print(f"| {label} | {res['frames']} | {fmt_seconds(res['features_seconds'])} "
              f"| {peak:.0f} MiB "
              f"(after features {res['peak_rss_mib']['features']:.0f} MiB) |")
    print()
    print("MotionMap stage times (best run, ms; in brackets the stage's bound):")
    for label, res, rows in results:
        for m in METHODS:
            bounds = res["bounds"][m]
            stages = ", ".join(f"{k} {v * 1000:.1f}" +
                               (f" ({bounds[k] * 1000:.1f})" if k in bounds else "")
                               for k, v in res["methods"][m]["stages"].items())
            print(f"  {label} {m}: {stages}")
    print()
    for label, res, rows in results:
        if label == "CMU 64_08":
            total = sum(res["methods"][m]["best"] for m in METHODS)
            verdict = "meets" if total < 0.1 else "misses"
            print(f"CMU 64_08, all six maps: {total * 1000:.1f} ms together "
                  f"({verdict} the < 100 ms target)")
    slow = [(label, name, sk / mm) for label, res, rows in results
            for name, mm, sk, _, _ in rows
            if sk is not None and res["frames"] >= 2000 and name != "mds" and sk / mm < 10.0]
    if slow:
        print("below the 10× target (issue 11) at F ≥ 2000: " +
              ", ".join(f"{l} {n} {r:.1f}×" for l, n, r in slow))
    else:
        print("every method ≥ 10× its scikit-learn/scipy counterpart at F ≥ 2000 (issue 11)")
    far = []
    for label, res, rows in results:
        for m in METHODS:
            mm, bounds = res["methods"][m], res["bounds"][m]
            if mm["best"] > FAR * sum(bounds.values()):
                above = {s: t - bounds.get(s, 0.0) for s, t in mm["stages"].items()}
                stage = max(above, key=above.get)
                far.append(f"  {label} {m}: {mm['best'] / sum(bounds.values()):.0f}× its bound; "
                           f"{stage} {above[stage] * 1000:.1f} ms above its own")
    print(f"next speed work, MotionMap > {FAR:.0f}× its bound (and the stage most above its bound):"
          + ("\n" + "\n".join(far) if far else " none"))
    print(f"load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
