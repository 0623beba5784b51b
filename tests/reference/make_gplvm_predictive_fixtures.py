#!/usr/bin/python3
"""Reference numbers for the GP-LVM's predictive mean and variance read as a map
(embed::GplvmMap, tests/embed/gplvm_map_test.cpp), from an independent dense numpy
implementation, written to tests/reference/gplvm/predictive.txt and predictive_sparse.txt.

    /usr/bin/python3 tests/reference/make_gplvm_predictive_fixtures.py

Y is tests/reference/fixtures/clip_cmu_64_08/X.txt (CMU 64_08 every 4th frame: 91 frames of
per-joint quaternion features), its column mean m, centred. The latent points X and the kernel
theta = (log sf2, log l, log sb2, log sn2) are random.txt's (make_gplvm_fixtures.py). With
k(x) = sf2 exp(-|x - b|^2 / (2 l^2)) + sb2 over the basis points b, eps = 1e-8 sf2, s = sn2 + eps:

  full    mu(x) = k(x, X) K^-1 Y, K = k(X, X) + s I;  var(x) = sf2 + sb2 - k K^-1 k
  sparse  Z = X[SPARSE_ROWS], K_uu = k(Z, Z) + eps I, P = K_uu + K_uf K_fu / s,
          mu(x) = k(x, Z) P^-1 K_uf Y / s;  var(x) = sf2 + sb2 - k (K_uu^-1 - P^-1) k

(var without the noise s). Each row of the matrix is one query point x: [x (2) | var | mu(x) + m
(D) | mu(x) + m with each joint's 4 values normalised (D)]. The queries: the latent points of
frames 0, 30 and 60, the midpoints between frames 10 and 11 and between 45 and 46, a point a
lengthscale beside frame 20, and one far from every latent point.
"""
import os

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
JITTER = 1e-8
SPARSE_ROWS = [0, 7, 15, 22, 31, 40, 48, 57, 66, 75, 83, 90]


def read(path):
    header, rows = {}, []
    with open(path) as f:
        for line in f:
            if line.startswith("#"):
                parts = line[1:].split()
                if parts and not parts[0][0].isdigit():
                    header[parts[0]] = parts[1:]
                continue
            if line.strip():
                rows.append([float(v) for v in line.split()])
    return header, np.array(rows)


def kern(A, B, sf2, l, sb2):
    d2 = np.sum((A[:, None, :] - B[None, :, :]) ** 2, axis=2)
    return sf2 * np.exp(-d2 / (2 * l * l)) + sb2


def main():
    _, F = read(os.path.join(HERE, "fixtures", "clip_cmu_64_08", "X.txt"))
    mean = F.mean(axis=0)
    Y = F - mean
    header, R = read(os.path.join(HERE, "gplvm", "random.txt"))
    theta = np.array([float(v) for v in header["theta"]])
    X = R[:, :2]
    sf2, l, sb2, sn2 = np.exp(theta)
    eps = JITTER * sf2
    s = sn2 + eps
    l_ = l
    queries = [X[0], X[30], X[60], 0.5 * (X[10] + X[11]), 0.5 * (X[45] + X[46]),
               X[20] + np.array([l_, 0.0]), X.max(axis=0) + 10 * l_]
    Q = np.array(queries)
    for name, sparse in (("predictive.txt", False), ("predictive_sparse.txt", True)):
        if sparse:
            Z = X[SPARSE_ROWS]
            Kuu = kern(Z, Z, sf2, l, sb2) + eps * np.eye(len(Z))
            Kuf = kern(Z, X, sf2, l, sb2)
            P = Kuu + Kuf @ Kuf.T / s
            alpha = np.linalg.solve(P, Kuf @ Y) / s
            Cm = np.linalg.inv(Kuu) - np.linalg.inv(P)
            basis = Z
        else:
            K = kern(X, X, sf2, l, sb2) + s * np.eye(len(X))
            alpha = np.linalg.solve(K, Y)
            Cm = np.linalg.inv(K)
            basis = X
        k = kern(Q, basis, sf2, l, sb2)
        mu = k @ alpha + mean
        var = sf2 + sb2 - np.einsum("ij,jk,ik->i", k, Cm, k)
        norm = mu.reshape(len(Q), -1, 4)
        norm = (norm / np.linalg.norm(norm, axis=2, keepdims=True)).reshape(len(Q), -1)
        M = np.hstack([Q, var[:, None], mu, norm])
        with open(os.path.join(HERE, "gplvm", name), "w") as f:
            f.write("# theta %s\n" % " ".join("%.17g" % v for v in theta))
            if sparse:
                f.write("# inducing_rows %s\n" % " ".join(str(r) for r in SPARSE_ROWS))
            f.write("# %d %d\n" % M.shape)
            for row in M:
                f.write(" ".join("%.17g" % v for v in row) + "\n")


if __name__ == "__main__":
    main()
