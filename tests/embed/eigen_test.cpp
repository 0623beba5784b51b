// Eigen wrappers: residuals ‖A·v − λ·v‖, orthonormality, dense path = Lanczos path, the null
// vector skipped, Ritz estimates, the sign convention, and the error messages.
#include <cmath>
#include <limits>
#include <random>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCore>

#include "motionmap/core/error.h"
#include "motionmap/embed/eigen.h"

namespace motionmap::embed {
namespace {

using ::testing::HasSubstr;

// Symmetric with a known, well spread spectrum: Q·diag(λ)·Qᵀ, λ_i = 1/(i+1) (a few negative).
Eigen::MatrixXd test_matrix(int n, unsigned seed, Eigen::VectorXd* spectrum = nullptr) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  Eigen::MatrixXd R(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) R(i, j) = g(rng);
  }
  const Eigen::MatrixXd Q = Eigen::HouseholderQR<Eigen::MatrixXd>(R).householderQ();
  Eigen::VectorXd lambda(n);
  for (int i = 0; i < n; ++i) lambda[i] = (i % 7 == 6 ? -0.5 : 1.0) / (i + 1.0);
  if (spectrum) *spectrum = lambda;
  return Q * lambda.asDiagonal() * Q.transpose();
}

// The path graph's Laplacian L = Deg − W (weights 1): eigenvalues 2 − 2·cos(π·m/n), m = 0 … n−1,
// null vector the constant.
Eigen::SparseMatrix<double> path_laplacian(int n) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, (i == 0 || i == n - 1) ? 1.0 : 2.0);
    if (i + 1 < n) {
      t.emplace_back(i, i + 1, -1.0);
      t.emplace_back(i + 1, i, -1.0);
    }
  }
  Eigen::SparseMatrix<double> L(n, n);
  L.setFromTriplets(t.begin(), t.end());
  return L;
}

void expect_eigenpairs(const Eigen::MatrixXd& A, const EigenPairs& p, double tol) {
  for (Eigen::Index c = 0; c < p.values.size(); ++c) {
    const Eigen::VectorXd v = p.vectors.col(c);
    EXPECT_NEAR(v.norm(), 1.0, 1e-12);
    EXPECT_LE((A * v - p.values[c] * v).norm(), tol) << "pair " << c;
  }
  const Eigen::MatrixXd gram = p.vectors.transpose() * p.vectors;
  EXPECT_LE((gram - Eigen::MatrixXd::Identity(gram.rows(), gram.cols())).cwiseAbs().maxCoeff(),
            1e-9);
}

TEST(EmbedEigen, LargestDenseAndLanczosAgree) {
  Eigen::VectorXd lambda;
  const Eigen::MatrixXd A = test_matrix(300, 1, &lambda);
  const EigenPairs dense = largest_eigenpairs(A, 3, "test", 1000);
  const EigenPairs lanczos = largest_eigenpairs(A, 3, "test", 10);
  EXPECT_EQ(dense.restarts, 0);
  EXPECT_GT(lanczos.products, 0);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(dense.values[c], 1.0 / (c + 1.0), 1e-12);
    EXPECT_NEAR(lanczos.values[c], 1.0 / (c + 1.0), 1e-12);
    EXPECT_NEAR(std::abs(dense.vectors.col(c).dot(lanczos.vectors.col(c))), 1.0, 1e-12);
  }
  expect_eigenpairs(A, dense, 1e-12);
  expect_eigenpairs(A, lanczos, 1e-9);
}

TEST(EmbedEigen, LargestReadsTheLowerTriangleOnly) {
  Eigen::MatrixXd A = test_matrix(250, 2);
  const EigenPairs want = largest_eigenpairs(A, 2, "test");
  A.triangularView<Eigen::StrictlyUpper>().setConstant(1e6);  // garbage above the diagonal
  for (int limit : {10, 1000}) {
    const EigenPairs got = largest_eigenpairs(A, 2, "test", limit);
    EXPECT_NEAR(got.values[0], want.values[0], 1e-10);
    EXPECT_NEAR(got.values[1], want.values[1], 1e-10);
  }
}

