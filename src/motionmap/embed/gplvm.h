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
// PCA scores scaled to unit variance per axis. The full model costs O(N³) per evaluation. L has no
// minimum over X and ℓ together — the kernel sees X only through |x − x'|/ℓ, so (X, ℓ) → (cX, cℓ)
// keeps the likelihood and lowers ½|X|², and the fit slides X and ℓ towards 0 until its iteration
// limit; with ℓ held (fit_gplvm's fit_lengthscale) it has minima, which the fit converges to.
//
// The sparse model (above kGplvmSparseAbove frames, or with EmbedOptions::inducing): M inducing
// inputs Z (M × q) and Titsias's collapsed variational bound ("Variational learning of inducing
// variables in sparse Gaussian processes", AISTATS 2009; the variational DTC of Titsias &
// Lawrence's Bayesian GP-LVM and GPy's SparseGPLVM), with K_uu = k(Z, Z) + ε I, Q = K_fu K_uu⁻¹
// K_uf, s = σ_n² + ε (ε = 10⁻⁸ σ_f², the full model's jitter) and t = Σ_i k(x_i, x_i) without the
// noise, N (σ_f² + σ_b²):
//   L_s = D/2 log|Q + s I| + 1/2 tr((Q + s I)⁻¹ Y Yᵀ) + N D/2 log 2π + D/(2s) (t − tr Q)
//         + 1/2 |X|²_F + N q/2 log 2π,
// over X, Z and θ together (the same optimiser). It is an upper bound of L (a lower bound of the
// likelihood) for every Z, tightens as inducing inputs are added, and equals L up to the jitter
// when Z = X. O(N M² + N M D) per evaluation.
#include <memory>

#include <Eigen/Core>

#include "motionmap/core/control.h"
#include "motionmap/core/map_gp.h"

