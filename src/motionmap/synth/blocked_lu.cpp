#include "motionmap/synth/detail/blocked_lu.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "motionmap/core/error.h"
#include "motionmap/core/parallel.h"

namespace motionmap::synth::detail {

namespace {

using Eigen::Index;

// Most flops of one column block of the trailing update (A22 −= L21·U12): a few ms on one core
// at the Release build's SSE2 GEMM speed (tens of ms under AddressSanitizer), so a cancellation
// is seen, and the blocks other threads started are finished, well within 100 ms. Smaller
// blocks cost nothing measurable (the product's other dimensions stay in the thousands).
constexpr double kChunkFlops = 2.5e7;
constexpr Index kMinChunkColumns = 8;
constexpr Index kMaxChunkColumns = 512;
// Rows (columns) of the triangular factors handled per step of a solve, and columns per chunk of
// the O(n²) passes (norm, final interchanges): a few MB each.
constexpr Index kSolveBlock = 256;
constexpr Index kPassColumns = 256;

// Columns per block of the trailing update below a panel of `rows` rows and `kb` columns: as
// many as fit kChunkFlops. Depends on the sizes only, so the blocks (and the factors) are the
// same on any number of threads.
Index chunk_columns(Index rows, Index kb) {
  const double per_column = 2.0 * static_cast<double>(rows) * static_cast<double>(kb);
  const auto w = static_cast<Index>(kChunkFlops / std::max(per_column, 1.0));
  return std::clamp(w, kMinChunkColumns, kMaxChunkColumns);
}

int num_chunks(Index count, Index width) {
  return static_cast<int>((count + width - 1) / width);
}

// Columns of a panel below which its factorisation does not poll for cancellation.
constexpr Index kPanelPollWidth = 16;

// Applies the row interchanges piv[0 … count) (row j ↔ row piv[j], in order) to the columns of
// `block`. Column by column: the swaps of one column stay inside its contiguous storage.
template <class Block>
void swap_rows(Block&& block, const int* piv, Index count) {
  for (Index c = 0; c < block.cols(); ++c) {
    for (Index j = 0; j < count; ++j) {
      if (piv[j] != j) std::swap(block(j, c), block(piv[j], c));
    }
  }
}

// P·A = L·U of the m by b panel (m ≥ b) in place, recursively: piv[j] is the row (relative to
// the panel's top) swapped with row j, interchanges applied across the panel's columns only.
// A column whose candidates are all 0 gets no interchange and no scaling (U's pivot stays 0).
// Polls `control` between the halves of sub-panels at least kPanelPollWidth wide.
void factor_panel(Eigen::Ref<Eigen::MatrixXd> p, int* piv, const Control& control) {
  const Index m = p.rows(), b = p.cols();
  if (b == 1) {
    Index best = 0;
    double largest = std::abs(p(0, 0));
    for (Index i = 1; i < m; ++i) {
      if (std::abs(p(i, 0)) > largest) {
        largest = std::abs(p(i, 0));
        best = i;
      }
    }
    piv[0] = static_cast<int>(best);
    if (largest == 0.0) return;
    std::swap(p(0, 0), p(best, 0));
    p.col(0).tail(m - 1) /= p(0, 0);
    return;
  }
  const Index b1 = b / 2, b2 = b - b1;
  factor_panel(p.leftCols(b1), piv, control);
  if (b >= kPanelPollWidth) control.check();
  auto right = p.rightCols(b2);
  swap_rows(right, piv, b1);
  p.topLeftCorner(b1, b1).triangularView<Eigen::UnitLower>().solveInPlace(right.topRows(b1));
  right.bottomRows(m - b1).noalias() -= p.bottomLeftCorner(m - b1, b1) * right.topRows(b1);
  factor_panel(right.bottomRows(m - b1), piv + b1, control);
  for (Index j = b1; j < b; ++j) piv[j] += static_cast<int>(b1);
  // The right half's interchanges, on the left half's rows b1 … m.
  auto left_lower = p.bottomLeftCorner(m - b1, b1);
  for (Index c = 0; c < b1; ++c) {
    for (Index j = b1; j < b; ++j) {
      if (piv[j] != j) std::swap(left_lower(j - b1, c), left_lower(piv[j] - b1, c));
    }
  }
}

// Fraction of the elimination's work (Σ (rows left)², about n³/3) done before column k.
double work_before(Index k, Index n) {
  const double left = static_cast<double>(n - k) / static_cast<double>(n);
  return 1.0 - left * left * left;
}

// Vector b (one column of a solve) → sign vector as Eigen's condition estimator makes it.
Eigen::VectorXd signs(const Eigen::VectorXd& v) {
  return (v.array() < 0.0)
      .select(-Eigen::VectorXd::Ones(v.size()), Eigen::VectorXd::Ones(v.size()));
}

}  // namespace

BlockedLu::BlockedLu(Eigen::MatrixXd a, const Control& control) : m_lu(std::move(a)) {
  if (m_lu.rows() != m_lu.cols()) {
    throw ParameterError("LU: the matrix is " + std::to_string(m_lu.rows()) + " by " +
                         std::to_string(m_lu.cols()) + "; it must be square");
  }
  const Index n = m_lu.rows();
  m_pivots.assign(static_cast<std::size_t>(n), 0);
  if (n == 0) return;
  const Control norm_part = control.part(0.0, 0.01);
  const Control elim_part = control.part(0.01, 0.99);
  const Control swap_part = control.part(0.99, 1.0);

  // ‖A‖₁, per block of columns (the maximum does not depend on the order).
  {
    const int chunks = num_chunks(n, kPassColumns);
    std::vector<double> block_max(static_cast<std::size_t>(chunks), 0.0);
    parallel_chunks(
        chunks,
        [&](int c, int) {
          const Index c0 = c * kPassColumns, c1 = std::min(n, c0 + kPassColumns);
          double largest = 0.0;
          for (Index col = c0; col < c1; ++col)
            largest = std::max(largest, m_lu.col(col).cwiseAbs().sum());
          block_max[static_cast<std::size_t>(c)] = largest;
        },
        [&](int done) { norm_part.update(static_cast<double>(done) / chunks); });
    m_l1_norm = *std::max_element(block_max.begin(), block_max.end());
  }

  // Elimination, panel by panel.
  for (Index k0 = 0; k0 < n; k0 += kPanelWidth) {
    const Index kb = std::min<Index>(kPanelWidth, n - k0);
    const Index rows = n - k0;
    const double f0 = work_before(k0, n), f1 = work_before(k0 + kb, n);
    elim_part.update(f0);
    int* piv = m_pivots.data() + k0;
    factor_panel(m_lu.block(k0, k0, rows, kb), piv, elim_part);
    const Index right = n - k0 - kb;
    if (right > 0) {
      elim_part.check();
      const Index width = chunk_columns(rows, kb);
      const int chunks = num_chunks(right, width);
      parallel_chunks(
          chunks,
          [&](int c, int) {
            const Index c0 = k0 + kb + c * width;
            const Index cw = std::min(width, n - c0);
            swap_rows(m_lu.block(k0, c0, rows, cw), piv, kb);
            m_lu.block(k0, k0, kb, kb)
                .triangularView<Eigen::UnitLower>()
                .solveInPlace(m_lu.block(k0, c0, kb, cw));
            if (rows > kb) {
              m_lu.block(k0 + kb, c0, rows - kb, cw).noalias() -=
                  m_lu.block(k0 + kb, k0, rows - kb, kb) * m_lu.block(k0, c0, kb, cw);
            }
          },
          [&](int done) { elim_part.update(f0 + (f1 - f0) * done / chunks); });
    }
    for (Index j = 0; j < kb; ++j) piv[j] += static_cast<int>(k0);
  }

  // The interchanges of every later panel, on the columns of L left of it.
  const int chunks = num_chunks(n, kPassColumns);
  parallel_chunks(
      chunks,
      [&](int c, int) {
        const Index c0 = c * kPassColumns, c1 = std::min(n, c0 + kPassColumns);
        for (Index col = c0; col < c1; ++col) {
          const Index panel_end = std::min(n, (col / kPanelWidth + 1) * kPanelWidth);
          for (Index k = panel_end; k < n; ++k) {
            const int p = m_pivots[static_cast<std::size_t>(k)];
            if (p != k) std::swap(m_lu(k, col), m_lu(p, col));
          }
        }
      },
      [&](int done) { swap_part.update(static_cast<double>(done) / chunks); });
  control.finish();
}

void BlockedLu::solve_in_place(Eigen::Ref<Eigen::MatrixXd> b, const Control& control) const {
  const Index n = size();
  if (b.rows() != n) {
    throw ParameterError("LU solve: the right-hand side has " + std::to_string(b.rows()) +
                         " rows for a system of order " + std::to_string(n));
  }
  // P·B, then L⁻¹ (forward, by blocks of columns of L), then U⁻¹ (backward).
  for (Index k = 0; k < n; ++k) {
    const int p = m_pivots[static_cast<std::size_t>(k)];
    if (p != k) b.row(k).swap(b.row(p));
  }
  for (Index b0 = 0; b0 < n; b0 += kSolveBlock) {
    const Index bs = std::min(kSolveBlock, n - b0), b1 = b0 + bs;
    m_lu.block(b0, b0, bs, bs)
        .triangularView<Eigen::UnitLower>()
        .solveInPlace(b.middleRows(b0, bs));
    if (b1 < n)
      b.bottomRows(n - b1).noalias() -= m_lu.block(b1, b0, n - b1, bs) * b.middleRows(b0, bs);
    control.check();
  }
  for (Index b1 = n; b1 > 0;) {
    const Index b0 = ((b1 - 1) / kSolveBlock) * kSolveBlock, bs = b1 - b0;
    m_lu.block(b0, b0, bs, bs).triangularView<Eigen::Upper>().solveInPlace(b.middleRows(b0, bs));
    if (b0 > 0) b.topRows(b0).noalias() -= m_lu.block(0, b0, b0, bs) * b.middleRows(b0, bs);
    b1 = b0;
    control.check();
  }
}

void BlockedLu::solve_transposed_in_place(Eigen::Ref<Eigen::MatrixXd> b,
                                          const Control& control) const {
  const Index n = size();
  if (b.rows() != n) {
    throw ParameterError("LU solve: the right-hand side has " + std::to_string(b.rows()) +
                         " rows for a system of order " + std::to_string(n));
  }
  // Aᵀ = Uᵀ·Lᵀ·P: Uᵀ⁻¹ (forward), Lᵀ⁻¹ (backward), then Pᵀ (the interchanges in reverse).
  // Each step reads a block of columns of the factors (contiguous in memory).
  for (Index b0 = 0; b0 < n; b0 += kSolveBlock) {
    const Index bs = std::min(kSolveBlock, n - b0);
    if (b0 > 0)
      b.middleRows(b0, bs).noalias() -= m_lu.block(0, b0, b0, bs).transpose() * b.topRows(b0);
    m_lu.block(b0, b0, bs, bs)
        .transpose()
        .triangularView<Eigen::Lower>()
        .solveInPlace(b.middleRows(b0, bs));
    control.check();
  }
  for (Index b1 = n; b1 > 0;) {
    const Index b0 = ((b1 - 1) / kSolveBlock) * kSolveBlock, bs = b1 - b0;
    if (b1 < n) {
      b.middleRows(b0, bs).noalias() -=
          m_lu.block(b1, b0, n - b1, bs).transpose() * b.bottomRows(n - b1);
    }
    m_lu.block(b0, b0, bs, bs)
        .transpose()
        .triangularView<Eigen::UnitUpper>()
        .solveInPlace(b.middleRows(b0, bs));
    b1 = b0;
    control.check();
  }
  for (Index k = n - 1; k >= 0; --k) {
    const int p = m_pivots[static_cast<std::size_t>(k)];
    if (p != k) b.row(k).swap(b.row(p));
  }
}

double BlockedLu::rcond(const Control& control) const {
  // Eigen's rcond_estimate_helper and rcond_invmatrix_L1_norm_estimate (Higham, "FORTRAN codes
  // for estimating the one-norm of a real or complex matrix", 1988, algorithms 4.1 and 5.1),
  // step for step for real matrices.
  const Index n = size();
  if (n == 0) return std::numeric_limits<double>::infinity();
  if (m_l1_norm == 0.0) return 0.0;
  if (n == 1) return 1.0;
  if ((m_lu.diagonal().array() == 0.0).any()) return 0.0;
  constexpr double kMaxSolves = 11.0;
  int solves = 0;
  auto solve = [&](Eigen::VectorXd& v, bool transposed) {
    const Control part = control.part(solves / kMaxSolves, (solves + 1) / kMaxSolves);
    if (transposed) {
      solve_transposed_in_place(v, part);
    } else {
      solve_in_place(v, part);
    }
    ++solves;
    control.update(solves / kMaxSolves);
  };

  Eigen::VectorXd v = Eigen::VectorXd::Constant(n, 1.0 / static_cast<double>(n));
  solve(v, false);
  double lower_bound = v.lpNorm<1>();
  double old_lower_bound = lower_bound;
  Eigen::VectorXd sign_vector(n), old_sign_vector;
  Index v_max_abs_index = -1, old_v_max_abs_index = -1;
  for (int k = 0; k < 4; ++k) {
    sign_vector = signs(v);
    if (k > 0 && sign_vector == old_sign_vector) break;  // stagnated
    v = sign_vector;
    solve(v, true);
    v.cwiseAbs().maxCoeff(&v_max_abs_index);
    if (v_max_abs_index == old_v_max_abs_index) break;  // stagnated
    v = Eigen::VectorXd::Unit(n, v_max_abs_index);
    solve(v, false);
    lower_bound = v.lpNorm<1>();
    if (lower_bound <= old_lower_bound) break;  // no gain
    old_sign_vector = sign_vector;
    old_v_max_abs_index = v_max_abs_index;
    old_lower_bound = lower_bound;
  }
  // Higham's second estimate, from entries of alternating sign and slowly growing magnitude.
  double alternating_sign = 1.0;
  for (Index i = 0; i < n; ++i) {
    v[i] = alternating_sign * (1.0 + static_cast<double>(i) / static_cast<double>(n - 1));
    alternating_sign = -alternating_sign;
  }
  solve(v, false);
  const double alternate_lower_bound = (2.0 * v.lpNorm<1>()) / (3.0 * static_cast<double>(n));
  const double inverse_norm = std::max(lower_bound, alternate_lower_bound);
  control.finish();
  return inverse_norm == 0.0 ? 0.0 : (1.0 / inverse_norm) / m_l1_norm;
}

}  // namespace motionmap::synth::detail
