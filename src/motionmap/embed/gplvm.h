#pragma once
// The Gaussian Process Latent Variable Model (Lawrence, "Probabilistic non-linear principal
// component analysis with Gaussian process latent variable models", JMLR 2005; used for motion by
// Grochow et al., "Style-based inverse kinematics", SIGGRAPH 2004): latent points X (N × q) whose
// Gaussian process maps them to the data Y (N × D, centred), found with the kernel's parameters by
// maximising the marginal likelihood. `--method gplvm` (docs/methods/gplvm.md).
//
// The model: each column of Y is a draw from a GP over X with the kernel
//   k(x, x') = σ_f² exp(−|x − x'|² / (2ℓ²)) + σ_b² + σ_n² δ(x, x')      (RBF + bias + white)
// and each latent point has the prior N(0, I). The objective minimised is the negative log of the
// joint density of Y and X:
//   L = D/2 log|K| + 1/2 tr(K⁻¹ Y Yᵀ) + N D/2 log 2π + 1/2 |X|²_F + N q/2 log 2π,
// over X and θ = (log σ_f², log ℓ, log σ_b², log σ_n²), with analytic gradients, by LBFGS++'s
// L-BFGS (Debian's liblbfgspp-dev) with a strong-Wolfe line search (Nocedal & Wright), from X = the
// PCA scores scaled to unit variance per axis. The full model costs O(N³) per evaluation; this is
// the full model only (no sparse approximation yet): kGplvmMaxFrames frames at most.
#include <Eigen/Core>

#include "motionmap/core/control.h"

namespace motionmap::embed {

/// The most frames gplvm maps (the full model's N × N kernel is factorised at every step).
inline constexpr int kGplvmMaxFrames = 2000;

/// The kernel's parameters, as their logarithms (the optimiser's coordinates).
struct GplvmKernel {
  double log_rbf_variance = 0.0;    ///< log σ_f²
  double log_lengthscale = 0.0;     ///< log ℓ
  double log_bias_variance = 0.0;   ///< log σ_b²
  double log_noise_variance = 0.0;  ///< log σ_n²
};

/// The objective L above at latent points X (N × q) and kernel θ for data Y (N × D, centred by
/// the caller). With `grad_X` (N × q) and/or `grad_kernel` (4: the order of GplvmKernel's
/// fields), fills the gradients. @throws NumericalError when K is not positive definite.
double gplvm_objective(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& X,
                       const GplvmKernel& kernel, Eigen::MatrixXd* grad_X = nullptr,
                       Eigen::VectorXd* grad_kernel = nullptr);

struct GplvmFit {
  Eigen::MatrixXd X;  ///< the latent points (N × q)
  GplvmKernel kernel;
  double objective = 0.0;
  /// L-BFGS iterations; −1 when the line search stopped it (LBFGS++ does not say how many).
  int iterations = 0;
  int evaluations = 0;  ///< of the objective and its gradient
  /// Why the optimiser stopped: "converged" (gradient below tolerance), "iteration limit", or
  /// "line search" (no further decrease found along the last direction: at the optimum to
  /// within rounding, or stuck; the best point so far is kept).
  const char* stopped = "";
};

/// Fits the model to Y (N × D, centred) from latent points X0 (N × q) and `kernel`, at most
/// `max_iterations` L-BFGS iterations. `control` hears the iterations and is polled for cancel.
/// @throws ParameterError for mismatched sizes or non-finite inputs; NumericalError as
///   gplvm_objective(); Cancelled.
GplvmFit fit_gplvm(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& X0, const GplvmKernel& kernel,
                   int max_iterations, const Control& control = {});

/// The starting kernel for Y and latent points of unit variance: σ_f² = the mean column variance
/// of Y, ℓ = 1, σ_b² = 10⁻³ σ_f², σ_n² = 10⁻¹ σ_f² (σ_f² = 1 when Y has no variance).
GplvmKernel initial_gplvm_kernel(const Eigen::MatrixXd& Y);

}  // namespace motionmap::embed
