#!/usr/bin/python3
"""Reference numbers for MotionMap's umap (tests/embed/umap_test.cpp) from umap-learn (Debian's
umap-learn, a test reference only), written under tests/reference/umap/ (beside fixtures/, whose folders are map cases).

    /usr/bin/python3 tests/reference/make_umap_fixtures.py [path/to/motionmap]

(the CLI, default build/apps/cli/motionmap, writes the Bandai takes' point clouds for bandai.txt)

UMAP is stochastic, so its maps are compared through what is deterministic and through quality
numbers, never coordinates:

  fuzzy_graph.txt  umap-learn's fuzzy_simplicial_set (rho, sigma, the symmetric memberships) on
                   the k-NN graph of clip_cmu_64_08/D.txt (CMU 64_08, every 4th frame, point-cloud
                   distances, from tests/reference/mocap.py): n_neighbors = 15, each frame's 14
                   nearest others, ties to the smaller index, their distances rounded to
                   float32 values (see fuzzy_graph_fixture).
  curve.txt        find_ab_params(spread 1, min_dist) for several min_dist.
  bandai.txt       the 12 Bandai takes of /work/shared/data/bandai, D = the point-cloud distances
                   of the heading-local points MotionMap computes (`motionmap map --save`'s
                   /model/points, read with h5py, so both sides map the same input): umap-learn's map
                   (metric "precomputed", n_neighbors 15, min_dist 0.1, its default epochs and
                   spectral start) for seeds 0…4, each map's trustworthiness at 10 neighbours
                   (sklearn) and its 10-NN action accuracy (a frame's 10 nearest map neighbours
                   from the other takes vote on its action, the file name's second word; a tie
                   goes to the tied action of the nearest neighbour), plus a fingerprint of D
                   (frames, sum, a few entries) for the test to check it has the same input.
"""
import glob
import os
import subprocess
import sys
import tempfile

import h5py

import numpy as np
import scipy.sparse
from scipy.spatial.distance import cdist
from sklearn.manifold import trustworthiness

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mocap  # noqa: E402

import umap  # noqa: E402
import umap.umap_ as uu  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "umap")
SHARED = os.path.abspath(os.path.join(HERE, "..", "..", "..", "shared", "data"))
if not os.path.isdir(SHARED):
    SHARED = "/work/shared/data"


def read_matrix(path):
    rows = [line for line in open(path) if not line.startswith("#")]
    return np.array([[float(v) for v in line.split()] for line in rows])


def knn(D, others):
    n = D.shape[0]
    index = np.zeros((n, others), dtype=np.int64)
    for i in range(n):
        order = np.lexsort((np.arange(n), D[i]))
        order = order[order != i][:others]
        index[i] = order
    return index


def fuzzy_graph_fixture():
    D = read_matrix(os.path.join(HERE, "fixtures", "clip_cmu_64_08", "D.txt"))
    n = D.shape[0]
    k = 15
    others = knn(D, k - 1)
    knn_indices = np.hstack([np.arange(n)[:, None], others])
    # The distances rounded to float32 values (umap-learn keeps rho in float32, so only then is
    # its rho the nearest distance exactly), held in float64: fuzzy_simplicial_set's steps in
    # their Python form (its numba form subtracts in float32, which moves sigma's bisection by
    # ~5e-6), smooth_knn_dist, compute_membership_strengths, then its fuzzy union A + Aᵀ − A∘Aᵀ.
    knn_dists = np.hstack([np.zeros((n, 1)), D[np.arange(n)[:, None], others]])
    knn_dists = knn_dists.astype(np.float32).astype(np.float64)
    sigmas, rhos = uu.smooth_knn_dist.py_func(knn_dists, float(k))
    rows, cols, vals = uu.compute_membership_strengths.py_func(
        knn_indices, knn_dists, sigmas, rhos)[:3]
    A = scipy.sparse.coo_matrix((vals.astype(np.float64), (rows, cols)), shape=(n, n)).tocsr()
    A.eliminate_zeros()
    graph = (A + A.T - A.multiply(A.T)).tocoo()
    with open(os.path.join(OUT, "fuzzy_graph.txt"), "w") as f:
        f.write("# umap-learn %s fuzzy_simplicial_set of clip_cmu_64_08/D.txt, n_neighbors %d\n"
                % (umap.__version__, k))
        f.write("# frames %d\n" % n)
        f.write("# per frame: its %d nearest others, their distances, rho, sigma\n"
                % (k - 1))
        for i in range(n):
            f.write(" ".join(str(int(j)) for j in others[i]) + " "
                    + " ".join("%.17g" % d for d in knn_dists[i, 1:]) + " %.9g %.9g\n"
                    % (rhos[i], sigmas[i]))
        upper = [(int(i), int(j), float(w)) for i, j, w in zip(graph.row, graph.col, graph.data)
                 if i < j and w > 0]
        f.write("# edges %d (i < j, membership)\n" % len(upper))
        for i, j, w in sorted(upper):
            f.write("%d %d %.9g\n" % (i, j, w))


