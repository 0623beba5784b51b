#include "motionmap/embed/eigen.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

#include <Spectra/SymEigsSolver.h>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>

#include "motionmap/core/error.h"
#include "motionmap/core/format.h"
#include "motionmap/core/parallel.h"
#include "motionmap/embed/detail/progress.h"
#include "motionmap/embed/detail/sparse_ldlt.h"

namespace motionmap::embed {

namespace {

constexpr int kMaxRestarts = 1000;
// Row chunks of top_singular_scores' Gram matrix.
constexpr int kGramChunks = 8;
// Gram matrices above this size use Lanczos: 2 eigenpairs of a 120 by 120 Gram matrix take
// 0.07 ms by Lanczos, 1.3 ms by the dense solver (which computes all 120).
constexpr int kDenseGramLimit = 32;

// Spectra's operator concept over a std::function product.
class ProductOp {
 public:
  using Scalar = double;
  ProductOp(Eigen::Index n, const Product& product) : m_n(n), m_product(product) {}
  Eigen::Index rows() const { return m_n; }
  Eigen::Index cols() const { return m_n; }
  void perform_op(const double* x, double* y) const { m_product(x, y); }

 private:
  Eigen::Index m_n;
  const Product& m_product;
};

void check_count(Eigen::Index n, int count, int max_count, std::string_view what) {
  if (count < 1 || count > max_count) {
    throw ParameterError(std::string(what) + ": cannot compute " + std::to_string(count) +
                         " eigenpairs of a " + std::to_string(n) + " by " + std::to_string(n) +
                         " matrix (at most " + std::to_string(std::max(0, max_count)) + ")");
  }
}

// Spectra's solver, also keeping the smallest Ritz value of the final Krylov subspace (the hook
// runs once, at the end of compute(), while all ncv Ritz values are still there).
class RitzSolver : public Spectra::SymEigsSolver<ProductOp> {
 public:
  RitzSolver(ProductOp& op, Eigen::Index nev, Eigen::Index ncv)
      : Spectra::SymEigsSolver<ProductOp>(op, nev, ncv) {}
  double smallest_ritz = std::numeric_limits<double>::quiet_NaN();