TEST(EmbedEigen, SmallestExcludingTheNullVector) {
  const int n = 400;
  const Eigen::SparseMatrix<double> L = path_laplacian(n);
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(n, 1.0 / std::sqrt(double(n)));
  const EigenPairs sparse = smallest_eigenpairs_excluding(L, q, 3, "test", {}, 10);
  const EigenPairs dense = smallest_eigenpairs_excluding(L, q, 3, "test", {}, 1000);
  const Eigen::MatrixXd Ld(L);
  for (int c = 0; c < 3; ++c) {
    const double want = 2.0 - 2.0 * std::cos(M_PI * (c + 1) / n);
    EXPECT_NEAR(sparse.values[c], want, 1e-12 * want + 1e-16);
    EXPECT_NEAR(dense.values[c], want, 1e-12);
    EXPECT_NEAR(std::abs(sparse.vectors.col(c).dot(dense.vectors.col(c))), 1.0, 1e-9);
    EXPECT_LE(std::abs(sparse.vectors.col(c).dot(q)), 1e-12);
  }
  expect_eigenpairs(Ld, sparse, 1e-10);
  expect_eigenpairs(Ld, dense, 1e-12);
}

TEST(EmbedEigen, SmallestRitzValueBoundsTheSmallestEigenvalue) {
  Eigen::VectorXd lambda;
  const Eigen::MatrixXd A = test_matrix(300, 3, &lambda);
  const double smallest = lambda.minCoeff();  // −0.5/7
  const EigenPairs lanczos = largest_eigenpairs(A, 2, "test", 10);
  EXPECT_GE(lanczos.smallest_ritz, smallest - 1e-12);
  EXPECT_LE(lanczos.smallest_ritz, 0.9 * smallest);
  const EigenPairs dense = largest_eigenpairs(A, 2, "test", 1000);
  EXPECT_NEAR(dense.smallest_ritz, smallest, 1e-12);
}

TEST(EmbedEigen, TopSingularScores) {
  std::mt19937 rng(4);
  std::normal_distribution<double> g;
  // Tall (Gram ZᵀZ, chunked in parallel above 1024 rows) and wide (Z·Zᵀ).
  for (const auto& [rows, cols] : {std::pair{60, 8}, std::pair{3000, 8}, std::pair{8, 60}}) {
    Eigen::MatrixXd A(rows, cols);
    for (int i = 0; i < rows; ++i) {
      for (int j = 0; j < cols; ++j) A(i, j) = g(rng) * (1.0 + j) + 10.0;
    }
    Eigen::RowVectorXd shift(cols), scale(cols);
    for (int j = 0; j < cols; ++j) {
      shift[j] = 10.0 + 0.1 * j;
      scale[j] = 0.5 + 0.2 * j;
    }
    for (bool transformed : {false, true}) {
      Eigen::MatrixXd Z = A;
      if (transformed) Z = ((A.rowwise() - shift).array().rowwise() / scale.array()).matrix();
      Eigen::VectorXd s2;
      const Eigen::MatrixXd scores = transformed
                                         ? top_singular_scores(A, shift, scale, 2, "test", s2)
                                         : top_singular_scores(A, {}, {}, 2, "test", s2);
      Eigen::JacobiSVD<Eigen::MatrixXd> svd(Z, Eigen::ComputeThinU);
      for (int c = 0; c < 2; ++c) {
        const double sigma = svd.singularValues()[c];
        EXPECT_NEAR(s2[c], sigma * sigma, 1e-10 * sigma * sigma);
        const Eigen::VectorXd want = svd.matrixU().col(c) * sigma;
        EXPECT_NEAR(std::abs(scores.col(c).dot(want)), want.squaredNorm(),
                    1e-9 * want.squaredNorm());
      }
    }
  }
}

