#include "motionmap/embed/gplvm.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <LBFGS.h>
#include <Eigen/Cholesky>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/embed/detail/methods.h"
#include "motionmap/embed/detail/progress.h"

namespace motionmap::embed {

namespace {

constexpr double kJitter = 1e-8;  // added to K's diagonal (relative to σ_f²), for rounding

Eigen::MatrixXd squared_distances(const Eigen::MatrixXd& X) {
  const Eigen::VectorXd n2 = X.rowwise().squaredNorm();
  Eigen::MatrixXd R2 = (-2.0 * X * X.transpose()).colwise() + n2;
  R2.rowwise() += n2.transpose();
  return R2.cwiseMax(0.0);
}

// |a_i − b_j|² (rows of A by rows of B).
Eigen::MatrixXd cross_squared_distances(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  Eigen::MatrixXd R2 = (-2.0 * A * B.transpose()).colwise() + A.rowwise().squaredNorm();
  R2.rowwise() += B.rowwise().squaredNorm().transpose();
  return R2.cwiseMax(0.0);
}

// The kernel without noise, σ_f² exp(−|a − b|²/(2ℓ²)) + σ_b², between the rows of A and B.
Eigen::MatrixXd rbf_bias(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, double sf2, double l2,
                         double sb2) {
  return (sf2 * (-0.5 / l2 * cross_squared_distances(A, B)).array().exp() + sb2).matrix();
}

// The sparse model's factors at inducing inputs Z and latent points X: K_uu + εI = L Lᵀ,
// A = L⁻¹K_uf and B = I + AAᵀ/s, which the predictive and the frames' weights are solved with.
struct SparseFactors {
  Eigen::LLT<Eigen::MatrixXd> Kuu;
  Eigen::MatrixXd A;
  Eigen::LLT<Eigen::MatrixXd> B;
};

// @throws NumericalError `not_pd` when K_uu or B is not positive definite.
SparseFactors sparse_factors(const Eigen::MatrixXd& Z, const Eigen::MatrixXd& X, double sf2,
                             double l2, double sb2, double eps, double s, const char* not_pd) {
  SparseFactors f;
  Eigen::MatrixXd Kuu = rbf_bias(Z, Z, sf2, l2, sb2);
  Kuu.diagonal().array() += eps;
  f.Kuu.compute(Kuu);
  if (f.Kuu.info() != Eigen::Success) throw NumericalError(not_pd);
  f.A = f.Kuu.matrixL().solve(rbf_bias(Z, X, sf2, l2, sb2));
  Eigen::MatrixXd B = f.A * f.A.transpose() / s;
  B.diagonal().array() += 1.0;
  f.B.compute(B);
  if (f.B.info() != Eigen::Success) throw NumericalError(not_pd);
  return f;
}

}  // namespace

double gplvm_objective(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& X,
                       const GplvmKernel& kernel, Eigen::MatrixXd* grad_X,
                       Eigen::VectorXd* grad_kernel) {
  const Eigen::Index N = Y.rows(), D = Y.cols(), q = X.cols();
  const double sf2 = std::exp(kernel.log_rbf_variance), l2 = std::exp(2 * kernel.log_lengthscale);
  const double sb2 = std::exp(kernel.log_bias_variance), sn2 = std::exp(kernel.log_noise_variance);
  const Eigen::MatrixXd R2 = squared_distances(X);
  const Eigen::MatrixXd Krbf = sf2 * (-0.5 / l2 * R2).array().exp().matrix();
  Eigen::MatrixXd K = Krbf.array() + sb2;
  K.diagonal().array() += sn2 + kJitter * sf2;
  const Eigen::LLT<Eigen::MatrixXd> llt(K);
  if (llt.info() != Eigen::Success || !K.allFinite()) {
    throw NumericalError("gplvm: the kernel matrix is not positive definite (σ_f² " +
                         std::to_string(sf2) + ", ℓ " + std::to_string(std::sqrt(l2)) + ", σ_n² " +
                         std::to_string(sn2) + ")");
  }
  const Eigen::MatrixXd A = llt.solve(Y);  // K⁻¹ Y
  const double log_det = 2.0 * llt.matrixLLT().diagonal().array().log().sum();
  const double two_pi = std::log(2.0 * std::numbers::pi);
  const double value = 0.5 * double(D) * log_det + 0.5 * Y.cwiseProduct(A).sum() +
                       0.5 * double(N * D) * two_pi + 0.5 * X.squaredNorm() +
                       0.5 * double(N * q) * two_pi;
  if (grad_X == nullptr && grad_kernel == nullptr) return value;

  // dL/dK = (D K⁻¹ − K⁻¹ Y Yᵀ K⁻¹) / 2.
  const Eigen::MatrixXd Kinv = llt.solve(Eigen::MatrixXd::Identity(N, N));
  const Eigen::MatrixXd G = 0.5 * (double(D) * Kinv - A * A.transpose());
  const Eigen::MatrixXd W = G.cwiseProduct(Krbf);
  if (grad_X != nullptr) {
    // dL/dx_i = Σ_j 2 G_ij ∂k_ij/∂x_i + x_i, ∂k_ij/∂x_i = −k_rbf(i, j) (x_i − x_j)/ℓ².
    const Eigen::VectorXd row_sums = W.rowwise().sum();
    *grad_X = (-2.0 / l2) * (row_sums.asDiagonal() * X - W * X) + X;
  }
  if (grad_kernel != nullptr) {
    grad_kernel->resize(4);
    (*grad_kernel)[0] = W.sum();
    (*grad_kernel)[1] = W.cwiseProduct(R2).sum() / l2;
    (*grad_kernel)[2] = sb2 * G.sum();
    // The jitter is σ_f²-relative: dK/dlog σ_f² = K_rbf + jitter·σ_f²·I.
    (*grad_kernel)[0] += kJitter * sf2 * G.trace();
    (*grad_kernel)[3] = sn2 * G.trace();
  }
  return value;
}

double sparse_gplvm_objective(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& X,
                              const Eigen::MatrixXd& Z, const GplvmKernel& kernel,
                              Eigen::MatrixXd* grad_X, Eigen::MatrixXd* grad_Z,
                              Eigen::VectorXd* grad_kernel) {
  const Eigen::Index N = Y.rows(), D = Y.cols(), q = X.cols(), M = Z.rows();
  const double sf2 = std::exp(kernel.log_rbf_variance), l2 = std::exp(2 * kernel.log_lengthscale);
  const double sb2 = std::exp(kernel.log_bias_variance), sn2 = std::exp(kernel.log_noise_variance);
  const double eps = kJitter * sf2, s = sn2 + eps;
  const Eigen::MatrixXd R2uf = cross_squared_distances(Z, X);  // M × N
  const Eigen::MatrixXd Kuf_rbf = sf2 * (-0.5 / l2 * R2uf).array().exp().matrix();
  const Eigen::MatrixXd Kuf = Kuf_rbf.array() + sb2;
  const Eigen::MatrixXd R2uu = squared_distances(Z);
  const Eigen::MatrixXd Kuu_rbf = sf2 * (-0.5 / l2 * R2uu).array().exp().matrix();
  Eigen::MatrixXd Kuu = Kuu_rbf.array() + sb2;
  Kuu.diagonal().array() += eps;
  const Eigen::LLT<Eigen::MatrixXd> llt(Kuu);
  if (llt.info() != Eigen::Success || !Kuu.allFinite() || !(s > 0.0)) {
    throw NumericalError(
        "gplvm: the inducing inputs' kernel matrix is not positive definite (σ_f² " +
        std::to_string(sf2) + ", ℓ " + std::to_string(std::sqrt(l2)) + ", σ_n² " +
        std::to_string(sn2) + ")");
  }
  const auto L = llt.matrixL();
  // Whitened by K_uu = L Lᵀ: A = L⁻¹ K_uf (M × N), Φ_w = A Aᵀ = L⁻¹ K_uf K_fu L⁻ᵀ,
  // B = I + Φ_w / s (so that P = K_uu + K_uf K_fu / s = L B Lᵀ and log|Q + sI| = log|B| + N log s),
  // Ψ_w = A Y, c = B⁻¹ Ψ_w (tr(Yᵀ K_fu P⁻¹ K_uf Y) = Ψ_w·c). A is solved for before it is squared:
  // L⁻¹ (K_uf K_fu) L⁻ᵀ, two solves of an M × M matrix, is not symmetric positive semi-definite to
  // rounding when K_uu is ill-conditioned (inducing inputs closer than ℓ/100 give cond(K_uu) ≈
  // 10⁹), and B then failed to factorise at steps the objective is defined at.
  const Eigen::MatrixXd A = L.solve(Kuf);
  Eigen::MatrixXd Phi_w = Eigen::MatrixXd::Zero(M, M);
  Phi_w.selfadjointView<Eigen::Lower>().rankUpdate(A);
  Phi_w.triangularView<Eigen::StrictlyUpper>() = Phi_w.transpose();
  Eigen::MatrixXd B = Phi_w / s;
  B.diagonal().array() += 1.0;
  const Eigen::LLT<Eigen::MatrixXd> lltB(B);
  if (lltB.info() != Eigen::Success || !B.allFinite()) {
    throw NumericalError(
        "gplvm: the sparse model's matrix I + K_uu⁻¹K_uf K_fu/s is not positive "
        "definite");
  }
  const Eigen::MatrixXd Psi_w = A * Y;
  const Eigen::MatrixXd c = lltB.solve(Psi_w);
  const double quad = Psi_w.cwiseProduct(c).sum();
  const double log_det_B = 2.0 * lltB.matrixLLT().diagonal().array().log().sum();
  const double yy = Y.squaredNorm();
  const double t = double(N) * (sf2 + sb2), trQ = A.squaredNorm();
  const double two_pi = std::log(2.0 * std::numbers::pi);
  const double dD = double(D), dN = double(N);
  const double value = 0.5 * dD * (log_det_B + dN * std::log(s)) + 0.5 * (yy / s - quad / (s * s)) +
                       0.5 * dN * dD * two_pi + 0.5 * dD / s * (t - trQ) + 0.5 * X.squaredNorm() +
                       0.5 * double(N * q) * two_pi;
  if (grad_X == nullptr && grad_Z == nullptr && grad_kernel == nullptr) return value;

  // dL/dP = L⁻ᵀ (D/2 B⁻¹ + c cᵀ/(2s²)) L⁻¹; dL/dK_uu and dL/dΦ (Φ = K_uf K_fu) likewise L⁻ᵀ·L⁻¹
  // of the "core" matrices below (the derivation: docs/methods/gplvm.md).
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(M, M);
  const Eigen::MatrixXd Bi = lltB.solve(I);
  const Eigen::MatrixXd cc = c * c.transpose();
  const Eigen::MatrixXd core_P = 0.5 * dD * Bi + cc / (2 * s * s);
  const Eigen::MatrixXd core_uu = 0.5 * dD * (Bi + B - 2 * I) + cc / (2 * s * s);
  const Eigen::MatrixXd core_Phi = 0.5 * dD / s * (Bi - I) + cc / (2 * s * s * s);
  auto unwhiten = [&](const Eigen::MatrixXd& C) {  // L⁻ᵀ C L⁻¹
    const Eigen::MatrixXd T = L.transpose().solve(C);
    return Eigen::MatrixXd(L.transpose().solve(T.transpose()).transpose());
  };
  Eigen::MatrixXd G_uu = unwhiten(core_uu);
  G_uu = 0.5 * (G_uu + G_uu.transpose()).eval();
  // dL/dK_uf = −P⁻¹K_uf Y Yᵀ/s² + 2 (dL/dΦ) K_uf = L⁻ᵀ (−c Yᵀ/s² + 2 core_Φ A).
  const Eigen::MatrixXd G_uf = L.transpose().solve(
      Eigen::MatrixXd((-1.0 / (s * s)) * (c * Y.transpose()) + 2.0 * core_Phi * A));
  const double dL_ds = 0.5 * dD * dN / s - 0.5 * yy / (s * s) + quad / (s * s * s) -
                       0.5 * dD / (s * s) * (t - trQ) - core_P.cwiseProduct(Phi_w).sum() / (s * s);
  const double dL_dt = 0.5 * dD / s;
  const Eigen::MatrixXd Wf = G_uf.cwiseProduct(Kuf_rbf);  // M × N
  const Eigen::MatrixXd Wu = G_uu.cwiseProduct(Kuu_rbf);  // M × M
  if (grad_X != nullptr) {
    const Eigen::VectorXd col_sums = Wf.colwise().sum().transpose();
    *grad_X = (1.0 / l2) * (Wf.transpose() * Z - col_sums.asDiagonal() * X) + X;
  }
  if (grad_Z != nullptr) {
    const Eigen::VectorXd f_sums = Wf.rowwise().sum(), u_sums = Wu.rowwise().sum();
    *grad_Z = (1.0 / l2) * (Wf * X - f_sums.asDiagonal() * Z) +
              (2.0 / l2) * (Wu * Z - u_sums.asDiagonal() * Z);
  }
  if (grad_kernel != nullptr) {
    grad_kernel->resize(4);
    // The jitter ε = 10⁻⁸σ_f² is in K_uu and s: d/dlog σ_f² reaches both.
    (*grad_kernel)[0] = Wf.sum() + Wu.sum() + eps * G_uu.trace() + dL_ds * eps + dL_dt * dN * sf2;
    (*grad_kernel)[1] = (Wf.cwiseProduct(R2uf).sum() + Wu.cwiseProduct(R2uu).sum()) / l2;
    (*grad_kernel)[2] = sb2 * (G_uf.sum() + G_uu.sum()) + dL_dt * dN * sb2;
    (*grad_kernel)[3] = dL_ds * sn2;
  }
  return value;
}

Eigen::MatrixXd gplvm_inducing_start(const Eigen::MatrixXd& X, int M) {
  const int N = static_cast<int>(X.rows());
  if (M < 1 || M > N) {
    throw ParameterError("gplvm: " + std::to_string(M) + " inducing points for " +
                         std::to_string(N) + " frames; give between 1 and the number of frames");
  }
  std::vector<int> index(static_cast<std::size_t>(N));
  for (int i = 0; i < N; ++i) index[std::size_t(i)] = i;
  std::mt19937 random(kGplvmInducingSeed);
  for (int i = 0; i < M; ++i) {
    const int j = i + static_cast<int>(random() % std::uint32_t(N - i));
    std::swap(index[std::size_t(i)], index[std::size_t(j)]);
  }
  std::sort(index.begin(), index.begin() + M);
  Eigen::MatrixXd Z(M, X.cols());
  for (int m = 0; m < M; ++m) Z.row(m) = X.row(index[std::size_t(m)]);
  return Z;
}

GplvmKernel initial_gplvm_kernel(const Eigen::MatrixXd& Y) {
  double variance = 0.0;
  if (Y.rows() > 1) {
    variance = (Y.rowwise() - Y.colwise().mean()).squaredNorm() / double(Y.rows() - 1) /
               double(std::max<Eigen::Index>(1, Y.cols()));
  }
  if (!(variance > 0.0) || !std::isfinite(variance)) variance = 1.0;
  GplvmKernel k;
  k.log_rbf_variance = std::log(variance);
  k.log_lengthscale = 0.0;
  k.log_bias_variance = std::log(1e-3 * variance);
  k.log_noise_variance = std::log(1e-1 * variance);
  return k;
}

namespace {

// The optimiser's coordinates: X row-major, Z row-major (the sparse model), then log σ_f², log ℓ
// (unless the lengthscale is held), log σ_b², log σ_n².
Eigen::VectorXd pack(const Eigen::MatrixXd& X, const Eigen::MatrixXd& Z, const GplvmKernel& k,
                     bool fit_lengthscale) {
  Eigen::VectorXd v(X.size() + Z.size() + (fit_lengthscale ? 4 : 3));
  Eigen::Index at = 0;
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    for (Eigen::Index a = 0; a < X.cols(); ++a) v[at++] = X(i, a);
  for (Eigen::Index i = 0; i < Z.rows(); ++i)
    for (Eigen::Index a = 0; a < Z.cols(); ++a) v[at++] = Z(i, a);
  v[at++] = k.log_rbf_variance;
  if (fit_lengthscale) v[at++] = k.log_lengthscale;
  v[at++] = k.log_bias_variance;
  v[at++] = k.log_noise_variance;
  return v;
}

void unpack(const Eigen::VectorXd& v, Eigen::MatrixXd& X, Eigen::MatrixXd& Z, GplvmKernel& k,
            bool fit_lengthscale) {
  Eigen::Index at = 0;
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    for (Eigen::Index a = 0; a < X.cols(); ++a) X(i, a) = v[at++];
  for (Eigen::Index i = 0; i < Z.rows(); ++i)
    for (Eigen::Index a = 0; a < Z.cols(); ++a) Z(i, a) = v[at++];
  k.log_rbf_variance = v[at++];
  if (fit_lengthscale) k.log_lengthscale = v[at++];
  k.log_bias_variance = v[at++];
  k.log_noise_variance = v[at++];
}

// Fresh starts of L-BFGS from the best point after a failed line search (fit_gplvm).
constexpr int kMaxRestarts = 50;

}  // namespace

GplvmFit fit_gplvm(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& X0, const GplvmKernel& kernel,
                   int max_iterations, const Control& control, const Eigen::MatrixXd* Z0,
                   bool fit_lengthscale) {
  if (X0.rows() != Y.rows() || X0.cols() < 1 || Y.rows() < 2 || Y.cols() < 1) {
    throw ParameterError("gplvm: latent points of " + std::to_string(X0.rows()) + " × " +
                         std::to_string(X0.cols()) + " for data of " + std::to_string(Y.rows()) +
                         " × " + std::to_string(Y.cols()) + ", expected N × q for N × D, N ≥ 2");
  }
  if (!Y.allFinite() || !X0.allFinite()) {
    throw ParameterError("gplvm: the data or the starting points are not finite");
  }
  if (Z0 != nullptr && (Z0->rows() < 1 || Z0->rows() > Y.rows() || Z0->cols() != X0.cols())) {
    throw ParameterError("gplvm: inducing inputs of " + std::to_string(Z0->rows()) + " × " +
                         std::to_string(Z0->cols()) + " for " + std::to_string(Y.rows()) +
                         " latent points of " + std::to_string(X0.cols()) +
                         " dimensions, expected M × q with 1 ≤ M ≤ N");
  }
  if (Z0 != nullptr && !Z0->allFinite()) {
    throw ParameterError("gplvm: the starting inducing inputs are not finite");
  }
  if (max_iterations < 1) {
    throw ParameterError("gplvm: " + std::to_string(max_iterations) +
                         " iterations asked for, expected at least 1");
  }
  GplvmFit fit;
  fit.X = X0;
  if (Z0 != nullptr) fit.Z = *Z0;
  fit.kernel = kernel;
  Eigen::MatrixXd X = X0, gX, Z = fit.Z, gZ;
  GplvmKernel k = kernel;
  Eigen::VectorXd gk;
  // The best point evaluated: what is kept when the line search gives up.
  double best = std::numeric_limits<double>::infinity(), best_gradient_norm = 0.0;
  int evaluations = 0;
  bool last_failed = false;  // the last evaluation was of a kernel that cannot be factorised
  auto objective = [&](const Eigen::VectorXd& v, Eigen::VectorXd& grad) {
    control.check();
    unpack(v, X, Z, k, fit_lengthscale);
    last_failed = true;
    double value;
    try {
      value = Z0 != nullptr ? sparse_gplvm_objective(Y, X, Z, k, &gX, &gZ, &gk)
                            : gplvm_objective(Y, X, k, &gX, &gk);
    } catch (const NumericalError&) {
      // A step into a kernel that cannot be factorised: tell the line search it is no better.
      grad = Eigen::VectorXd::Zero(v.size());
      return std::numeric_limits<double>::max();
    }
    last_failed = false;
    ++evaluations;
    control.update(std::min(1.0, double(evaluations) / (1.5 * max_iterations)));
    if (value < best) {
      best = value;
      fit.X = X;
      fit.Z = Z;
      fit.kernel = k;
    }
    grad.resize(v.size());
    Eigen::Index at = 0;
    for (Eigen::Index i = 0; i < gX.rows(); ++i)
      for (Eigen::Index a = 0; a < gX.cols(); ++a) grad[at++] = gX(i, a);
    for (Eigen::Index i = 0; i < Z.rows(); ++i)
      for (Eigen::Index a = 0; a < Z.cols(); ++a) grad[at++] = gZ(i, a);
    for (int j = 0; j < 4; ++j) {
      if (j != 1 || fit_lengthscale) grad[at++] = gk[j];  // pack()'s order
    }
    if (value == best) best_gradient_norm = grad.norm();
    return value;
  };
  LBFGSpp::LBFGSParam<double> param;
  param.epsilon = 1e-5;
  param.epsilon_rel = 1e-7;
  param.past = 5;
  param.delta = 1e-10;
  param.linesearch = LBFGSpp::LBFGS_LINESEARCH_BACKTRACKING_STRONG_WOLFE;
  Eigen::VectorXd v = pack(X0, fit.Z, kernel, fit_lengthscale);
  double fx = 0.0;
  // LBFGS++'s line search, out of trials, either returns its last one — when that was a kernel
  // that cannot be factorised, its zero gradient would read as convergence — or gives up. Either
  // way the fit starts again from the best point (a fresh L-BFGS memory) while that keeps
  // lowering the objective and iterations remain; a line search that gave up counts its
  // evaluations as iterations (each iteration evaluates at least once).
  int used = 0;
  double best_at_restart = std::numeric_limits<double>::infinity();
  for (int restart = 0;; ++restart) {
    param.max_iterations = max_iterations - used;
    LBFGSpp::LBFGSSolver<double, LBFGSpp::LineSearchNocedalWright> solver(param);
    const int evaluations_before = evaluations;
    bool gave_up = false;
    try {
      used += solver.minimize(objective, v, fx);
    } catch (const std::runtime_error&) {  // LBFGS++: the line search found no decrease
      gave_up = true;
    } catch (const std::logic_error&) {
      gave_up = true;
    }
    if (gave_up) used += std::max(1, evaluations - evaluations_before);
    fit.iterations = gave_up ? -1 : used;
    fit.stopped = used >= max_iterations ? "iteration limit"
                  : gave_up              ? "line search"
                                         : "converged";
    const bool stuck = gave_up || last_failed;
    const bool progress = best < best_at_restart - 1e-12 * std::abs(best);
    if (!stuck || used >= max_iterations || restart == kMaxRestarts || !std::isfinite(best) ||
        !progress)
      break;
    best_at_restart = best;
    v = pack(fit.X, fit.Z, fit.kernel, fit_lengthscale);
  }
  if (last_failed && fit.iterations >= 0 && fit.iterations < max_iterations) {
    fit.stopped = "line search";
  }
  fit.evaluations = evaluations;
  if (!std::isfinite(best)) {
    throw NumericalError("gplvm: the kernel matrix is not positive definite at the start");
  }
  fit.objective = best;
  fit.gradient_norm = best_gradient_norm;
  control.update(1.0);
  return fit;
}

GplvmPredictive gplvm_predictive(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& X,
                                 const Eigen::MatrixXd& Z, const GplvmKernel& kernel) {
  const double sf2 = std::exp(kernel.log_rbf_variance), l2 = std::exp(2 * kernel.log_lengthscale);
  const double sb2 = std::exp(kernel.log_bias_variance), sn2 = std::exp(kernel.log_noise_variance);
  const double eps = kJitter * sf2, s = sn2 + eps;
  GplvmPredictive p;
  p.rbf_variance = sf2;
  p.lengthscale = std::sqrt(l2);
  p.bias_variance = sb2;
  p.prior_variance = sf2 + sb2 + s;
  const char* not_pd = "gplvm: the fitted model's kernel matrix is not positive definite";
  if (Z.rows() == 0) {
    p.basis = X;
    Eigen::MatrixXd K = rbf_bias(X, X, sf2, l2, sb2);
    K.diagonal().array() += s;
    const Eigen::LLT<Eigen::MatrixXd> llt(K);
    if (llt.info() != Eigen::Success) throw NumericalError(not_pd);
    p.alpha = llt.solve(Y);
    p.C = llt.solve(Eigen::MatrixXd::Identity(K.rows(), K.cols()));
    return p;
  }
  p.basis = Z;
  const Eigen::Index M = Z.rows();
  const SparseFactors f = sparse_factors(Z, X, sf2, l2, sb2, eps, s, not_pd);
  const auto L = f.Kuu.matrixL();
  const Eigen::MatrixXd c = f.B.solve(f.A * Y);
  p.alpha = L.transpose().solve(c) / s;
  // K_uu⁻¹ − P⁻¹ = L⁻ᵀ (I − B⁻¹) L⁻¹.
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(M, M);
  const Eigen::MatrixXd T = L.transpose().solve(I - f.B.solve(I));
  p.C = L.transpose().solve(T.transpose()).transpose();
  p.C = 0.5 * (p.C + p.C.transpose()).eval();
  return p;
}

double gplvm_place_objective(const GplvmPredictive& p, const Eigen::VectorXd& y,
                             const Eigen::VectorXd& x, Eigen::VectorXd* grad) {
  const double l2 = p.lengthscale * p.lengthscale;
  const Eigen::MatrixXd diff = (-p.basis).rowwise() + x.transpose();  // x − b_j
  const Eigen::VectorXd krbf =
      p.rbf_variance * (-0.5 / l2 * diff.rowwise().squaredNorm()).array().exp();
  const Eigen::VectorXd k = krbf.array() + p.bias_variance;
  const Eigen::VectorXd r = y - p.alpha.transpose() * k;
  const Eigen::VectorXd Ck = p.C * k;
  // σ² ≥ s in exact arithmetic; the floor keeps rounding from a log of ≤ 0.
  const double var = std::max(p.prior_variance - k.dot(Ck), 1e-12 * p.prior_variance);
  const double D = double(y.size()), rr = r.squaredNorm();
  const double value = 0.5 * D * std::log(var) + 0.5 * rr / var + 0.5 * x.squaredNorm();
  if (grad != nullptr) {
    // dk_j/dx = −krbf_j (x − b_j)/ℓ²; dσ²/dx = −2 Σ_j (Ck)_j dk_j/dx; d|r|²/dx = −2 Σ_j
    // (alpha_j·r) dk_j/dx.
    const Eigen::VectorXd ar = p.alpha * r;
    const Eigen::VectorXd wvar = -2.0 * Ck.cwiseProduct(krbf) * (-1.0 / l2);
    const Eigen::VectorXd wrr = -2.0 * ar.cwiseProduct(krbf) * (-1.0 / l2);
    const Eigen::VectorXd dvar = diff.transpose() * wvar, drr = diff.transpose() * wrr;
    *grad = (0.5 * D / var - 0.5 * rr / (var * var)) * dvar + 0.5 / var * drr + x;
  }
  return value;
}

Eigen::VectorXd gplvm_place(const GplvmPredictive& p, const Eigen::VectorXd& y,
                            const Eigen::MatrixXd& starts) {
  LBFGSpp::LBFGSParam<double> param;
  // Near a training point σ² is as small as the noise and the objective's gradient large: stop
  // on a relative gradient of 1e-6 or a relative decrease below 1e-9 over 2 iterations.
  param.max_iterations = 100;
  param.epsilon = 1e-6;
  param.epsilon_rel = 1e-6;
  param.past = 2;
  param.delta = 1e-9;
  param.linesearch = LBFGSpp::LBFGS_LINESEARCH_BACKTRACKING_STRONG_WOLFE;
  LBFGSpp::LBFGSSolver<double, LBFGSpp::LineSearchNocedalWright> solver(param);
  double best = std::numeric_limits<double>::infinity();
  Eigen::VectorXd best_x = starts.row(0).transpose();
  for (Eigen::Index s = 0; s < starts.rows(); ++s) {
    auto f = [&](const Eigen::VectorXd& x, Eigen::VectorXd& g) {
      const double value = gplvm_place_objective(p, y, x, &g);
      if (value < best) {
        best = value;
        best_x = x;
      }
      return value;
    };
    Eigen::VectorXd x = starts.row(s).transpose();
    double fx = 0.0;
    try {
      solver.minimize(f, x, fx);
    } catch (const std::runtime_error&) {  // the line search found no decrease: keep the best
    } catch (const std::logic_error&) {
    }
  }
  return best_x;
}

void run_gplvm(const Eigen::MatrixXd& X, const EmbedOptions& options, Embedding& out,
               Progress& progress) {
  const int N = static_cast<int>(X.rows());
  const int M = gplvm_inducing_points(N, options.inducing);
  // Start from the PCA scores, each axis scaled to unit variance (the prior's).
  Embedding pca;
  run_pca(X, options, pca, progress);
  Eigen::MatrixXd X0 = pca.coordinates;
  for (Eigen::Index a = 0; a < X0.cols(); ++a) {
    const double sd = std::sqrt(X0.col(a).squaredNorm() / std::max(1.0, double(N - 1)));
    if (sd > 0) X0.col(a) /= sd;
  }
  const Eigen::MatrixXd Y = X.rowwise() - X.colwise().mean();
  progress.stage("optimise", 0.05, 1.0);
  // The sparse model: inducing inputs from a seeded subset of the start's latent points.
  const Eigen::MatrixXd Z0 = M > 0 ? gplvm_inducing_start(X0, M) : Eigen::MatrixXd();
  // ℓ held at options.lengthscale, or fitted (0).
  GplvmKernel kernel = initial_gplvm_kernel(Y);
  const bool fit_lengthscale = !(options.lengthscale > 0.0);
  if (!fit_lengthscale) kernel.log_lengthscale = std::log(options.lengthscale);
  const GplvmFit fit = fit_gplvm(Y, X0, kernel, options.max_iterations, progress.control(),
                                 M > 0 ? &Z0 : nullptr, fit_lengthscale);
  out.coordinates = fit.X;
  out.gplvm_kernel = {fit.kernel.log_rbf_variance, fit.kernel.log_lengthscale,
                      fit.kernel.log_bias_variance, fit.kernel.log_noise_variance};
  out.gplvm_inducing = fit.Z;
  out.eigenvalues = pca.eigenvalues;  // of the start, as umap reports its spectral start's
  out.notes.push_back(
      "gplvm" +
      (M > 0 ? " (sparse, " + std::to_string(M) + " inducing points)" : std::string(" (full)")) +
      ": " + (fit.iterations >= 0 ? std::to_string(fit.iterations) + " iterations, " : "") +
      std::to_string(fit.evaluations) + " evaluations (" + fit.stopped + ", gradient norm " +
      format_number(fit.gradient_norm, 2) + "), " +
      (M > 0 ? "bound on −log likelihood " : "−log likelihood ") + std::to_string(fit.objective) +
      ", σ_f² " + std::to_string(std::exp(fit.kernel.log_rbf_variance)) + ", ℓ " +
      std::to_string(std::exp(fit.kernel.log_lengthscale)) + (fit_lengthscale ? "" : " (held)") +
      ", σ_n² " + std::to_string(std::exp(fit.kernel.log_noise_variance)));
}

}  // namespace motionmap::embed