 protected:
  void sort_ritzpair(Spectra::SortRule rule) override {
    smallest_ritz = this->m_ritz_val.minCoeff();
    Spectra::SymEigsSolver<ProductOp>::sort_ritzpair(rule);
  }
};

// `count` orthonormal columns: those of `basis`, then unit vectors made orthogonal to every
// column before them (Gram–Schmidt, twice).
Eigen::MatrixXd extend_orthonormal(const Eigen::MatrixXd& basis, Eigen::Index count) {
  const Eigen::Index n = basis.rows();
  Eigen::MatrixXd v(n, count);
  Eigen::Index have = std::min(basis.cols(), count);
  v.leftCols(have) = basis.leftCols(have);
  for (Eigen::Index e = 0; e < n && have < count; ++e) {
    Eigen::VectorXd u = Eigen::VectorXd::Unit(n, e);
    for (int pass = 0; pass < 2; ++pass) u -= v.leftCols(have) * (v.leftCols(have).transpose() * u);
    if (u.norm() > 0.5) v.col(have++) = u.normalized();
  }
  return v;
}

// Whether every pair satisfies A·v = λ·v, checked with one product (they can cost as much as a
// tenth of the solve): for w = Σ cᵢ·vᵢ with unequal weights, ‖A·w − Σ cᵢ·λᵢ·vᵢ‖ ≤ 1e-6 · ‖A·w‖.
bool pairs_hold(Eigen::Index n, const Product& product, const EigenPairs& pairs) {
  if (!pairs.values.allFinite()) return false;
  const Eigen::Index count = pairs.values.size();
  const Eigen::VectorXd c = Eigen::VectorXd::LinSpaced(count, 1.0, 2.0);
  const Eigen::VectorXd w = pairs.vectors * c;
  Eigen::VectorXd aw(n);
  product(w.data(), aw.data());
  const double residual = (aw - pairs.vectors * c.cwiseProduct(pairs.values)).norm();
  return residual <= 1e-6 * aw.norm();
}

// The eigenpairs of an operator of rank below `block`, exactly: Rayleigh–Ritz on the range of
// A·Ω for `block` probe vectors Ω, which is A's whole range; the other eigenvalues are 0, with
// any vectors orthogonal to it. Spectra 1.0's Lanczos breaks down on such operators (the Krylov
// space runs out; a rank-one 60 × 60 Gram matrix came back with λ = 2e25 for 33, and a zero one
// threw; yixuan/spectra#159): the centred data of a static clip, a clip of two poses.
EigenPairs low_rank_eigenpairs(Eigen::Index n, const Product& product, int count,
                               Spectra::SortRule rule, Eigen::Index block) {
  block = std::min(block, n);
  Eigen::MatrixXd omega(n, block), y(n, block);
  std::uint64_t state = 0x9E3779B97F4A7C15ull;  // deterministic, structureless probes
  for (Eigen::Index j = 0; j < block; ++j) {
    for (Eigen::Index i = 0; i < n; ++i) {
      state = state * 6364136223846793005ull + 1442695040888963407ull;
      omega(i, j) = static_cast<double>(state >> 11) * 0x1.0p-53 - 0.5;
    }
    product(omega.col(j).data(), y.col(j).data());
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(y);
  const double largest = qr.matrixQR().diagonal().cwiseAbs().maxCoeff();
  Eigen::Index rank = 0;
  while (rank < block && std::abs(qr.matrixQR()(rank, rank)) > 1e-10 * largest) ++rank;
  const Eigen::MatrixXd q =
      (qr.householderQ() * Eigen::MatrixXd::Identity(n, block)).leftCols(rank);
  Eigen::MatrixXd aq(n, rank);
  for (Eigen::Index j = 0; j < rank; ++j) product(q.col(j).data(), aq.col(j).data());
  const Eigen::MatrixXd t = q.transpose() * aq;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ritz;
  if (rank > 0) ritz.compute(0.5 * (t + t.transpose()));
  // Candidates: the Ritz pairs, and 0 for the rest of the space (if any), in the rule's order.
  struct Candidate {
    double value;
    Eigen::Index ritz;  // column of the Ritz vectors, or -1 for a null vector
  };
  std::vector<Candidate> all;
  for (Eigen::Index j = 0; j < rank; ++j) all.push_back({ritz.eigenvalues()[j], j});
  for (Eigen::Index z = rank; z < n && z < rank + count; ++z) all.push_back({0.0, -1});
  const bool largest_first = rule == Spectra::SortRule::LargestAlge;
  std::stable_sort(all.begin(), all.end(), [&](const Candidate& a, const Candidate& b) {
    return largest_first ? a.value > b.value : a.value < b.value;
  });
  const Eigen::MatrixXd ritz_vectors = rank > 0 ? Eigen::MatrixXd(q * ritz.eigenvectors()) : q;
  const Eigen::Index nulls = std::min<Eigen::Index>(count, n - rank);
  const Eigen::MatrixXd null_vectors = extend_orthonormal(q, rank + nulls).rightCols(nulls);
  EigenPairs out;
  out.values.resize(count);
  out.vectors.resize(n, count);
  int next_null = 0;
  for (int a = 0; a < count; ++a) {
    out.values[a] = all[a].value;
    out.vectors.col(a) =
        all[a].ritz >= 0 ? ritz_vectors.col(all[a].ritz) : null_vectors.col(next_null++);
  }
  out.products = static_cast<int>(block + rank);
  out.smallest_ritz = largest_first ? all.back().value : all.front().value;  // exact here
  return out;
}

// Runs Lanczos for the `count` eigenpairs at the end `rule` selects; vectors sorted as `rule`.
EigenPairs lanczos(Eigen::Index n, const Product& product, int count, Spectra::SortRule rule,
                   std::string_view what, double tolerance, int lanczos_vectors = 0) {
  ProductOp op(n, product);
  const Eigen::Index ncv = std::min<Eigen::Index>(
      n, lanczos_vectors > 0 ? std::max(lanczos_vectors, count + 2) : std::max(2 * count + 1, 20));
  EigenPairs out;
  Eigen::Index nconv = 0;
  Spectra::CompInfo info = Spectra::CompInfo::NotComputed;
  std::string failure;  // why Spectra's answer cannot be used
  try {
    RitzSolver solver(op, count, ncv);
    solver.init();
    nconv = solver.compute(rule, kMaxRestarts, tolerance, rule);
    info = solver.info();
    out.restarts = static_cast<int>(solver.num_iterations());
    out.products = static_cast<int>(solver.num_operations());
    if (info == Spectra::CompInfo::Successful) {
      out.values = solver.eigenvalues();
      out.vectors = solver.eigenvectors();
      out.smallest_ritz = solver.smallest_ritz;
    }
  } catch (const motionmap::Error&) {
    throw;  // Cancelled from inside the product
  } catch (const std::exception& e) {
    failure = std::string(": the Lanczos eigen solver failed: ") + e.what();
  }
  if (failure.empty() && info != Spectra::CompInfo::Successful) {
    throw NumericalError(
        std::string(what) +
        ": the Lanczos eigen solver did not converge: " + std::to_string(nconv) + " of " +
        std::to_string(count) + " eigenpairs converged in " + std::to_string(out.restarts) +
        " Lanczos iterations (" + std::to_string(out.products) + " products, tolerance " +
        format_number(tolerance, 6) + ", " + std::to_string(ncv) + " Lanczos vectors)");
  }
  // Every pair is checked against the operator: Spectra 1.0 throws on a zero operator and
  // reports converged pairs that are not eigenpairs when the operator's rank is below the
  // Lanczos basis; low_rank_eigenpairs then gives the exact answer.
  if (failure.empty()) {
    if (pairs_hold(n, product, out)) return out;
    failure = ": the Lanczos eigen solver returned eigenpairs with A·v far from λ·v (λ₁ = " +
              format_number(out.values[0], 6) + ")";
  }
  EigenPairs exact = low_rank_eigenpairs(n, product, count, rule, ncv + 4);
  if (pairs_hold(n, product, exact)) return exact;
  throw NumericalError(std::string(what) + failure);
}

}  // namespace

EigenPairs largest_eigenpairs(Eigen::Index n, const Product& product, int count,
                              std::string_view what, double tolerance, int lanczos_vectors) {
  check_count(n, count, static_cast<int>(n) - 1, what);
  return lanczos(n, product, count, Spectra::SortRule::LargestAlge, what, tolerance,
                 lanczos_vectors);
}

EigenPairs largest_eigenpairs(const Eigen::MatrixXd& A, int count, std::string_view what,
                              int dense_limit) {
  const Eigen::Index n = A.rows();
  if (n <= dense_limit) {
    check_count(n, count, static_cast<int>(n), what);
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(A);
    if (solver.info() != Eigen::Success) {
      throw NumericalError(std::string(what) + ": the dense eigen solver did not converge");
    }
    EigenPairs out;
    out.values = solver.eigenvalues().reverse().head(count);
    out.vectors = solver.eigenvectors().rowwise().reverse().leftCols(count);
    out.smallest_ritz = solver.eigenvalues()[0];
    return out;
  }
  const Product product = [&A](const double* x, double* y) {
    Eigen::Map<Eigen::VectorXd>(y, A.rows()).noalias() =
        A.selfadjointView<Eigen::Lower>() * Eigen::Map<const Eigen::VectorXd>(x, A.rows());
  };
  return largest_eigenpairs(n, product, count, what);
}

EigenPairs smallest_eigenpairs_excluding(const Eigen::SparseMatrix<double>& A,
                                         const Eigen::VectorXd& null_vector, int count,
                                         std::string_view what, const Control& control,
                                         int dense_limit, const ShiftInvert& shift_invert) {
  const Eigen::Index n = A.rows();
  check_count(n, count, static_cast<int>(n) - 2, what);
  const Eigen::VectorXd& q = null_vector;
  // ‖A‖∞ bounds A's spectrum.
  double norm_inf = 0.0;
  {
    Eigen::VectorXd row_sums = Eigen::VectorXd::Zero(n);
    for (int c = 0; c < A.outerSize(); ++c) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(A, c); it; ++it) {
        row_sums[it.row()] += std::abs(it.value());
      }
    }
    norm_inf = row_sums.maxCoeff();
  }

