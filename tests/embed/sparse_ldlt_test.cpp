// The supernodal LDLᵀ of the points path (embed/detail/sparse_ldlt.h) against Eigen's
// SimplicialLDLT: the same factor size (same ordering and structure) and the same solutions, on
// graph Laplacians of several shapes, a dense matrix (one big front: the parallel products), and
// the degenerate cases.
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/SparseCholesky>

#include "motionmap/core/error.h"
#include "motionmap/embed/detail/sparse_ldlt.h"

namespace motionmap::embed {
namespace {

// A random graph's Laplacian plus `shift`·I: `degree` random edges per vertex plus a path
// through all of them (so the structure is connected, like a k-NN graph's).
Eigen::SparseMatrix<double> laplacian(int n, int degree, double shift, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> vertex(0, std::max(0, n - 1));
  std::uniform_real_distribution<double> weight(0.1, 1.0);
  std::vector<Eigen::Triplet<double>> t;
  Eigen::VectorXd deg = Eigen::VectorXd::Zero(n);
  auto edge = [&](int a, int b) {
    if (a == b) return;
    const double w = weight(rng);
    t.emplace_back(a, b, -w);
    t.emplace_back(b, a, -w);
    deg[a] += w;
    deg[b] += w;
  };
  for (int i = 0; i + 1 < n; ++i) edge(i, i + 1);
  for (int i = 0; i < n; ++i) {
    for (int e = 0; e < degree; ++e) edge(i, vertex(rng));
  }
  for (int i = 0; i < n; ++i) t.emplace_back(i, i, deg[i] + shift);
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

void expect_same_as_simplicial(const Eigen::SparseMatrix<double>& A, const char* what) {
  const Eigen::Index n = A.rows();
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> simplicial(A);
  ASSERT_EQ(simplicial.info(), Eigen::Success) << what;
  const SupernodalLdlt supernodal(A);
  EXPECT_EQ(supernodal.rows(), n);
  EXPECT_EQ(supernodal.factor_entries(), simplicial.matrixL().nestedExpression().nonZeros())
      << what;
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 3; ++trial) {
    Eigen::VectorXd b(n);
    for (Eigen::Index i = 0; i < n; ++i) b[i] = normal(rng);
    const Eigen::VectorXd want = simplicial.solve(b);
    Eigen::VectorXd got = b;
    supernodal.solve(got.data());
    EXPECT_LE((got - want).norm(), 1e-10 * want.norm()) << what;
    EXPECT_LE((A.selfadjointView<Eigen::Lower>() * got - b).norm(), 1e-10 * b.norm()) << what;
  }
}

TEST(EmbedSparseLdlt, SolvesAsSimplicialLdlt) {
  for (int n : {1, 2, 7, 300, 4000}) {
    for (int degree : {0, 2, 8}) {
      expect_same_as_simplicial(laplacian(n, degree, 1e-3, unsigned(n * 10 + degree)), "laplacian");
    }
  }
}

TEST(EmbedSparseLdlt, OneBigFrontSplitsItsProducts) {
  // Every entry non-zero: one supernode of 1500 columns, the trailing products over the pool.
  const int n = 1500;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd B(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) B(i, j) = u(rng);
  }
  const Eigen::MatrixXd dense = B * B.transpose() / n + Eigen::MatrixXd::Identity(n, n);
  const Eigen::SparseMatrix<double> A = dense.sparseView();
  expect_same_as_simplicial(A, "dense");
  EXPECT_EQ(SupernodalLdlt(A).supernodes(), 1);
}

TEST(EmbedSparseLdlt, ZeroPivotIsANumericalError) {
  // A Laplacian without its shift is singular: the last pivot of a connected graph is 0 in exact
  // arithmetic; a vertex with no edge gives an exact 0 at once.
  Eigen::SparseMatrix<double> A = laplacian(50, 2, 1.0, 3);
  A.coeffRef(0, 0) = 0.0;
  for (int j = 1; j < 50; ++j) {
    A.coeffRef(j, 0) = 0.0;
    A.coeffRef(0, j) = 0.0;
  }
  EXPECT_THROW(SupernodalLdlt{A}, NumericalError);
}

}  // namespace
}  // namespace motionmap::embed