TEST(EmbedEigen, RankBelowTheLanczosBasisGivesExactPairs) {
  // Spectra 1.0's Lanczos breaks down when the operator's rank is below its basis (a rank-one
  // Gram matrix came back with λ = 2e25, a zero one threw): a static clip, a clip of two poses.
  // Such operators are solved exactly; the missing eigenvalues are 0, with vectors orthogonal to
  // the range.
  std::mt19937 rng(7);
  std::normal_distribution<double> g;
  const int n = 60;  // above the dense limit: Lanczos
  for (int rank : {0, 1, 2}) {
    Eigen::MatrixXd V(n, rank);
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < rank; ++j) V(i, j) = g(rng) * (3.0 - j);
    }
    const Eigen::MatrixXd A = V * V.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> dense(A);
    const Product product = [&](const double* x, double* y) {
      Eigen::Map<Eigen::VectorXd>(y, n).noalias() = A * Eigen::Map<const Eigen::VectorXd>(x, n);
    };
    for (const EigenPairs& e :
         {largest_eigenpairs(A, 3, "test", 32), largest_eigenpairs(n, product, 3, "test")}) {
      ASSERT_EQ(e.values.size(), 3);
      for (int a = 0; a < 3; ++a) {
        const double want = dense.eigenvalues()[n - 1 - a];
        EXPECT_NEAR(e.values[a], want, 1e-10 * (1.0 + std::abs(dense.eigenvalues()[n - 1])))
            << "rank " << rank << " pair " << a;
        const Eigen::VectorXd v = e.vectors.col(a);
        EXPECT_NEAR(v.norm(), 1.0, 1e-12);
        EXPECT_LE((A * v - e.values[a] * v).norm(), 1e-9 * (1.0 + A.norm())) << "rank " << rank;
      }
      EXPECT_LE((e.vectors.transpose() * e.vectors - Eigen::MatrixXd::Identity(3, 3)).norm(),
                1e-12);
    }
  }
  // Scores of data with fewer dimensions than asked: the flat axes are exactly 0.
  for (const auto& [rows, cols] : {std::pair{60, 120}, std::pair{3000, 40}}) {
    Eigen::MatrixXd X(rows, cols);
    for (int i = 0; i < rows; ++i) {
      for (int j = 0; j < cols; ++j) X(i, j) = (i % 2 == 0 ? 1.0 : -1.0) * (j + 1) + 5.0;
    }
    const Eigen::RowVectorXd mean = X.colwise().mean();
    Eigen::VectorXd s2;
    const Eigen::MatrixXd centred = top_singular_scores(X, mean, {}, 2, "test", s2);  // rank 1
    EXPECT_GT(s2[0], 0.0);
    EXPECT_EQ(s2[1], 0.0);
    EXPECT_TRUE(centred.col(1).isZero(0.0));
    EXPECT_NEAR(centred.col(0).cwiseAbs().minCoeff(), (X.row(0) - mean).norm(), 1e-9 * s2[0]);
    const Eigen::MatrixXd constant =
        top_singular_scores(Eigen::MatrixXd::Constant(rows, cols, 2.0),
                            Eigen::RowVectorXd::Constant(cols, 2.0), {}, 2, "test", s2);  // rank 0
    EXPECT_EQ(s2[0], 0.0);
    EXPECT_TRUE(constant.isZero(0.0));
  }
}

TEST(EmbedEigen, NormalizeSigns) {
  Eigen::MatrixXd M(4, 3);
  M << 1, -5, 0,  //
      -3, 2, 0,   //
      2, 5, 0,    //
      0, 0, 0;
  normalize_signs(M);
  EXPECT_EQ(M.col(0), Eigen::Vector4d(-1, 3, -2, 0));  // −3 was the largest magnitude
  EXPECT_EQ(M.col(1), Eigen::Vector4d(5, -2, -5, 0));  // tie |−5| = |5|: the first wins
  EXPECT_EQ(M.col(2), Eigen::Vector4d::Zero());
  EXPECT_FALSE(std::signbit(M(3, 0)));  // no −0 after a flip
}

TEST(EmbedEigen, ErrorMessages) {
  const Eigen::MatrixXd A = test_matrix(5, 5);
  try {
    largest_eigenpairs(A, 6, "pca");
    ADD_FAILURE();
  } catch (const ParameterError& e) {
    EXPECT_THAT(e.what(), HasSubstr("pca: cannot compute 6 eigenpairs of a 5 by 5 matrix (at "
                                    "most 5)"));
  }
  // Tolerance 0 can never be met: Lanczos runs out of restarts.
  const Eigen::MatrixXd B = test_matrix(100, 6);
  const Product product = [&](const double* x, double* y) {
    Eigen::Map<Eigen::VectorXd>(y, 100) = B * Eigen::Map<const Eigen::VectorXd>(x, 100);
  };
  try {
    largest_eigenpairs(100, product, 2, "mds", 0.0);
    ADD_FAILURE();
  } catch (const NumericalError& e) {
    EXPECT_THAT(e.what(), HasSubstr("mds: the Lanczos eigen solver did not converge: "));
    EXPECT_THAT(e.what(), HasSubstr("0 of 2 eigenpairs converged in 1001 Lanczos iterations ("));
    EXPECT_THAT(e.what(), HasSubstr(" products, tolerance 0, 20 Lanczos vectors)"));
  }
  // Non-finite products: Spectra's own failure, reported as a NumericalError.
  const Product nan = [](const double*, double* y) {
    for (int i = 0; i < 100; ++i) y[i] = std::numeric_limits<double>::quiet_NaN();
  };
  try {
    largest_eigenpairs(100, nan, 2, "isomap");
    ADD_FAILURE();
  } catch (const NumericalError& e) {
    EXPECT_THAT(e.what(), HasSubstr("isomap: the Lanczos eigen solver failed: "));
  }
}

}  // namespace
}  // namespace motionmap::embed