  EigenPairs out;
  if (n <= dense_limit) {
    // Lift q's eigenvalue 0 above the whole spectrum; the rest is unchanged since A·q = 0.
    Eigen::MatrixXd dense = Eigen::MatrixXd(A);
    dense.noalias() += (2.0 * norm_inf + 1.0) * q * q.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> solver(dense);
    if (solver.info() != Eigen::Success) {
      throw NumericalError(std::string(what) + ": the dense eigen solver did not converge");
    }
    out.vectors = solver.eigenvectors().leftCols(count);
  } else {
    // Shift-invert: A + εI is positive definite, so LDLᵀ needs no pivoting; ε only has to be
    // small next to the wanted eigenvalues' gaps, the solve itself is backward stable.
    const double eps = shift_invert.relative_shift * std::max(norm_inf, 1e-300);
    Eigen::SparseMatrix<double> shifted = A;
    for (Eigen::Index i = 0; i < n; ++i) shifted.coeffRef(i, i) += eps;
    const std::string failed = std::string(what) + ": the sparse LDLT factorization failed (" +
                               std::to_string(n) + " by " + std::to_string(n) + ", shift " +
                               format_number(eps, 6) + ")";
    std::unique_ptr<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower>> ldlt;
    std::unique_ptr<SupernodalLdlt> supernodal;
    if (shift_invert.supernodal) {
      try {
        supernodal = std::make_unique<SupernodalLdlt>(shifted, control);
      } catch (const NumericalError& e) {
        throw NumericalError(failed + ": " + e.what());
      }
    } else {
      ldlt = std::make_unique<Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower>>(
          shifted);
      if (ldlt->info() != Eigen::Success) throw NumericalError(failed);
    }
    Eigen::VectorXd tmp(n);
    const Product product = [&](const double* x, double* y) {
      control.check();
      Eigen::Map<const Eigen::VectorXd> xv(x, n);
      Eigen::Map<Eigen::VectorXd> yv(y, n);
      tmp = xv - q * q.dot(xv);
      if (supernodal) {
        yv = tmp;
        supernodal->solve(yv.data());
      } else {
        yv = ldlt->solve(tmp);
      }
      yv -= q * q.dot(yv);
    };
    out = lanczos(n, product, count, Spectra::SortRule::LargestAlge, what, kEigenTolerance);
  }
  // Rayleigh quotients are more accurate than 1/θ − ε, and sort the pairs ascending.
  out.values.resize(count);
  for (int c = 0; c < count; ++c) {
    out.vectors.col(c).normalize();
    out.values[c] = out.vectors.col(c).dot(A * out.vectors.col(c));
  }
  std::vector<int> order(static_cast<std::size_t>(count));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return out.values[a] < out.values[b]; });
  EigenPairs sorted = out;
  for (int c = 0; c < count; ++c) {
    sorted.values[c] = out.values[order[c]];
    sorted.vectors.col(c) = out.vectors.col(order[c]);
  }
  return sorted;
}

