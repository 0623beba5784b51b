#include "motionmap/synth/detail/blocked_lu.h"

#include <algorithm>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/LU>

#include "motionmap/core/error.h"
#include "motionmap/core/parallel.h"

namespace motionmap::synth::detail {
namespace {

// Sizes around and off the panel width (64) and the solves' block (256).
constexpr int kSizes[] = {1, 2, 63, 64, 65, 200, 777};

Eigen::MatrixXd random_matrix(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd a(n, n);
  for (Eigen::Index j = 0; j < n; ++j)
    for (Eigen::Index i = 0; i < n; ++i) a(i, j) = u(rng);
  return a;
}

// The bordered linear-variogram matrix [A 1; 1ᵀ 0] of n − 1 random map points (A_ij = ‖c_i −
// c_j‖): zeros on the diagonal, so it cannot be factored without pivoting.
Eigen::MatrixXd kriging_matrix(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  const int np = n - 1;
  std::vector<Eigen::Vector2d> p(static_cast<std::size_t>(np));
  for (auto& c : p) c = Eigen::Vector2d(u(rng), u(rng));
  Eigen::MatrixXd a(n, n);
  for (int j = 0; j < np; ++j) {
    for (int i = 0; i < np; ++i) a(i, j) = (p[i] - p[j]).norm();
    a(np, j) = a(j, np) = 1.0;
  }
  a(np, np) = 0.0;
  return a;
}

// Solutions of A·X = B and Aᵀ·X = B agree with Eigen::PartialPivLU's to within what the
// condition number allows, and so do the reciprocal condition estimates.
void expect_matches_eigen(const Eigen::MatrixXd& a, const std::string& what) {
  SCOPED_TRACE(what + ", n = " + std::to_string(a.rows()));
  const Eigen::PartialPivLU<Eigen::MatrixXd> ref(a);
  const BlockedLu lu(a);
  ASSERT_EQ(lu.size(), a.rows());
  const double rcond = ref.rcond();
  const double tol = 1e-14 / rcond;  // forward error ≲ κ·ε
  const Eigen::MatrixXd b =
      random_matrix(static_cast<int>(a.rows()), 99).leftCols(std::min<Eigen::Index>(3, a.rows()));
  Eigen::MatrixXd x = b;
  lu.solve_in_place(x);
  const Eigen::MatrixXd expected = ref.solve(b);
  EXPECT_LE((x - expected).norm(), tol * expected.norm());
  EXPECT_LE((a * x - b).norm(), 1e-12 * a.norm() * x.norm());
  Eigen::MatrixXd xt = b;
  lu.solve_transposed_in_place(xt);
  const Eigen::MatrixXd expected_t = ref.transpose().solve(b);
  EXPECT_LE((xt - expected_t).norm(), tol * expected_t.norm());
  // The same estimator: equal up to rounding unless a near tie in its choices went another way.
  EXPECT_NEAR(lu.rcond(), rcond, 1e-6 * rcond);
  EXPECT_DOUBLE_EQ(lu.l1_norm(), a.cwiseAbs().colwise().sum().maxCoeff());
  // P·A = L·U, with |L| ≤ 1 (partial pivoting).
  const Eigen::Index n = a.rows();
  const Eigen::MatrixXd L = lu.factors().triangularView<Eigen::UnitLower>();
  const Eigen::MatrixXd U = lu.factors().triangularView<Eigen::Upper>();
  Eigen::MatrixXd pa = a;
  for (Eigen::Index k = 0; k < n; ++k) {
    ASSERT_GE(lu.pivots()[k], k);
    ASSERT_LT(lu.pivots()[k], n);
    pa.row(k).swap(pa.row(lu.pivots()[k]));
  }
  EXPECT_LE((pa - L * U).norm(), 1e-13 * a.norm());
  EXPECT_LE(L.cwiseAbs().maxCoeff(), 1.0);
}

TEST(SynthBlockedLu, MatchesPartialPivLuOnRandomMatrices) {
  for (int n : kSizes) expect_matches_eigen(random_matrix(n, 7 + n), "random");
}

TEST(SynthBlockedLu, MatchesPartialPivLuOnKrigingMatrices) {
  for (int n : kSizes) {
    if (n < 2) continue;
    expect_matches_eigen(kriging_matrix(n, 3 + n), "kriging");
  }
}

TEST(SynthBlockedLu, FactorsDoNotDependOnTheThreadCount) {
  // A loop started inside a parallel loop's body runs on its calling thread alone: the same
  // factorisation once on every pool thread, once on one thread, bit for bit.
  const Eigen::MatrixXd a = kriging_matrix(700, 17);
  const BlockedLu pooled(a);
  std::optional<BlockedLu> single;
  parallel_for(2, [&](int i) {
    if (i == 0) single.emplace(a);
  });
  ASSERT_TRUE(single.has_value());
  EXPECT_EQ(single->pivots(), pooled.pivots());
  EXPECT_TRUE(single->factors() == pooled.factors());
}

TEST(SynthBlockedLu, RcondOfSingularAndTrivialMatrices) {
  Eigen::MatrixXd singular = random_matrix(130, 5);
  singular.col(100) = singular.col(3) * 2.0 - singular.col(77);  // rank deficient
  EXPECT_LT(BlockedLu(singular).rcond(), 1e-15);
  EXPECT_EQ(BlockedLu(Eigen::MatrixXd::Zero(70, 70)).rcond(), 0.0);
  EXPECT_EQ(BlockedLu(Eigen::MatrixXd::Constant(1, 1, 4.0)).rcond(), 1.0);
  EXPECT_NEAR(BlockedLu(Eigen::MatrixXd::Identity(100, 100)).rcond(), 1.0, 1e-14);
  const BlockedLu empty;
  EXPECT_EQ(empty.size(), 0);
  EXPECT_THROW(BlockedLu(Eigen::MatrixXd(3, 4)), ParameterError);
  Eigen::MatrixXd wrong(5, 1);
  EXPECT_THROW(BlockedLu(random_matrix(4, 1)).solve_in_place(wrong), ParameterError);
}

TEST(SynthBlockedLu, ReportsProgressAndStopsWhenCancelled) {
  std::vector<double> fractions;
  int polls = 0;
  const Control watch([&](double f, std::string_view) { fractions.push_back(f); },
                      [&] { return ++polls < 0; });
  const BlockedLu lu(kriging_matrix(500, 1), watch);
  ASSERT_FALSE(fractions.empty());
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_EQ(fractions.back(), 1.0);
  EXPECT_GT(polls, 8);  // between panels and column blocks, not only at the ends

  // Cancelled after the first few polls: stops with Cancelled.
  int left = 5;
  const Control cancel({}, [&] { return --left < 0; });
  EXPECT_THROW(BlockedLu(kriging_matrix(500, 1), cancel), Cancelled);
}

}  // namespace
}  // namespace motionmap::synth::detail
