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

  sparse_start.txt, sparse_random.txt
               the sparse model's objective (embed/gplvm.h: Titsias's collapsed bound, eps =
               1e-8 sf2, s = sn2 + eps, K_uu = k(Z, Z) + eps I, Q = K_fu K_uu^-1 K_uf):

    L_s = D/2 log|Q + sI| + 1/2 tr((Q + sI)^-1 Y Y^T) + N D/2 log 2pi + D/(2s)(N(sf2 + sb2) - tr Q)
          + 1/2 |X|^2 + N q/2 log 2pi

               computed densely (the N x N matrix Q + sI, unlike MotionMap's M x M form), and its
               gradients by complex-step differentiation (Im L(p + i h e_j) / h, h = 1e-30:
               exact to rounding, and independent of MotionMap's analytic derivation), at X, Z =
               rows SPARSE_ROWS of X perturbed by seeded noise, theta: header theta, objective,
               grad_theta, rows; matrix [X | dL/dX] over [Z | dL/dZ] (N + M rows)

  optimum.txt  the fit's optimum by scipy's L-BFGS-B (gtol 1e-10, ftol 1e-16) on every 2nd row of
               Y (CMU 64_08 every 8th frame: 46 frames), from its start (as start.txt's, for those
               rows) over X and (log sf2, log sb2, log sn2), the lengthscale held at 1 (as
               fit_gplvm with fit_lengthscale false): header theta_start, theta, objective, iterations;
               matrix [X0 | X*]. The objective has a rotation of the latent plane as a symmetry,
               so maps are compared by Procrustes. With the lengthscale fitted too there is no
               optimum: (X, l) -> (cX, cl) leaves the likelihood as it is and lowers |X|^2/2, so X
               and l slide towards 0 (scipy: 14 587 iterations on the 91 frames, log sn2 = -12.4
               and still falling).
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


SPARSE_ROWS = [0, 7, 15, 22, 31, 40, 48, 57, 66, 75, 83, 90]


def kernel(A, B, sf2, l, sb2):
    """k(a, b) without the noise; analytic in every argument (complex-step safe)."""
    R2 = np.sum((A[:, None, :] - B[None, :, :]) ** 2, axis=2)
    return sf2 * np.exp(-R2 / (2 * l * l)) + sb2


def cholesky(A):
    """The lower Cholesky factor without conjugation (numpy's would conjugate a complex A)."""
    n = A.shape[0]
    L = np.zeros_like(A)
    for j in range(n):
        d = A[j, j] - np.sum(L[j, :j] * L[j, :j])
        L[j, j] = np.sqrt(d)
        L[j + 1:, j] = (A[j + 1:, j] - L[j + 1:, :j] @ L[j, :j]) / L[j, j]
    return L


def sparse_objective(Y, X, Z, theta):
    N, D = Y.shape
    q = X.shape[1]
    sf2, l, sb2, sn2 = np.exp(theta[0]), np.exp(theta[1]), np.exp(theta[2]), np.exp(theta[3])
    eps = JITTER * sf2
    s = sn2 + eps
    Kfu = kernel(X, Z, sf2, l, sb2)
    Kuu = kernel(Z, Z, sf2, l, sb2) + eps * np.eye(Z.shape[0])
    Q = Kfu @ np.linalg.solve(Kuu, Kfu.T)
    C = Q + s * np.eye(N)
    logdet = 2 * np.sum(np.log(np.diag(cholesky(C))))
    t = N * (sf2 + sb2)
    return (0.5 * D * logdet + 0.5 * np.sum(Y * np.linalg.solve(C, Y))
            + 0.5 * N * D * np.log(2 * np.pi) + 0.5 * D / s * (t - np.trace(Q))
            + 0.5 * np.sum(X * X) + 0.5 * N * q * np.log(2 * np.pi))


def complex_step_gradient(f, p, h=1e-30):
    g = np.zeros(p.size)
    for j in range(p.size):
        pc = p.astype(complex)
        pc[j] += 1j * h
        g[j] = f(pc).imag / h
    return g


def sparse_fixture(name, Y, X, Z, theta):
    N, q = X.shape
    M = Z.shape[0]

    def f(p):
        return sparse_objective(Y, p[:N * q].reshape(N, q), p[N * q:N * q + M * q].reshape(M, q),
                                p[N * q + M * q:])
    p = np.concatenate([X.ravel(), Z.ravel(), theta])
    L = sparse_objective(Y, X, Z, theta)
    g = complex_step_gradient(f, p)
    dX = g[:N * q].reshape(N, q)
    dZ = g[N * q:N * q + M * q].reshape(M, q)
    write(name, [("theta", fmt(theta)), ("objective", "%.17g" % L),
                 ("grad_theta", fmt(g[N * q + M * q:])), ("rows", "%d %d" % (N, M))],
          np.vstack([np.hstack([X, dX]), np.hstack([Z, dZ])]))


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
    # The sparse model: 12 inducing inputs near rows of X.
    Z0 = X0[SPARSE_ROWS] + rng.normal(scale=0.05, size=(len(SPARSE_ROWS), 2))
    sparse_fixture("sparse_start.txt", Y, X0, Z0, theta0)
    Zr = Xr[SPARSE_ROWS] + rng.normal(scale=0.3, size=(len(SPARSE_ROWS), 2))
    sparse_fixture("sparse_random.txt", Y, Xr, Zr, thetar)
    optimum_fixture(Y[::2] - Y[::2].mean(axis=0))


def optimum_fixture(Y):
    from scipy.optimize import minimize
    X0, theta0 = start(Y)
    for a in range(2):
        if X0[np.argmax(np.abs(X0[:, a])), a] < 0:
            X0[:, a] = -X0[:, a]
    N, q = X0.shape
    fitted = [0, 2, 3]  # log sf2, log sb2, log sn2; log l stays at theta0[1] = 0

    def f(p):
        theta = theta0.copy()
        theta[fitted] = p[N * q:]
        L, dX, dtheta = objective(Y, p[:N * q].reshape(N, q), theta)
        return L, np.concatenate([dX.ravel(), dtheta[fitted]])
    r = minimize(f, np.concatenate([X0.ravel(), theta0[fitted]]), jac=True, method="L-BFGS-B",
                 options=dict(maxiter=50000, maxfun=100000, gtol=1e-10, ftol=1e-16))
    theta = theta0.copy()
    theta[fitted] = r.x[N * q:]
    write("optimum.txt", [("theta_start", fmt(theta0)), ("theta", fmt(theta)),
                          ("objective", "%.17g" % r.fun), ("iterations", "%d" % r.nit)],
          np.hstack([X0, r.x[:N * q].reshape(N, q)]))


if __name__ == "__main__":
    main()