EigenPairs gram_eigenpairs(const Eigen::MatrixXd& gram, int count, std::string_view what) {
  return largest_eigenpairs(gram, count, what, kDenseGramLimit);
}

Eigen::MatrixXd top_singular_scores(const Eigen::MatrixXd& A, const Eigen::RowVectorXd& shift,
                                    const Eigen::RowVectorXd& scale, int count,
                                    std::string_view what,
                                    Eigen::VectorXd& squared_singular_values) {
  const Eigen::Index m = A.rows(), p = A.cols();
  auto transform = [&](Eigen::MatrixXd& block) {
    if (shift.size() > 0) block.rowwise() -= shift;
    if (scale.size() > 0) block.array().rowwise() /= scale.array();
  };
  if (p > m) {
    // Few frames, many features: Z·Zᵀ is the small one; Z itself is small too.
    Eigen::MatrixXd Z = A;
    transform(Z);
    Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(m, m);
    gram.selfadjointView<Eigen::Lower>().rankUpdate(Z);
    EigenPairs top = largest_eigenpairs(gram, count, what, kDenseGramLimit);
    squared_singular_values = top.values;
    return top.vectors * top.values.cwiseMax(0.0).cwiseSqrt().asDiagonal();
  }
  // ZᵀZ (lower triangle) over row chunks; a fixed chunk count keeps the summation order, and so
  // the result, independent of the number of threads. The Gram matrix squares the condition
  // number, which costs accuracy only on the small singular values; the maps use the largest.
  const int chunks = m >= 1024 ? kGramChunks : 1;
  const Eigen::Index rows_per_chunk = (m + chunks - 1) / chunks;
  std::vector<Eigen::MatrixXd> partial(static_cast<std::size_t>(chunks));
  auto rows_of = [&](int c, Eigen::MatrixXd& block) {
    const Eigen::Index r0 = std::min(m, c * rows_per_chunk);
    block = A.middleRows(r0, std::min(m, r0 + rows_per_chunk) - r0);
    transform(block);
  };
  parallel_chunks(chunks, [&](int c, int) {
    Eigen::MatrixXd block;
    rows_of(c, block);
    partial[c] = Eigen::MatrixXd::Zero(p, p);
    partial[c].selfadjointView<Eigen::Lower>().rankUpdate(block.transpose());
  });
  Eigen::MatrixXd gram = partial[0];
  for (int c = 1; c < chunks; ++c) gram += partial[c];
  EigenPairs top = largest_eigenpairs(gram, count, what, kDenseGramLimit);
  squared_singular_values = top.values;
  Eigen::MatrixXd scores(m, count);
  parallel_chunks(chunks, [&](int c, int) {
    Eigen::MatrixXd block;
    rows_of(c, block);
    scores.middleRows(std::min(m, c * rows_per_chunk), block.rows()).noalias() =
        block * top.vectors;
  });
  // An axis without variance is 0, not the rounding noise of a product with a null vector.
  for (int a = 0; a < count; ++a) {
    if (!(top.values[a] > 0.0)) scores.col(a).setZero();
  }
  return scores;
}

std::vector<bool> normalize_signs(Eigen::MatrixXd& M) {
  std::vector<bool> flipped(std::size_t(M.cols()), false);
  for (Eigen::Index c = 0; c < M.cols(); ++c) {
    Eigen::Index arg = 0;
    double best = -1.0;
    for (Eigen::Index r = 0; r < M.rows(); ++r) {
      if (std::abs(M(r, c)) > best) {
        best = std::abs(M(r, c));
        arg = r;
      }
    }
    // (+ 0.0 turns the −0 of a flipped zero back into +0, for byte-identical text output.)
    if (M.rows() > 0 && M(arg, c) < 0.0) {
      M.col(c) = (-M.col(c)).array() + 0.0;
      flipped[std::size_t(c)] = true;
    }
  }
  return flipped;
}

}  // namespace motionmap::embed
