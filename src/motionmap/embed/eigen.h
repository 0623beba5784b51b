#pragma once
// Partial symmetric eigenproblems, the only kind the embedding methods need: a few eigenpairs at
// one end of the spectrum. Spectra's implicitly restarted Lanczos does the work above
// kDenseEigenLimit rows; below it a dense SelfAdjointEigenSolver is both faster and exact.
//
//   EigenPairs top = largest_eigenpairs(A, 2, "mds");              // A·v = λ·v, λ descending
//   EigenPairs low = smallest_eigenpairs_excluding(L, q, 2, "le");  // skipping null vector q
#include <functional>
#include <limits>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "motionmap/core/control.h"

namespace motionmap::embed {

/// Matrices with at most this many rows are solved densely (full spectrum, exact); larger ones
/// with Lanczos.
constexpr int kDenseEigenLimit = 200;
/// Lanczos convergence tolerance: each Ritz pair's residual ‖A·v − θ·v‖ ≤ tol·|θ|.
constexpr double kEigenTolerance = 1e-10;
/// Shift-invert's shift ε relative to ‖A‖∞ in smallest_eigenpairs_excluding (the dense path's).
constexpr double kRelativeShift = 1e-12;
/// The shift of the points path's Laplacian eigenmap and LLE: the wanted eigenvalues of a large
/// library's graph can lie far below 1e-12·‖A‖∞ (LLE's M on 72 000 library frames: 6.5e-15 and
/// 1.1e-14 with ‖M‖∞ = 20), where 1/(λ + ε) bunch together and Lanczos restarts over and over (16
/// restarts, 290 solves there; 1 restart, 21 solves with this shift). Still ~100 units of
/// rounding of ‖A‖∞, so A + ε·I stays positive definite through the factorization.
constexpr double kPointsRelativeShift = 1e-14;

/// How smallest_eigenpairs_excluding factorizes A + ε·I for its shift-invert solves.
struct ShiftInvert {
  double relative_shift = kRelativeShift;  ///< ε ÷ ‖A‖∞
  /// false: Eigen's SimplicialLDLT, one thread (the dense path, whose maps keep its bits);
  /// true: the supernodal LDLᵀ of detail/sparse_ldlt.h on the thread pool (the points path,
  /// whose large graphs it factors several times faster).
  bool supernodal = false;
};
/// The points path's.
constexpr ShiftInvert kPointsShiftInvert{kPointsRelativeShift, true};

/// A few eigenpairs.
struct EigenPairs {
  Eigen::VectorXd values;   ///< count eigenvalues, in the order the function states
  Eigen::MatrixXd vectors;  ///< n by count, unit-norm columns, the matching eigenvectors
  int restarts = 0;         ///< Lanczos iterations, i.e. restarts + 1 (0: dense)
  int products = 0;         ///< products with the operator (0: dense)
  /// largest_eigenpairs only: an upper bound on the operator's smallest eigenvalue, free with the
  /// solve: the smallest Ritz value of Lanczos's final Krylov subspace (Rayleigh–Ritz values
  /// never go below the spectrum; usually close when that eigenvalue is well separated), or the
  /// exact smallest eigenvalue from the dense solver.
  double smallest_ritz = std::numeric_limits<double>::quiet_NaN();
};

/// y = A·x for an n-vector x (both arrays of n doubles).
using Product = std::function<void(const double* x, double* y)>;

/// The `count` algebraically largest eigenpairs of the symmetric n by n operator `product`,
/// largest first, by Lanczos. `what` names the caller in error messages. `lanczos_vectors` is
/// the Krylov subspace size per restart (0: max(2·count + 1, 20), clamped to n); convergence is
/// checked once per restart, so a smaller one suits costly products on well-separated spectra
/// (classical MDS: converged after ~10 products) at the risk of more restarts on hard ones.
/// @throws NumericalError when Lanczos does not converge within 1000 restarts (names nconv,
///   iterations, products and the tolerance); ParameterError unless 1 ≤ count < n.
EigenPairs largest_eigenpairs(Eigen::Index n, const Product& product, int count,
                              std::string_view what, double tolerance = kEigenTolerance,
                              int lanczos_vectors = 0);

/// The `count` algebraically largest eigenpairs of the dense symmetric matrix A (its lower
/// triangle is read), largest first: dense solver when A.rows() ≤ dense_limit, else Lanczos.
/// @throws as above.
EigenPairs largest_eigenpairs(const Eigen::MatrixXd& A, int count, std::string_view what,
                              int dense_limit = kDenseEigenLimit);

/// The `count` smallest eigenpairs, ascending, of the sparse symmetric positive semi-definite
/// A (n by n, both triangles stored) whose null space contains the unit vector `null_vector`,
/// leaving that vector out (a graph Laplacian and √deg, LLE's M and the constant vector):
///   dense (n ≤ dense_limit): the smallest eigenpairs of A + c·q·qᵀ, c above A's spectrum;
///   sparse: Lanczos on P·(A + ε·I)⁻¹·P (shift-invert with a sparse LDLᵀ factorization, P the
///   projector off q, ε = shift_invert.relative_shift·‖A‖∞), whose largest eigenvalues 1/(λ + ε)
///   are A's smallest; the smaller ε is next to the wanted eigenvalues' gaps, the fewer restarts.
/// Eigenvalues are the Rayleigh quotients vᵀ·A·v. `control` is polled for cancellation.
/// @throws NumericalError when the factorization fails or Lanczos does not converge;
///   ParameterError unless 1 ≤ count ≤ n − 2; Cancelled.
EigenPairs smallest_eigenpairs_excluding(const Eigen::SparseMatrix<double>& A,
                                         const Eigen::VectorXd& null_vector, int count,
                                         std::string_view what, const Control& control = {},
                                         int dense_limit = kDenseEigenLimit,
                                         const ShiftInvert& shift_invert = {});

/// The rows of Z = (A − shift)·diag(1/scale) projected on Z's top `count` right-singular
/// vectors: Z·V = U·Σ (m by count), with σ² in `squared_singular_values` (descending). A: m by p;
/// shift, scale: 1 by p, or empty for 0 resp. 1 (PCA centres, SVD does not). Through the smaller
/// Gram matrix (ZᵀZ, or Z·Zᵀ when m < p) and largest_eigenpairs; ZᵀZ is accumulated over a fixed
/// number of row chunks in parallel, without forming Z. @throws as largest_eigenpairs.
Eigen::MatrixXd top_singular_scores(const Eigen::MatrixXd& A, const Eigen::RowVectorXd& shift,
                                    const Eigen::RowVectorXd& scale, int count,
                                    std::string_view what,
                                    Eigen::VectorXd& squared_singular_values);

/// The `count` largest eigenpairs of a Gram matrix ZᵀZ (p by p, its lower triangle read), as
/// top_singular_scores() solves its own: the dense solver up to a small size, Lanczos above.
/// For callers that accumulate ZᵀZ themselves (embed/projection_stream.h). @throws as
/// largest_eigenpairs.
EigenPairs gram_eigenpairs(const Eigen::MatrixXd& gram, int count, std::string_view what);

/// Flips each column of M so that its entry of largest magnitude (the first such) is positive;
/// returns which columns it flipped (for what must flip with them, such as projection axes).
std::vector<bool> normalize_signs(Eigen::MatrixXd& M);

}  // namespace motionmap::embed
