#!/usr/bin/python3
"""Reference maps for tests/embed: every MotionMap embedding method recomputed independently
with numpy / scipy / scikit-learn on deterministic cases, written as small text files under
tests/reference/fixtures/<case>/.

Run with Debian's python (numpy, scipy, scikit-learn):  /usr/bin/python3 tests/reference/make_fixtures.py

Each case is a Case(name, X, D, k, ...) entry in CASES. D = None means D = the Euclidean
distances of X's rows, which tests/embed recompute bit for bit (one column at a time, in column
order, then sqrt) instead of reading a large file; give D explicitly (e.g. a pose-distance
matrix from features/) and it is written to D.txt. Clip cases (the built-in
sample swing and a subset of CMU 64_08) take X and D from tests/reference/mocap.py, an
independent NumPy/SciPy reading of the BVH; their X.txt names the source, stride and file frames,
and tests/features/reference_pipeline_test.cpp checks the C++ features and maps against them.
The sample case needs the sample written first:
    motionmap sample --kind swing -o /tmp/swing.bvh
    /usr/bin/python3 tests/reference/make_fixtures.py --sample /tmp/swing.bvh

Files per case:
  X.txt                    "# rows cols" then one row per line (%.17g)
  D.txt                    only when the case gives D explicitly
  <run>.txt                one per run: "# key value…" header lines (method, dims, k, heat, reg,
                           standardize, eigenvalues, trustworthiness, continuity, stress, jump),
                           then the expected map, one row per frame. Axes follow MotionMap's sign
                           convention (the entry of largest |value| in each column is positive).

Independent references: sklearn PCA / StandardScaler / TruncatedSVD, numpy eigh of classical
MDS's B, scipy shortest_path on the symmetric k-NN graph, scipy.linalg.eigh(L, Deg) for the
Laplacian eigenmap, sklearn's barycenter weights + dense null space for LLE (with neighbours from
D), sklearn.manifold.trustworthiness. Cross-checks against sklearn's Isomap and
LocallyLinearEmbedding run where their neighbours are the same (D Euclidean, no ties).
"""
import os
import sys
from dataclasses import dataclass, field
from typing import Optional

import numpy as np
import scipy.linalg
from scipy.sparse.csgraph import connected_components, csgraph_from_dense, shortest_path
from sklearn.datasets import make_s_curve, make_swiss_roll
from sklearn.decomposition import PCA, TruncatedSVD
from sklearn.manifold import Isomap, LocallyLinearEmbedding, trustworthiness
from sklearn.preprocessing import StandardScaler

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "fixtures")


# ----------------------------------------------------------------------------------------------
# Cases


@dataclass
class Run:
    method: str  # pca svd mds isomap le lle
    label: str = ""  # file name; default = method
    heat: Optional[float] = None  # le: None = auto
    standardize: bool = False  # pca
    dims: Optional[int] = None  # default: the case's


@dataclass
class Case:
    name: str
    X: np.ndarray
    D: Optional[np.ndarray]  # None = Euclidean distances of X
    k: int
    dims: int = 2
    reg: float = 1e-3
    runs: list = field(default_factory=list)
    ties: bool = False  # duplicate frames: skip the sklearn cross-checks (tie-breaking differs)
    meta: list = field(default_factory=list)  # extra X.txt header lines (clip cases: source…)


def euclidean(X):
    """Pairwise distances summed one column at a time, in column order, then sqrt: the same
    floating-point operations as tests/embed's C++ code, so both get identical bits."""
    n = X.shape[0]
    s = np.zeros((n, n))
    for c in range(X.shape[1]):
        diff = X[:, c][:, None] - X[:, c][None, :]
        s += diff * diff
    return np.sqrt(s)


def all_runs(extra=()):
    return [Run("pca"), Run("svd"), Run("mds"), Run("isomap"), Run("le"), Run("lle"), *extra]


