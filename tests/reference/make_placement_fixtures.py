#!/usr/bin/python3
"""Reference results for the points path and placement (tests/embed/placement_reference_test.cpp),
recomputed independently with numpy / scipy, written under tests/reference/placement/<case>/.

Run with Debian's python:  /usr/bin/python3 tests/reference/make_placement_fixtures.py

Cases reuse make_fixtures.py's swiss roll and closed loop (X.txt is written again here). Each
case fits on its first `fit` rows and places the rest:
  lmds.txt       landmark MDS of the first `fit` rows (de Silva & Tenenbaum: max-min landmarks
                 from frame 0, classical MDS of the landmarks in up to 20 axes, triangulation,
                 then PCA of the triangulated frames), header "landmarks i j …"; then the
                 placement of the remaining rows by the same triangulation.
  le_nystrom.txt the Laplacian eigenmap of the first `fit` rows (scipy.linalg.eigh(L, Deg)) and
                 the Nyström extension (Bengio et al. 2004) of the remaining rows:
                 y(x) = Σ_s w_s·y_s ÷ ((1 − λ)·Σ_s w_s) over x's k nearest samples, w_s the heat
                 kernel exp(−d²/t).
Both: rows 0 … fit−1 are the fitted map, the rest the placed frames; MotionMap's sign convention
is applied to the fitted map and the same flips to the placed frames.
"""
import os

import numpy as np

import make_fixtures as mf

HERE = os.path.dirname(os.path.abspath(__file__))
AXES = 20


def distances_to(X, rows):
    """Euclidean distances from each of X[rows] to every row of X: len(rows) by #rows."""
    return np.sqrt(((X[rows][:, None, :] - X[None, :, :]) ** 2).sum(axis=2))


def maxmin(X, count):
    landmarks, nearest = [0], np.full(X.shape[0], np.inf)
    for _ in range(count):
        nearest = np.minimum(nearest, distances_to(X, [landmarks[-1]])[0])
        if len(landmarks) == count:
            break
        landmarks.append(int(np.argmax(nearest)))
    return landmarks


def landmark_mds(X_fit, X_new, count, dims):
    lm = maxmin(X_fit, count)
    T = distances_to(X_fit, lm)[:, lm]
    S = T ** 2
    mu = S.mean(axis=0)
    J = np.eye(count) - 1.0 / count
    w, V = np.linalg.eigh(-0.5 * J @ S @ J)
    w, V = w[::-1], V[:, ::-1]
    r = min(count - 1, max(dims, AXES))
    kept = int(np.sum(w[:r] > 1e-12 * max(w[0], 0)))
    P = (V[:, :kept] / np.sqrt(w[:kept])).T

    def triangulate(X):
        delta = np.sqrt(((X[:, None, :] - X_fit[lm][None, :, :]) ** 2).sum(axis=2))
        return -0.5 * (delta ** 2 - mu) @ P.T

    Z = triangulate(X_fit)
    mean = Z.mean(axis=0)
    e, W = np.linalg.eigh((Z - mean).T @ (Z - mean))
    W = W[:, ::-1][:, :dims]
    fit = (Z - mean) @ W
    new = (triangulate(X_new) - mean) @ W
    return fit, new, lm


def le_nystrom(X_fit, X_new, k, dims):
    D = mf.euclidean(X_fit)
    Y, lam, heat = mf.ref_le(D, k, None, dims)
    new = np.empty((X_new.shape[0], dims))
    for i, x in enumerate(X_new):
        d = np.sqrt(((X_fit - x) ** 2).sum(axis=1))
        nb = np.argsort(d, kind="stable")[:k]
        w = np.exp(-(d[nb] ** 2 - d[nb[0]] ** 2) / heat)
        new[i] = (w @ Y[nb]) / (w.sum() * (1.0 - lam))
    return Y, new, heat


def flip_together(fit, new):
    signs = np.ones(fit.shape[1])
    for c in range(fit.shape[1]):
        if fit[np.argmax(np.abs(fit[:, c])), c] < 0:
            signs[c] = -1.0
    return fit * signs + 0.0, new * signs + 0.0


def main():
    for case in mf.make_cases():
        if case.name not in ("swiss_roll", "closed_loop"):
            continue
        X = np.asarray(case.X, dtype=float)
        fit_rows = X.shape[0] - 40
        folder = os.path.join(HERE, "placement", case.name)
        os.makedirs(folder, exist_ok=True)
        mf.write_matrix(os.path.join(folder, "X.txt"), X, ["fit %d" % fit_rows])
        fit, new, lm = landmark_mds(X[:fit_rows], X[fit_rows:], 30, 2)
        fit, new = flip_together(fit, new)
        mf.write_matrix(os.path.join(folder, "lmds.txt"), np.vstack([fit, new]),
                        ["method mds", "dims 2", "fit %d" % fit_rows, "count 30",
                         "landmarks " + " ".join(str(i) for i in lm)])
        fit, new, heat = le_nystrom(X[:fit_rows], X[fit_rows:], case.k, 2)
        fit, new = flip_together(fit, new)
        mf.write_matrix(os.path.join(folder, "le_nystrom.txt"), np.vstack([fit, new]),
                        ["method le", "dims 2", "fit %d" % fit_rows, "k %d" % case.k,
                         "heat %.17g" % heat])


if __name__ == "__main__":
    main()
