#!/usr/bin/python3
"""Reference numbers for MotionMap's GP-LVM (tests/embed/gplvm_test.cpp), from an independent
numpy implementation of the full model's objective and gradients and scipy's L-BFGS-B, written
under tests/reference/gplvm/.

    /usr/bin/python3 tests/reference/make_gplvm_fixtures.py

Y is tests/reference/fixtures/clip_cmu_64_08/X.txt (CMU 64_08 every 4th frame: 91 frames of
quaternion features, read from the BVH by tests/reference/mocap.py), centred. The objective is
embed/gplvm.h's: the kernel k(x, x') = sf2 exp(-|x - x'|^2 / (2 l^2)) + sb2 + (sn2 + 1e-8 sf2)
[x = x'], latent prior N(0, I), and

    L = D/2 log|K| + 1/2 tr(K^-1 Y Y^T) + N D/2 log 2pi + 1/2 |X|^2 + N q/2 log 2pi,

over X and theta = (log sf2, log l, log sb2, log sn2). Files ("# key value..." header lines, then
"# rows cols" and the matrix):

  start.txt    at X0 = the PCA scores of Y scaled to unit variance per axis and the starting
               kernel (sf2 = mean column variance of Y, l = 1, sb2 = 1e-3 sf2, sn2 = 0.1 sf2):
               header theta, objective, grad_theta; matrix [X0 | dL/dX]
  random.txt   the same at a seeded random X and theta

Not written: a common optimum. On this clip (D = 120 features ≥ N = 91 frames) the likelihood has
none: the noise variance falls towards 0 and the lengthscale with it (scipy's L-BFGS-B, 14 587
iterations from the start below: log sn2 = -12.4 and falling), as MotionMap's fit does.
"""
import os

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
JITTER = 1e-8


def read_matrix(path):
    rows = []
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            rows.append([float(v) for v in line.split()])
    return np.array(rows)


def objective(Y, X, theta):
    """(L, dL/dX, dL/dtheta) by the formulas in the docstring, written independently."""
    N, D = Y.shape
    q = X.shape[1]
    sf2, l, sb2, sn2 = np.exp(theta[0]), np.exp(theta[1]), np.exp(theta[2]), np.exp(theta[3])
    diff = X[:, None, :] - X[None, :, :]
    R2 = np.sum(diff ** 2, axis=2)
    Krbf = sf2 * np.exp(-R2 / (2 * l * l))
    K = Krbf + sb2 + (sn2 + JITTER * sf2) * np.eye(N)
    C = np.linalg.cholesky(K)
    Kinv = np.linalg.inv(K)
    A = Kinv @ Y
    logdet = 2 * np.sum(np.log(np.diag(C)))
    L = (0.5 * D * logdet + 0.5 * np.sum(Y * A) + 0.5 * N * D * np.log(2 * np.pi)
         + 0.5 * np.sum(X * X) + 0.5 * N * q * np.log(2 * np.pi))
    G = 0.5 * (D * Kinv - A @ A.T)  # dL/dK
    # dK_ij/dx_i = -Krbf_ij (x_i - x_j) / l^2, and K is symmetric: dL/dx_i = 2 sum_j G_ij dK_ij/dx_i.
    dX = np.einsum("ij,ijk->ik", 2 * G * Krbf, -diff / (l * l)) + X
    dtheta = np.array([
        np.sum(G * Krbf) + JITTER * sf2 * np.trace(G),
        np.sum(G * Krbf * R2) / (l * l),
        sb2 * np.sum(G),
        sn2 * np.trace(G),
    ])
    return L, dX, dtheta


def start(Y):
    U, S, Vt = np.linalg.svd(Y, full_matrices=False)
    X0 = U[:, :2] * S[:2]
    X0 = X0 / np.sqrt(np.sum(X0 ** 2, axis=0) / (Y.shape[0] - 1))
    var = np.sum(Y ** 2) / (Y.shape[0] - 1) / Y.shape[1]
    theta = np.log([var, 1.0, 1e-3 * var, 1e-1 * var])
    return X0, theta


def fmt(values):
    return " ".join("%.17g" % v for v in values)


def write(name, header, M):
    with open(os.path.join(HERE, "gplvm", name), "w") as f:
        for key, value in header:
            f.write("# %s %s\n" % (key, value))
        f.write("# %d %d\n" % M.shape)
        for row in M:
            f.write(fmt(row) + "\n")


def main():
    os.makedirs(os.path.join(HERE, "gplvm"), exist_ok=True)
    Y = read_matrix(os.path.join(HERE, "fixtures", "clip_cmu_64_08", "X.txt"))
    Y = Y - Y.mean(axis=0)
    X0, theta0 = start(Y)
    # The PCA scores' signs are MotionMap's (largest |value| of each column positive).
    for a in range(2):
        if X0[np.argmax(np.abs(X0[:, a])), a] < 0:
            X0[:, a] = -X0[:, a]
    L, dX, dt = objective(Y, X0, theta0)
    write("start.txt", [("theta", fmt(theta0)), ("objective", "%.17g" % L),
                        ("grad_theta", fmt(dt))], np.hstack([X0, dX]))
    rng = np.random.default_rng(25)
    Xr = rng.normal(size=X0.shape)
    thetar = theta0 + rng.normal(scale=0.3, size=4)
    L, dX, dt = objective(Y, Xr, thetar)
    write("random.txt", [("theta", fmt(thetar)), ("objective", "%.17g" % L),
                         ("grad_theta", fmt(dt))], np.hstack([Xr, dX]))


if __name__ == "__main__":
    main()
