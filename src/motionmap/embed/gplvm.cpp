#include "motionmap/embed/gplvm.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include <LBFGS.h>
#include <Eigen/Cholesky>

#include "motionmap/core/error.h"
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

// The optimiser's coordinates: X row-major, then θ.
Eigen::VectorXd pack(const Eigen::MatrixXd& X, const GplvmKernel& k) {
  Eigen::VectorXd v(X.size() + 4);
  Eigen::Index at = 0;
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    for (Eigen::Index a = 0; a < X.cols(); ++a) v[at++] = X(i, a);
  v[at++] = k.log_rbf_variance;
  v[at++] = k.log_lengthscale;
  v[at++] = k.log_bias_variance;
  v[at++] = k.log_noise_variance;
  return v;
}

void unpack(const Eigen::VectorXd& v, Eigen::MatrixXd& X, GplvmKernel& k) {
  Eigen::Index at = 0;
  for (Eigen::Index i = 0; i < X.rows(); ++i)
    for (Eigen::Index a = 0; a < X.cols(); ++a) X(i, a) = v[at++];
  k.log_rbf_variance = v[at++];
  k.log_lengthscale = v[at++];
  k.log_bias_variance = v[at++];
  k.log_noise_variance = v[at++];
}

}  // namespace

GplvmFit fit_gplvm(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& X0, const GplvmKernel& kernel,
                   int max_iterations, const Control& control) {
  if (X0.rows() != Y.rows() || X0.cols() < 1 || Y.rows() < 2 || Y.cols() < 1) {
    throw ParameterError("gplvm: latent points of " + std::to_string(X0.rows()) + " × " +
                         std::to_string(X0.cols()) + " for data of " + std::to_string(Y.rows()) +
                         " × " + std::to_string(Y.cols()) + ", expected N × q for N × D, N ≥ 2");
  }
  if (!Y.allFinite() || !X0.allFinite()) {
    throw ParameterError("gplvm: the data or the starting points are not finite");
  }
  if (max_iterations < 1) {
    throw ParameterError("gplvm: " + std::to_string(max_iterations) +
                         " iterations asked for, expected at least 1");
  }
  GplvmFit fit;
  fit.X = X0;
  fit.kernel = kernel;
  Eigen::MatrixXd X = X0, gX;
  GplvmKernel k = kernel;
  Eigen::VectorXd gk;
  // The best point evaluated: what is kept when the line search gives up.
  double best = std::numeric_limits<double>::infinity();
  int evaluations = 0;
  auto objective = [&](const Eigen::VectorXd& v, Eigen::VectorXd& grad) {
    control.check();
    unpack(v, X, k);
    double value;
    try {
      value = gplvm_objective(Y, X, k, &gX, &gk);
    } catch (const NumericalError&) {
      // A step into a kernel that cannot be factorised: tell the line search it is no better.
      grad = Eigen::VectorXd::Zero(v.size());
      return std::numeric_limits<double>::max();
    }
    ++evaluations;
    control.update(std::min(1.0, double(evaluations) / (1.5 * max_iterations)));
    if (value < best) {
      best = value;
      fit.X = X;
      fit.kernel = k;
    }
    grad.resize(v.size());
    Eigen::Index at = 0;
    for (Eigen::Index i = 0; i < gX.rows(); ++i)
      for (Eigen::Index a = 0; a < gX.cols(); ++a) grad[at++] = gX(i, a);
    for (int j = 0; j < 4; ++j) grad[at++] = gk[j];
    return value;
  };
  LBFGSpp::LBFGSParam<double> param;
  param.max_iterations = max_iterations;
  param.epsilon = 1e-5;
  param.epsilon_rel = 1e-7;
  param.past = 5;
  param.delta = 1e-10;
  param.linesearch = LBFGSpp::LBFGS_LINESEARCH_BACKTRACKING_STRONG_WOLFE;
  LBFGSpp::LBFGSSolver<double, LBFGSpp::LineSearchNocedalWright> solver(param);
  Eigen::VectorXd v = pack(X0, kernel);
  double fx = 0.0;
  try {
    fit.iterations = solver.minimize(objective, v, fx);
    fit.stopped = fit.iterations >= max_iterations ? "iteration limit" : "converged";
  } catch (const std::runtime_error&) {  // LBFGS++: the line search found no decrease
    fit.iterations = -1;
    fit.stopped = "line search";
  } catch (const std::logic_error&) {
    fit.iterations = -1;
    fit.stopped = "line search";
  }
  fit.evaluations = evaluations;
  if (!std::isfinite(best)) {
    throw NumericalError("gplvm: the kernel matrix is not positive definite at the start");
  }
  fit.objective = best;
  control.update(1.0);
  return fit;
}

void run_gplvm(const Eigen::MatrixXd& X, const EmbedOptions& options, Embedding& out,
               Progress& progress) {
  const int N = static_cast<int>(X.rows());
  if (N > kGplvmMaxFrames) {
    throw ParameterError("gplvm: " + std::to_string(N) + " frames; the full model maps at most " +
                         std::to_string(kGplvmMaxFrames) +
                         " (its N × N kernel is factorised at every step, and the sparse "
                         "approximation is not built yet): map every k-th frame with --stride");
  }
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
  const GplvmFit fit =
      fit_gplvm(Y, X0, initial_gplvm_kernel(Y), options.max_iterations, progress.control());
  out.coordinates = fit.X;
  out.eigenvalues = pca.eigenvalues;  // of the start, as umap reports its spectral start's
  out.notes.push_back(
      "gplvm: " + (fit.iterations >= 0 ? std::to_string(fit.iterations) + " iterations, " : "") +
      std::to_string(fit.evaluations) + " evaluations (" + fit.stopped + "), −log likelihood " +
      std::to_string(fit.objective) + ", σ_f² " +
      std::to_string(std::exp(fit.kernel.log_rbf_variance)) + ", ℓ " +
      std::to_string(std::exp(fit.kernel.log_lengthscale)) + ", σ_n² " +
      std::to_string(std::exp(fit.kernel.log_noise_variance)));
}

}  // namespace motionmap::embed