def curve_fixture():
    with open(os.path.join(OUT, "curve.txt"), "w") as f:
        f.write("# umap-learn %s find_ab_params(spread = 1, min_dist): min_dist a b\n"
                % umap.__version__)
        for min_dist in [0.0, 0.001, 0.01, 0.05, 0.1, 0.2, 0.25, 0.5, 0.8, 0.99]:
            a, b = uu.find_ab_params(1.0, min_dist)
            f.write("%.17g %.17g %.17g\n" % (min_dist, a, b))


def label_accuracy(Y, take, action, k=10):
    """Share of frames whose 10 nearest map neighbours from other takes vote for its action."""
    E = cdist(Y, Y)
    right = 0
    for i in range(Y.shape[0]):
        candidates = np.flatnonzero(take != take[i])
        order = candidates[np.lexsort((candidates, E[i, candidates]))][:k]
        votes = {}
        for j in order:
            votes[action[j]] = votes.get(action[j], 0) + 1
        best = max(votes.values())
        winner = next(action[j] for j in order if votes[action[j]] == best)
        right += winner == action[i]
    return right / Y.shape[0]


def bandai_fixture(cli):
    paths = sorted(glob.glob(os.path.join(SHARED, "bandai", "*.bvh")))
    with tempfile.TemporaryDirectory() as tmp:
        saved = os.path.join(tmp, "bandai.mmap")
        subprocess.run([cli, "map", *paths, "--method", "isomap", "--save", saved, "-q",
                        "-o", os.path.join(tmp, "bandai.csv")], check=True)
        with h5py.File(saved) as f:
            P = np.array(f["/model/points"])
            take = np.array(f["/samples/clip"]).astype(int)
    D = cdist(P, P)
    names = [os.path.basename(p).split("_")[1] for p in paths]
    action = np.array([names[t] for t in take])
    lines = []
    for seed in range(5):
        Y = umap.UMAP(n_neighbors=15, min_dist=0.1, metric="precomputed",
                      random_state=seed).fit_transform(D)
        t = trustworthiness(D, Y, n_neighbors=10, metric="precomputed")
        a = label_accuracy(Y, take, action)
        lines.append("%d %.6f %.6f" % (seed, t, a))
        print("umap-learn seed %d: trustworthiness %.4f, 10-NN action accuracy %.4f" % (seed, t, a))
    with open(os.path.join(OUT, "bandai.txt"), "w") as f:
        f.write("# umap-learn %s on the 12 Bandai takes, metric precomputed (point-cloud D), "
                "n_neighbors 15, min_dist 0.1\n" % umap.__version__)
        f.write("# takes %s\n" % " ".join(os.path.basename(p) for p in paths))
        f.write("# frames %d\n" % P.shape[0])
        f.write("# D sum %.17g D(0,1) %.17g D(100,2000) %.17g\n"
                % (D.sum(), D[0, 1], D[100, min(2000, D.shape[0] - 1)]))
        f.write("# seed trustworthiness(k=10) action_accuracy(10-NN, other takes)\n")
        f.write("\n".join(lines) + "\n")


def main():
    os.makedirs(OUT, exist_ok=True)
    cli = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, "..", "..", "build", "apps",
                                                             "cli", "motionmap")
    fuzzy_graph_fixture()
    curve_fixture()
    bandai_fixture(cli)


if __name__ == "__main__":
    main()