def make_cases():
    cases = []
    # A noisy swiss roll, padded with two low-noise columns and a constant one (for correlation
    # PCA's constant-column rule).
    roll, _ = make_swiss_roll(n_samples=300, noise=0.05, random_state=0)
    rng = np.random.default_rng(1)
    X = np.hstack([roll, 0.05 * rng.standard_normal((300, 2)), np.full((300, 1), 3.0)])
    cases.append(Case("swiss_roll", X, None, k=10,
                      runs=all_runs([Run("pca", "pca_std", standardize=True),
                                     Run("le", "le_heat", heat=20.0),
                                     Run("le", "le_unit", heat=0.0)])))
    # An S-curve mapped to 3-D.
    curve, _ = make_s_curve(n_samples=250, noise=0.02, random_state=2)
    X = np.hstack([curve, 0.1 * np.random.default_rng(4).standard_normal((250, 3))])
    cases.append(Case("s_curve_3d", X, None, k=12, dims=3, runs=all_runs()))
    # A smooth closed trajectory like one cycle of a periodic motion: 12 "joint angles", each a
    # sum of the first two harmonics with its own phases, plus a little noise.
    t = np.arange(240) / 240.0
    rng = np.random.default_rng(3)
    cols = []
    for j in range(12):
        a, b = 1.0 / (1 + 0.3 * j), 0.4 / (1 + 0.2 * j)
        p, q = rng.uniform(0, 2 * np.pi, 2)
        cols.append(a * np.sin(2 * np.pi * t + p) + b * np.sin(4 * np.pi * t + q))
    X = np.array(cols).T + 0.01 * rng.standard_normal((240, 12))
    cases.append(Case("closed_loop", X, None, k=8,
                      runs=all_runs([Run("pca", "pca_std", standardize=True)])))
    # Duplicate frames (a held pose repeats frames exactly): 60 poses on a curve, each twice,
    # some three times. Small (120 frames), so the C++ side takes its dense eigen path. The graph
    # methods map the 60 distinct poses (graph_map).
    s = np.linspace(0, 3, 60)
    poses = np.stack([np.cos(s), np.sin(1.5 * s), 0.5 * s, 0.2 * np.cos(3 * s)], axis=1)
    reps = [3 if i % 10 == 0 else 2 for i in range(60)]
    X = np.repeat(poses, reps, axis=0)[:120]
    cases.append(Case("duplicates", X, None, k=6, ties=True, runs=all_runs()))
    return cases


# ----------------------------------------------------------------------------------------------
# Reference implementations


def flip_signs(Y):
    """MotionMap's convention: the first entry of largest |value| in each column is positive."""
    Y = np.array(Y, dtype=float)
    for c in range(Y.shape[1]):
        r = np.argmax(np.abs(Y[:, c]))
        if Y[r, c] < 0:
            Y[:, c] = -Y[:, c]
    return Y + 0.0


def knn_lists(D, k):
    """k nearest by D, self excluded, ties to the smaller index (stable argsort)."""
    n = D.shape[0]
    out = np.empty((n, k), dtype=int)
    for i in range(n):
        row = D[:, i].copy()
        row[i] = np.inf
        out[i] = np.argsort(row, kind="stable")[:k]
    return out


def knn_graph(D, lists):
    """Dense symmetric k-NN graph: inf = no edge, else the lower-triangle length."""
    n = D.shape[0]
    G = np.full((n, n), np.inf)
    for i in range(n):
        for j in lists[i]:
            length = D[max(i, j), min(i, j)]
            G[i, j] = G[j, i] = length
    return G


def check_connected(G, name):
    ncomp, _ = connected_components(csgraph_from_dense(G, null_value=np.inf), directed=False)
    if ncomp != 1:
        sys.exit(f"{name}: the k-NN graph has {ncomp} components; pick a larger k")


def classical_mds(T, dims):
    n = T.shape[0]
    L = np.tril(T)
    S = (L + L.T) ** 2
    J = np.eye(n) - np.ones((n, n)) / n
    B = -0.5 * J @ S @ J
    w, V = np.linalg.eigh(B)
    w, V = w[::-1][:dims], V[:, ::-1][:, :dims]
    return V * np.sqrt(np.maximum(w, 0)), w


def ref_pca(X, dims, standardize):
    Z = StandardScaler().fit_transform(X) if standardize else X
    pca = PCA(dims, svd_solver="full").fit(Z)
    return pca.transform(Z), pca.explained_variance_


def ref_svd(X, dims):
    svd = TruncatedSVD(dims, algorithm="arpack", tol=0.0).fit(X)
    Y = svd.transform(X)
    # Cross-check with numpy's full SVD.
    U, s, Vt = np.linalg.svd(X, full_matrices=False)
    assert procrustes(Y, X @ Vt[:dims].T) < 1e-20
    return Y, s[:dims] ** 2


def ref_isomap(D, k, dims):
    G = knn_graph(D, knn_lists(D, k))
    geo = shortest_path(csgraph_from_dense(G, null_value=np.inf), method="D", directed=False)
    Y, w = classical_mds(geo, dims)
    return Y, w, geo


def auto_heat(D, lists):
    sq = np.array([D[j, i] ** 2 for i in range(D.shape[0]) for j in lists[i]])
    m = np.median(sq)
    if m == 0 and np.any(sq > 0):
        m = np.median(sq[sq > 0])
    return m


def ref_le(D, k, heat, dims):
    lists = knn_lists(D, k)
    G = knn_graph(D, lists)
    if heat is None:
        heat = auto_heat(D, lists)
    W = np.where(np.isfinite(G), np.exp(-G ** 2 / heat) if heat > 0 else 1.0, 0.0)
    Deg = np.diag(W.sum(axis=1))
    L = Deg - W
    w, V = scipy.linalg.eigh(L, Deg)  # Vᵀ·Deg·V = I
    return V[:, 1:dims + 1], w[1:dims + 1], heat