namespace motionmap::embed {

/// Above this many frames gplvm fits the sparse model (the full model's N × N kernel is
/// factorised at every step).
inline constexpr int kGplvmSparseAbove = 1000;
/// Inducing inputs of the sparse model when EmbedOptions::inducing is 0.
inline constexpr int kGplvmDefaultInducing = 100;
/// The seed of the inducing inputs' starting subset (gplvm_inducing_start).
inline constexpr unsigned kGplvmInducingSeed = 25;

/// The inducing points gplvm fits `frames` frames with when EmbedOptions::inducing is `inducing`:
/// 0 for the full model (inducing 0 and at most kGplvmSparseAbove frames), else `inducing`, or
/// min(kGplvmDefaultInducing, frames) when it is 0.
inline int gplvm_inducing_points(int frames, int inducing) {
  if (inducing > 0) return inducing;
  if (frames <= kGplvmSparseAbove) return 0;
  return frames < kGplvmDefaultInducing ? frames : kGplvmDefaultInducing;
}

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

/// The sparse model's objective L_s above at latent points X (N × q), inducing inputs Z (M × q)
/// and kernel θ; gradients as gplvm_objective, and `grad_Z` (M × q). @throws NumericalError when
/// K_uu is not positive definite.
double sparse_gplvm_objective(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& X,
                              const Eigen::MatrixXd& Z, const GplvmKernel& kernel,
                              Eigen::MatrixXd* grad_X = nullptr, Eigen::MatrixXd* grad_Z = nullptr,
                              Eigen::VectorXd* grad_kernel = nullptr);

/// The starting inducing inputs: M of the rows of X (N × q), a uniformly random subset drawn
/// with std::mt19937(kGplvmInducingSeed) by a partial Fisher–Yates shuffle (index i swapped with
/// i + r mod (N − i)), in frame order. @throws ParameterError unless 1 ≤ M ≤ N.
Eigen::MatrixXd gplvm_inducing_start(const Eigen::MatrixXd& X, int M);

struct GplvmFit {
  Eigen::MatrixXd X;  ///< the latent points (N × q)
  Eigen::MatrixXd Z;  ///< the sparse model's inducing inputs (M × q); empty for the full model
  GplvmKernel kernel;
  double objective = 0.0;
  /// L-BFGS iterations; −1 when the line search stopped it (LBFGS++ does not say how many).
  int iterations = 0;
  int evaluations = 0;  ///< of the objective and its gradient
  /// The Euclidean norm of the objective's gradient at the point kept (over the coordinates
  /// fitted: with the lengthscale held, without its entry).
  double gradient_norm = 0.0;
  /// Why the optimiser stopped: "converged" (gradient norm below max(10⁻⁵, 10⁻⁷ × the
  /// coordinates' norm), or the objective fallen by less than 10⁻¹⁰ of itself in 5 iterations),
  /// "iteration limit", or "line search" (no further decrease found along the last direction: at
  /// the optimum to within rounding, or stuck; the best point so far is kept).
  const char* stopped = "";
};

/// Fits the model to Y (N × D, centred) from latent points X0 (N × q) and `kernel` (with
/// `fit_lengthscale` false, its lengthscale held), at most `max_iterations` L-BFGS iterations: the
/// full model, or with `Z0` (M × q) the sparse one from those inducing inputs. `control` hears the
/// iterations and is polled for cancel.
/// @throws ParameterError for mismatched sizes or non-finite inputs; NumericalError as
///   gplvm_objective(); Cancelled.
GplvmFit fit_gplvm(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& X0, const GplvmKernel& kernel,
                   int max_iterations, const Control& control = {},
                   const Eigen::MatrixXd* Z0 = nullptr, bool fit_lengthscale = true);

/// The starting kernel for Y and latent points of unit variance: σ_f² = the mean column variance
/// of Y, ℓ = 1, σ_b² = 10⁻³ σ_f², σ_n² = 10⁻¹ σ_f² (σ_f² = 1 when Y has no variance).
GplvmKernel initial_gplvm_kernel(const Eigen::MatrixXd& Y);

/// What placing new frames on a fitted map needs: the GP's predictive at a latent point x,
///   μ(x) = k(x)ᵀ alpha,   σ²(x) = prior_variance − k(x)ᵀ C k(x),
/// k(x) the kernel without noise (RBF + bias) between x and the rows of `basis`. Full model:
/// basis = the latent points X, alpha = K⁻¹Y, C = K⁻¹ (K with the noise). Sparse model (Titsias's
/// predictive, the same as DTC's): basis = the inducing inputs Z, alpha = P⁻¹K_uf Y / s,
/// C = K_uu⁻¹ − P⁻¹, P = K_uu + K_uf K_fu / s. prior_variance = σ_f² + σ_b² + s.
struct GplvmPredictive {
  Eigen::MatrixXd basis;  ///< B × q
  Eigen::MatrixXd alpha;  ///< B × D
  Eigen::MatrixXd C;      ///< B × B
  double rbf_variance = 0.0, lengthscale = 1.0, bias_variance = 0.0, prior_variance = 0.0;
};

/// The predictive of the model fitted to Y (N × D, centred) at latent points X, with inducing
/// inputs Z (empty: the full model) and `kernel`. @throws NumericalError as the objectives.
GplvmPredictive gplvm_predictive(const Eigen::MatrixXd& Y, const Eigen::MatrixXd& X,
                                 const Eigen::MatrixXd& Z, const GplvmKernel& kernel);

/// The rule of where a GP-LVM map is valid (docs/methods/gplvm.md, "Where the map is valid"): a
/// map point x is inside the data when the GP's predictive variance without the noise, σ²(x) − s,
/// is at most this fraction τ of its prior σ_f² + σ_b² (the variance far from every latent point,
/// before the bias is learnt). Chosen on pictures of CMU 64_08 and the Bandai walks
/// (docs/gplvm-variance.png): at 0.1 the region is one piece per cluster of frames, about one
/// lengthscale around them; 0.05 leaves holes between a sparse model's inducing inputs, 0.2 and
/// 0.5 reach into the empty map.
inline constexpr double kGplvmValidFraction = 0.1;

/// A fitted GP-LVM read as a map: the GP's predictive mean as weights over the training frames
/// (the inverse map: the pose at any map point), and its predictive variance as the rule of where
/// the map is valid (kGplvmValidFraction). Latent dimension 2 (the map's plane).
///
///   GplvmMap gp(model.gplvm, coords, &Y);  // Y: the frames' features, centred
///   Eigen::VectorXd w = gp.frame_weights({0.3, -1.2});  // sums to 1
///   // Σ_i w_i (Y_i + mean) = μ(x) + mean: the GP's predictive mean of the features
///   bool ok = gp.inside({0.3, -1.2});
///
/// The predictive mean is a weighted sum of the centred training rows Y_i, μ(x) = Σ_i w_i Y_i with
/// w = W k(x): full model W = C = K⁻¹ (the basis is the latent points); sparse W = K_fu P⁻¹ / s
/// (K_fu = k(latent points, Z)). Adding (1 − Σw)/N to every w_i makes the weights sum to 1 and
/// gives Σ_i w'_i (Y_i + mean) = μ(x) + mean exactly (mean = the rows' mean), so a blend of the
/// frames with w' is the GP's prediction of every feature the frames have.
///
/// Both sums use k(x) = r(x) + σ_b² 1, r the RBF part, which is below e⁻⁴⁰ σ_f² (4·10⁻¹⁸ σ_f²)
/// beyond kGplvmCutoff·ℓ: only the basis points within it are visited (a grid of cells of that
/// size), the rest of k(x) is the bias, whose products C 1, 1ᵀC1 and W 1 are kept. The error of
/// dropping r beyond the cutoff is at most √B · 4·10⁻¹⁸ σ_f² times ‖C‖ or ‖W‖.
///
/// Thread-safe (const after construction).
class GplvmMap final : public MapGp {
 public:
  /// `p`: the fitted predictive (gplvm_predictive, or a map file's /model/gplvm); `latent`: the N
  /// training frames' latent points (N × 2, the map's coordinates, in frame order); `Y`, when
  /// given: their centred features (N × D), checked against the predictive (W ᵀ Y must give its
  /// alpha to 1e-6 relative), which catches a predictive that does not belong to these frames.
  /// @throws ParameterError for a latent dimension other than 2, sizes that do not fit, a full
  ///         model whose basis is not the latent points, or a predictive inconsistent with Y;
  ///         NumericalError for a sparse model whose kernel matrices cannot be factorised.
  GplvmMap(const GplvmPredictive& p, const Eigen::MatrixXd& latent,
           const Eigen::MatrixXd* Y = nullptr);
  ~GplvmMap() override;
  GplvmMap(GplvmMap&&) noexcept;
  GplvmMap& operator=(GplvmMap&&) noexcept;