namespace motionmap::embed {

struct GplvmMap::Impl {
  int N = 0;
  double sf2 = 0.0, l2 = 1.0, sb2 = 0.0, prior = 0.0, threshold = 0.0;
  Eigen::MatrixXd basis;  // B × 2
  Eigen::MatrixXd C;      // B × B
  Eigen::MatrixXd W;      // N × B: μ(x) = Σ_i (W k(x))_i Y_i
  Eigen::VectorXd C1, W1;
  double oneC1 = 0.0;
  // The basis points in a grid of square cells (side ≥ the cutoff), cell by cell: the points of
  // cell c are order[start[c] … start[c + 1]).
  Eigen::Vector2d lo = Eigen::Vector2d::Zero();
  double cell = 1.0;
  int nx = 1, ny = 1;
  std::vector<int> start, order;

  // The basis points within the cutoff of x and their RBF values.
  void nearby(const Eigen::Vector2d& x, std::vector<int>& idx, std::vector<double>& r) const {
    if (!x.allFinite()) {
      throw ParameterError("gplvm map: the point (" + format_number(x.x()) + ", " +
                           format_number(x.y()) + ") is not finite");
    }
    idx.clear();
    r.clear();
    const double cut2 = kGplvmCutoff * kGplvmCutoff * l2;
    const auto cx = static_cast<long>(std::floor((x.x() - lo.x()) / cell));
    const auto cy = static_cast<long>(std::floor((x.y() - lo.y()) / cell));
    for (long j = std::max(0L, cy - 1); j <= std::min(long(ny) - 1, cy + 1); ++j) {
      for (long i = std::max(0L, cx - 1); i <= std::min(long(nx) - 1, cx + 1); ++i) {
        const auto c = static_cast<std::size_t>(j * nx + i);
        for (int e = start[c]; e < start[c + 1]; ++e) {
          const int b = order[std::size_t(e)];
          const double d2 = (basis.row(b).transpose() - x).squaredNorm();
          if (d2 < cut2) {
            idx.push_back(b);
            r.push_back(sf2 * std::exp(-0.5 * d2 / l2));
          }
        }
      }
    }
  }
};

GplvmMap::GplvmMap(const GplvmPredictive& p, const Eigen::MatrixXd& latent,
                   const Eigen::MatrixXd* Y)
    : m(std::make_unique<Impl>()) {
  Impl& s = *m;
  const Eigen::Index B = p.basis.rows(), N = latent.rows();
  if (p.basis.cols() != 2 || latent.cols() != 2) {
    throw ParameterError("gplvm map: the latent points have " + std::to_string(latent.cols()) +
                         " and the basis " + std::to_string(p.basis.cols()) +
                         " dimensions; the GP's blend and validity need a 2-D map");
  }
  if (B == 0 || N == 0 || p.C.rows() != B || p.C.cols() != B) {
    throw ParameterError("gplvm map: " + std::to_string(B) + " basis points, " + std::to_string(N) +
                         " latent points and a " + std::to_string(p.C.rows()) + " × " +
                         std::to_string(p.C.cols()) + " matrix C (need B × B, B ≥ 1, N ≥ 1)");
  }
  if (!latent.allFinite() || !p.basis.allFinite() || !p.C.allFinite()) {
    throw ParameterError("gplvm map: non-finite latent points, basis or C");
  }
  s.N = static_cast<int>(N);
  s.sf2 = p.rbf_variance;
  s.l2 = p.lengthscale * p.lengthscale;
  s.sb2 = p.bias_variance;
  const double noise = p.prior_variance - p.rbf_variance - p.bias_variance;
  if (!(s.sf2 > 0) || !(s.l2 > 0) || !(s.sb2 >= 0) || !(noise > 0) || !std::isfinite(noise)) {
    throw ParameterError("gplvm map: the kernel's variances (σ_f² " + format_number(s.sf2) +
                         ", σ_b² " + format_number(s.sb2) + ", prior " +
                         format_number(p.prior_variance) +
                         ") leave no noise variance s = prior − σ_f² − σ_b² > 0");
  }
  s.prior = s.sf2 + s.sb2;
  s.threshold = kGplvmValidFraction * s.prior;
  s.basis = p.basis;
  s.C = p.C;
  if (B == N && p.basis == latent) {
    // The full model: its basis is the latent points, and W = C.
    s.W = p.C;
  } else if (B == N) {
    const double gap = (p.basis - latent).cwiseAbs().maxCoeff();
    throw ParameterError(
        "gplvm map: the full model's basis is not the latent points (they differ "
        "by up to " +
        format_number(gap) + "); the model does not belong to this map's coordinates");
  } else {
    // The sparse model, as gplvm_predictive(): K_uu = LLᵀ, B = I + L⁻¹K_uf K_fu L⁻ᵀ / s,
    // P = L B Lᵀ, so W = K_fu P⁻¹ / s = (L⁻¹K_uf)ᵀ B⁻¹ L⁻¹ / s.
    const SparseFactors f =
        sparse_factors(p.basis, latent, s.sf2, s.l2, s.sb2, kJitter * s.sf2, noise,
                       "gplvm map: the inducing inputs' kernel matrix is not positive definite");
    const Eigen::MatrixXd Li = f.Kuu.matrixL().solve(Eigen::MatrixXd::Identity(B, B));
    s.W = f.A.transpose() * f.B.solve(Li) / noise;
  }
  if (Y != nullptr) {
    // W ᵀ Y is the predictive's alpha when the predictive was fitted to these frames.
    if (Y->rows() != N || Y->cols() != p.alpha.cols() || p.alpha.rows() != B) {
      throw ParameterError("gplvm map: features of " + std::to_string(Y->rows()) + " × " +
                           std::to_string(Y->cols()) + " for " + std::to_string(N) +
                           " latent points and a predictive of " + std::to_string(p.alpha.rows()) +
                           " × " + std::to_string(p.alpha.cols()));
    }
    const double err = (s.W.transpose() * *Y - p.alpha).norm(), scale = p.alpha.norm();
    if (!(err <= 1e-6 * scale + std::numeric_limits<double>::min())) {
      throw ParameterError(
          "gplvm map: the GP's predictive does not belong to these frames and latent points "
          "(its weights reproduce its alpha to " +
          format_number(err / std::max(scale, std::numeric_limits<double>::min())) +
          " relative, need 1e-6)");
    }
  }
  s.C1 = s.C.rowwise().sum();
  s.W1 = s.W.rowwise().sum();
  s.oneC1 = s.C1.sum();
  // The grid: cells of side the cutoff (larger when that would make over 512 per side).
  s.lo = p.basis.colwise().minCoeff().transpose();
  const Eigen::Vector2d extent = p.basis.colwise().maxCoeff().transpose() - s.lo;
  s.cell = std::max({kGplvmCutoff * std::sqrt(s.l2), extent.maxCoeff() / 512.0,
                     std::numeric_limits<double>::min()});
  s.nx = static_cast<int>(extent.x() / s.cell) + 1;
  s.ny = static_cast<int>(extent.y() / s.cell) + 1;
  std::vector<int> cell_of(static_cast<std::size_t>(B));
  s.start.assign(static_cast<std::size_t>(s.nx) * s.ny + 1, 0);
  for (Eigen::Index b = 0; b < B; ++b) {
    const int cx = std::min(s.nx - 1, static_cast<int>((p.basis(b, 0) - s.lo.x()) / s.cell));
    const int cy = std::min(s.ny - 1, static_cast<int>((p.basis(b, 1) - s.lo.y()) / s.cell));
    cell_of[std::size_t(b)] = cy * s.nx + cx;
    ++s.start[std::size_t(cell_of[std::size_t(b)]) + 1];
  }
  for (std::size_t c = 1; c < s.start.size(); ++c) s.start[c] += s.start[c - 1];
  s.order.resize(static_cast<std::size_t>(B));
  std::vector<int> fill(s.start.begin(), s.start.end() - 1);
  for (Eigen::Index b = 0; b < B; ++b)
    s.order[std::size_t(fill[std::size_t(cell_of[std::size_t(b)])]++)] = static_cast<int>(b);
}

GplvmMap::~GplvmMap() = default;
GplvmMap::GplvmMap(GplvmMap&&) noexcept = default;
GplvmMap& GplvmMap::operator=(GplvmMap&&) noexcept = default;

int GplvmMap::num_frames() const {
  return m->N;
}

double GplvmMap::prior_variance() const {
  return m->prior;
}

double GplvmMap::threshold() const {
  return m->threshold;
}

double GplvmMap::lengthscale() const {
  return std::sqrt(m->l2);
}

double GplvmMap::variance(const Eigen::Vector2d& x) const {
  const Impl& s = *m;
  thread_local std::vector<int> idx;
  thread_local std::vector<double> r;
  s.nearby(x, idx, r);
  // kᵀCk = rᵀCr + 2σ_b² rᵀ(C1) + σ_b⁴ 1ᵀC1, r over the nearby basis points.
  double rCr = 0.0, rC1 = 0.0;
  for (std::size_t a = 0; a < idx.size(); ++a) {
    double row = 0.0;
    for (std::size_t b = 0; b < idx.size(); ++b) row += s.C(idx[a], idx[b]) * r[b];
    rCr += r[a] * row;
    rC1 += r[a] * s.C1[idx[a]];
  }
  const double kCk = rCr + 2.0 * s.sb2 * rC1 + s.sb2 * s.sb2 * s.oneC1;
  return std::max(0.0, s.prior - kCk);
}

Eigen::VectorXd GplvmMap::frame_weights(const Eigen::Vector2d& x) const {
  const Impl& s = *m;
  std::vector<int> idx;
  std::vector<double> r;
  s.nearby(x, idx, r);
  Eigen::VectorXd w = s.sb2 * s.W1;
  for (std::size_t a = 0; a < idx.size(); ++a) w += r[a] * s.W.col(idx[a]);
  w.array() += (1.0 - w.sum()) / s.N;
  return w;
}

}  // namespace motionmap::embed
