#pragma once
// A supernodal sparse LDLᵀ factorization for the shift-invert solves of the points path
// (eigen.h, smallest_eigenpairs_excluding with ShiftInvert::supernodal).
//
//   SupernodalLdlt ldlt(A);   // A: symmetric, its lower triangle read; A = Pᵀ·L·D·Lᵀ·P
//   ldlt.solve(x);            // x ← A⁻¹·x
//
// The ordering P is Eigen's approximate minimum degree, as SimplicialLDLT's, so the factor has
// the same entries; the work is arranged differently. Columns of L with the same structure below
// form a supernode, factorized multifrontally: each supernode's frontal matrix gathers its columns
// of A and its children's update matrices, its pivot columns are eliminated with dense blocked
// kernels (Eigen's matrix products), and what is left is its own update matrix for its parent.
// Subtrees of the supernodal elimination tree run on the thread pool, the big fronts at its top
// split their products over it. No pivoting: for positive definite A (or nearly: a tiny negative
// pivot from rounding is kept, as SimplicialLDLT does). Results do not depend on the thread count:
// every supernode is computed alone, from its children in a fixed order.
// Measured against SimplicialLDLT: bench/embed_bench.cpp, docs/performance.md.
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "motionmap/core/control.h"

namespace motionmap::embed {

class SupernodalLdlt {
 public:
  /// Factorizes A (n by n, symmetric: its lower triangle is read, diagonal included).
  /// @throws NumericalError on a zero or non-finite pivot; Cancelled when `control` says so.
  explicit SupernodalLdlt(const Eigen::SparseMatrix<double>& A, const Control& control = {});

  /// x ← A⁻¹·x for the n values at x.
  void solve(double* x) const;

  Eigen::Index rows() const { return m_n; }
  /// Entries of L below the diagonal (as SimplicialLDLT would hold them).
  std::int64_t factor_entries() const { return m_entries; }
  /// Supernodes of the factorization.
  int supernodes() const { return static_cast<int>(m_nodes.size()); }

 private:
  struct Node {
    int first = 0;  // its columns are [first, last) of the permuted matrix
    int last = 0;
    int parent = -1;        // the supernode holding the parent of column last − 1
    std::vector<int> rows;  // first … last − 1, then the rows below, ascending
    Eigen::MatrixXd L;  // rows.size() by (last − first): unit lower triangle on top, then L₂₁
  };

  // Supernode s's front from its columns of `lower` (the permuted lower triangle) and its
  // children's update matrices (freed); its columns of L and D, and its own update matrix.
  // `control`: on the calling thread, above the parallel subtrees (products split over the pool,
  // cancellation polled per panel); nullptr inside a subtree.
  void factorize_node(int s, const Eigen::SparseMatrix<double>& lower,
                      const std::vector<int>& children, std::vector<Eigen::MatrixXd>& updates,
                      std::vector<int>& slot, const Control* control);

  Eigen::Index m_n = 0;
  std::vector<int> m_perm;     // m_perm[i]: the position of original row i in the factor
  std::vector<Node> m_nodes;   // in column order: children before parents
  std::vector<double> m_diag;  // D
  std::int64_t m_entries = 0;
};

}  // namespace motionmap::embed
