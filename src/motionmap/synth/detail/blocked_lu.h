#pragma once
// Dense LU factorisation with partial pivoting, P·A = L·U, done in chunks of bounded work so that
// a long factorisation (the kriging system: (N+1)², N up to 10 000) reports progress and can be
// cancelled within a fraction of a second. Same maths as Eigen::PartialPivLU (row interchanges
// by largest magnitude in the column), blocked differently, so results agree to rounding.
//
//   motionmap::synth::detail::BlockedLu lu(std::move(A), control);  // may throw Cancelled
//   if (!(lu.rcond(control) > 1e-15)) throw ...;                     // near singular
//   lu.solve_in_place(B);                                            // B ← A⁻¹·B
//
// Algorithm (right-looking, as LAPACK's dgetrf), for each panel of kPanelWidth columns k0…k1:
//  1. factor the panel (rows k0…n) recursively (halve its columns, factor the left half, update
//     and factor the right half), recording its row interchanges;
//  2. for each block of columns right of the panel (as many as make ≈ 2.5·10⁷ flops, 8 to 512
//     columns), independently (in parallel, through parallel_chunks): apply the panel's
//     interchanges, U12 = L11⁻¹·A12 (triangular solve), A22 −= L21·U12 (a matrix product);
//  3. at the end, apply every panel's interchanges to the columns of L left of it.
// Progress is reported and cancellation polled between panels, inside them, and between column
// blocks: at most a few ms of work apart in Release. The
// column blocks depend only on the matrix size, never on the number of threads, and each is
// computed by one thread, so the factors do not depend on the thread count.
#include <vector>

#include <Eigen/Core>

#include "motionmap/core/control.h"

namespace motionmap::synth::detail {

class BlockedLu {
 public:
  /// Columns per panel (step 1 above).
  static constexpr int kPanelWidth = 64;

  /// An empty factorisation (size 0).
  BlockedLu() = default;
  /// Factors the square matrix `a`, which it takes over (move it in to avoid a copy: the factors
  /// replace it). Reports fractions 0…1 of `control`'s range.
  /// @throws ParameterError if `a` is not square; Cancelled if control says so (between chunks).
  /// A singular matrix is factored anyway (a zero pivot leaves a zero on U's diagonal): check
  /// rcond().
  explicit BlockedLu(Eigen::MatrixXd a, const Control& control = {});

  /// n, the order of the matrix.
  Eigen::Index size() const { return m_lu.rows(); }
  /// n by n: L strictly below the diagonal (its unit diagonal implied), U on and above.
  const Eigen::MatrixXd& factors() const { return m_lu; }
  /// The row interchanges, in order: row k was swapped with row pivots()[k] ≥ k (LAPACK's ipiv,
  /// 0-based).
  const std::vector<int>& pivots() const { return m_pivots; }
  /// ‖A‖₁ (largest column sum of magnitudes) of the matrix before factoring.
  double l1_norm() const { return m_l1_norm; }

  /// B ← A⁻¹·B for B with size() rows. Polls `control` between blocks of rows (not reporting).
  /// @throws ParameterError on a row count mismatch; Cancelled.
  void solve_in_place(Eigen::Ref<Eigen::MatrixXd> b, const Control& control = {}) const;
  /// B ← A⁻ᵀ·B. @throws as solve_in_place.
  void solve_transposed_in_place(Eigen::Ref<Eigen::MatrixXd> b, const Control& control = {}) const;

  /// Estimate of the reciprocal condition number 1 / (‖A‖₁·‖A⁻¹‖₁), by the same algorithm as
  /// Eigen's PartialPivLU::rcond() (Hager's estimate of ‖A⁻¹‖₁ with Higham's refinements, at
  /// most 11 solves): 0 for an exactly singular matrix (a zero on U's diagonal) or ‖A‖₁ = 0,
  /// 1 for n = 1, infinity for n = 0. Reports fractions 0…1 of `control`'s range.
  /// @throws Cancelled.
  double rcond(const Control& control = {}) const;

 private:
  Eigen::MatrixXd m_lu;
  std::vector<int> m_pivots;
  double m_l1_norm = 0.0;
};

}  // namespace motionmap::synth::detail