def barycenter_weights(X, lists, reg):
    """sklearn.manifold._locally_linear.barycenter_weights with given neighbour lists."""
    n, k = lists.shape
    B = np.empty((n, k))
    v = np.ones(k)
    for i, ind in enumerate(lists):
        C = X[ind] - X[i]
        G = C @ C.T
        trace = np.trace(G)
        G.flat[:: k + 1] += reg * trace if trace > 0 else reg
        w = scipy.linalg.solve(G, v, assume_a="pos")
        B[i] = w / np.sum(w)
    return B


def ref_lle(X, D, k, reg, dims):
    lists = knn_lists(D, k)
    n = X.shape[0]
    W = np.zeros((n, n))
    B = barycenter_weights(X, lists, reg)
    for i in range(n):
        W[i, lists[i]] = B[i]
    A = np.eye(n) - W
    M = A.T @ A
    w, V = scipy.linalg.eigh(M)
    return V[:, 1:dims + 1], w[1:dims + 1]


def stable_trustworthiness(Dx, Ye, k):
    """sklearn.manifold.trustworthiness(metric='precomputed') with ties broken by index in both
    spaces (sklearn leaves that to argsort / its tree); Dx: distances defining the ranks, the
    neighbours come from Ye (#frames by #frames distances too)."""
    n = Dx.shape[0]
    dx = Dx.copy()
    np.fill_diagonal(dx, np.inf)
    ind_x = np.argsort(dx, axis=1, kind="stable")
    de = Ye.copy()
    np.fill_diagonal(de, np.inf)
    ind_e = np.argsort(de, axis=1, kind="stable")[:, :k]
    inverted = np.zeros((n, n), dtype=int)
    ordered = np.arange(n + 1)
    inverted[ordered[:-1, None], ind_x] = ordered[1:]
    ranks = inverted[ordered[:-1, None], ind_e] - k
    t = np.sum(ranks[ranks > 0])
    return 1.0 - t * (2.0 / (n * k * (2.0 * n - 3.0 * k - 1.0)))


def map_distances(Y):
    return np.sqrt(((Y[:, None, :] - Y[None, :, :]) ** 2).sum(-1))


def quality(D, Y, ties, k=10):
    E = map_distances(Y)
    t = stable_trustworthiness(D, E, k)
    c = stable_trustworthiness(E, D, k)  # continuity: the roles swapped
    if not ties:
        t_sk = trustworthiness(D, Y, n_neighbors=k, metric="precomputed")
        assert abs(t - t_sk) < 1e-12, (t, t_sk)
    return t, c


def normalized_stress(T, Y):
    iu = np.tril_indices(T.shape[0], -1)
    t = T[iu]
    e = map_distances(Y)[iu]
    s = np.dot(t, e) / np.dot(e, e)
    return np.sqrt(np.sum((t - s * e) ** 2) / np.sum(t * t))


def jump_score(Y):
    steps = np.linalg.norm(np.diff(Y, axis=0), axis=1)
    med, p95 = np.median(steps), np.percentile(steps, 95)
    if med == 0:
        return 1.0 if p95 == 0 else np.inf  # as motionmap::embed::jump_score
    return p95 / med


def procrustes(A, B):
    """scipy.spatial.procrustes disparity (orthogonal Procrustes with scaling)."""
    A = A - A.mean(0)
    B = B - B.mean(0)
    A = A / np.linalg.norm(A)
    B = B / np.linalg.norm(B)
    u, s, vt = np.linalg.svd(B.T @ A)
    R = u @ vt
    return np.sum((A - B @ R * s.sum()) ** 2)


# ----------------------------------------------------------------------------------------------
# Writing


def fmt(values):
    return " ".join("%.17g" % v for v in np.ravel(values))


def write_matrix(path, M, header=()):
    with open(path, "w") as f:
        for line in header:
            f.write("# " + line + "\n")
        f.write("# %d %d\n" % M.shape)
        for row in M:
            f.write(fmt(row) + "\n")


REPEAT_TOLERANCE = 1e-6  # motionmap::embed::kRepeatTolerance


def distinct_poses(D):
    """The graph methods' repeated poses (embed/detail/distinct.h): frame f repeats the earliest
    first occurrence r < f with D[r, f] <= 1e-6 * sqrt(sum D^2 / (2 n^2)); returns the first
    occurrences and every frame's pose (an index into them)."""
    n = D.shape[0]
    tol = REPEAT_TOLERANCE * np.sqrt(np.sum(D * D) / (2.0 * n * n))
    first, pose_of = [], np.zeros(n, dtype=int)
    for f in range(n):
        near = [p for p, r in enumerate(first) if D[r, f] <= tol]
        if near:
            pose_of[f] = near[0]  # first occurrences are in frame order
        else:
            pose_of[f] = len(first)
            first.append(f)
    return np.array(first), pose_of