  int num_frames() const override;
  /// σ_f² + σ_b²: the noise-free predictive variance far from every latent point, before the
  /// bias is learnt.
  double prior_variance() const;
  /// σ²(x) − s: the predictive variance of the noise-free value at x (≥ 0), cut off as above.
  double variance(const Eigen::Vector2d& x) const override;
  // inside(x) (MapGp): variance(x) ≤ threshold().
  /// The threshold of inside(): kGplvmValidFraction · prior_variance().
  double threshold() const override;
  /// The kernel's lengthscale ℓ (latent units): the scale on which the variance changes.
  double lengthscale() const override;
  /// The weights w' (N, summing to 1) of the training frames at x, as above.
  Eigen::VectorXd frame_weights(const Eigen::Vector2d& x) const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> m;
};

/// Basis points farther than this many lengthscales from x are left out of k(x)'s RBF part
/// (e^{−c²/2} = e⁻⁴⁰).
inline constexpr double kGplvmCutoff = 8.94427190999916;  // √80

/// −log p(y | x) − log p(x) up to constants: D/2 log σ²(x) + |y − μ(x)|²/(2σ²(x)) + |x|²/2, for
/// a centred pose y (D) at latent point x (q); with `grad`, its gradient in x.
double gplvm_place_objective(const GplvmPredictive& p, const Eigen::VectorXd& y,
                             const Eigen::VectorXd& x, Eigen::VectorXd* grad = nullptr);

/// The minimum of gplvm_place_objective over x by L-BFGS (at most 100 iterations) from each of
/// `starts` (rows, q), the lowest kept.
Eigen::VectorXd gplvm_place(const GplvmPredictive& p, const Eigen::VectorXd& y,
                            const Eigen::MatrixXd& starts);

}  // namespace motionmap::embed