def graph_map(method, X, D, k, run, case, dims):
    """isomap, le or lle on the distinct poses (each once, k capped at their number - 1), every
    frame given its pose's place, as MotionMap maps frames that repeat poses."""
    first, pose_of = distinct_poses(D)
    if len(first) < len(D) and len(first) >= dims + 2:
        Y, w, extra = graph_map(method, X[first], D[np.ix_(first, first)],
                                min(k, len(first) - 1), run, case, dims)
        return Y[pose_of], w, extra
    if method == "isomap":
        Y, w, geo = ref_isomap(D, k, dims)
        return Y, w, normalized_stress(geo, Y)
    if method == "le":
        Y, w, heat = ref_le(D, k, run.heat, dims)
        return Y, w, heat
    return (*ref_lle(X, D, k, case.reg, dims), None)


def run_case(case):
    X = np.asarray(case.X, dtype=float)
    D = euclidean(X) if case.D is None else np.asarray(case.D, dtype=float)
    folder = os.path.join(OUT, case.name)
    os.makedirs(folder, exist_ok=True)
    write_matrix(os.path.join(folder, "X.txt"), X, case.meta)
    if case.D is not None:
        write_matrix(os.path.join(folder, "D.txt"), D)
    check_connected(knn_graph(D, knn_lists(D, case.k)), case.name)
    for run in case.runs:
        dims = run.dims or case.dims
        header = ["method " + run.method, "dims %d" % dims, "k %d" % case.k]
        stress = None
        if run.method == "pca":
            Y, w = ref_pca(X, dims, run.standardize)
            header.append("standardize %d" % run.standardize)
        elif run.method == "svd":
            Y, w = ref_svd(X, dims)
        elif run.method == "mds":
            Y, w = classical_mds(D, dims)
            stress = normalized_stress(D, Y)
        elif run.method == "isomap":
            Y, w, stress = graph_map("isomap", X, D, case.k, run, case, dims)
            if not case.ties:
                sk = Isomap(n_neighbors=case.k, n_components=dims, metric="precomputed",
                            eigen_solver="dense").fit_transform(D)
                assert procrustes(Y, sk) < 1e-12, procrustes(Y, sk)
        elif run.method == "le":
            Y, w, heat = graph_map("le", X, D, case.k, run, case, dims)
            header.append("heat %s" % ("auto" if run.heat is None else "%.17g" % run.heat))
            header.append("heat_used %.17g" % max(heat, 0.0))
        elif run.method == "lle":
            Y, w, _ = graph_map("lle", X, D, case.k, run, case, dims)
            header.append("reg %.17g" % case.reg)
            if not case.ties and case.D is None:
                sk = LocallyLinearEmbedding(n_neighbors=case.k, n_components=dims, reg=case.reg,
                                            eigen_solver="dense").fit_transform(X)
                assert procrustes(Y, sk) < 1e-12, procrustes(Y, sk)
        else:
            raise ValueError(run.method)
        Y = flip_signs(Y)
        t, c = quality(D, Y, case.ties)
        header += ["eigenvalues " + fmt(w), "trustworthiness %.17g" % t, "continuity %.17g" % c,
                   "jump %.17g" % jump_score(Y)]
        if stress is not None:
            header.append("stress %.17g" % stress)
        write_matrix(os.path.join(folder, (run.label or run.method) + ".txt"), Y, header)
        print(f"{case.name}/{run.label or run.method}: trust {t:.4f} continuity {c:.4f}")


def clip_cases(sample_bvh):
    """The built-in sample swing and CMU 64_08 (every 4th frame, the T-pose left out), k = 20."""
    import mocap
    shared = os.path.join(HERE, "..", "..", "..", "shared", "data")
    sources = [("clip_cmu_64_08", os.path.join(shared, "cmu", "64_08.bvh"), "cmu/64_08.bvh")]
    if sample_bvh:
        sources.append(("clip_sample_swing", sample_bvh, "sample:swing"))
    else:
        print("no --sample BVH given: clip_sample_swing left as it is")
    cases = []
    for name, path, source in sources:
        X, D, rows = mocap.map_inputs(path, stride=4)
        meta = ["source " + source, "stride 4", "frames " + " ".join(str(int(r)) for r in rows)]
        cases.append(Case(name, X, D, k=20, runs=all_runs(), meta=meta))
    return cases


def main():
    sample = sys.argv[sys.argv.index("--sample") + 1] if "--sample" in sys.argv else None
    for case in make_cases() + clip_cases(sample):
        run_case(case)


if __name__ == "__main__":
    main()
