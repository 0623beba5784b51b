// Map quality metrics: known answers, a brute-force trustworthiness from the definition, and
// the error messages. (Agreement with sklearn.manifold.trustworthiness on the reference maps is
// in reference_test.cpp.)
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "embed/embed_test_util.h"
#include "motionmap/core/error.h"
#include "motionmap/embed/metrics.h"

namespace motionmap::embed {
namespace {

using ::testing::HasSubstr;

// Venna & Kaski's definition, by full sorts: ranks in `rank_space`, neighbours in `nbr_space`.
double brute_trust(const Eigen::MatrixXd& rank_space, const Eigen::MatrixXd& nbr_space, int k) {
  const int n = static_cast<int>(rank_space.rows());
  auto order = [&](const Eigen::MatrixXd& M, int i) {
    std::vector<int> o;
    for (int j = 0; j < n; ++j) {
      if (j != i) o.push_back(j);
    }
    std::stable_sort(o.begin(), o.end(), [&](int a, int b) { return M(a, i) < M(b, i); });
    return o;
  };
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    const std::vector<int> ranked = order(rank_space, i);
    const std::vector<int> near = order(nbr_space, i);
    for (int a = 0; a < k; ++a) {
      const int j = near[a];
      const int rank = int(std::find(ranked.begin(), ranked.end(), j) - ranked.begin()) + 1;
      if (rank > k) sum += rank - k;
    }
  }
  return 1.0 - 2.0 / (n * k * (2.0 * n - 3.0 * k - 1.0)) * sum;
}

Eigen::MatrixXd random_matrix(int rows, int cols, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  Eigen::MatrixXd M(rows, cols);
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) M(i, j) = g(rng);
  }
  return M;
}

TEST(EmbedMetrics, PerfectMapScoresOne) {
  const Eigen::MatrixXd Y = random_matrix(50, 2, 1);
  const Eigen::MatrixXd D = test::euclidean_distances(Y);
  const NeighborhoodQuality q = neighborhood_quality(D, 3.0 * Y);
  EXPECT_DOUBLE_EQ(q.trustworthiness, 1.0);
  EXPECT_DOUBLE_EQ(q.continuity, 1.0);
  EXPECT_LE(normalized_stress(D, 3.0 * Y), 1e-12);
}

TEST(EmbedMetrics, TrustworthinessAndContinuityFromTheDefinition) {
  for (unsigned seed : {1u, 2u, 3u}) {
    const Eigen::MatrixXd X = random_matrix(70, 5, seed);
    const Eigen::MatrixXd Y = X.leftCols(2) + 0.3 * random_matrix(70, 2, seed + 10);
    const Eigen::MatrixXd D = test::euclidean_distances(X);
    const Eigen::MatrixXd E = test::euclidean_distances(Y);
    for (int k : {1, 5, 10, 34}) {
      const NeighborhoodQuality q = neighborhood_quality(D, Y, k);
      EXPECT_NEAR(q.trustworthiness, brute_trust(D, E, k), 1e-12) << k;
      EXPECT_NEAR(q.continuity, brute_trust(E, D, k), 1e-12) << k;
      EXPECT_LT(q.trustworthiness, 1.0);
      EXPECT_EQ(trustworthiness(D, Y, k), q.trustworthiness);
      EXPECT_EQ(continuity(D, Y, k), q.continuity);
    }
  }
}

TEST(EmbedMetrics, StressKnownValues) {
  // Three frames on a line at 0, 1, 2 (distances 1, 1, 2) mapped to 0, 1, 3 (1, 2, 3):
  // s = Σte/Σe² = (1 + 2 + 6)/(1 + 4 + 9) = 9/14, stress² = 1 − 81/(6·14) = 3/84.
  Eigen::MatrixXd T(3, 3);
  T << 0, 1, 2, 1, 0, 1, 2, 1, 0;
  Eigen::MatrixXd Y(3, 2);
  Y << 0, 0, 1, 0, 3, 0;
  EXPECT_NEAR(normalized_stress(T, Y), std::sqrt(3.0 / 84.0), 1e-15);
  // Only the lower triangle is read.
  T(0, 2) = 99.0;
  EXPECT_NEAR(normalized_stress(T, Y), std::sqrt(3.0 / 84.0), 1e-15);
  // A map collapsed to one point: 1; all target distances 0: 0.
  EXPECT_EQ(normalized_stress(T, Eigen::MatrixXd::Zero(3, 2)), 1.0);
  EXPECT_EQ(normalized_stress(Eigen::MatrixXd::Zero(3, 3), Y), 0.0);
}

TEST(EmbedMetrics, JumpScore) {
  // Steps 1 (×19) and 10 (×1): median 1; the 95th percentile of 20 sorted steps sits at
  // position 0.95·19 = 18.05, between 1 and 10: 1 + 0.05·9 = 1.45.
  Eigen::MatrixXd Y = Eigen::MatrixXd::Zero(21, 2);
  for (int f = 1; f < 21; ++f) Y(f, 0) = Y(f - 1, 0) + (f == 11 ? 10.0 : 1.0);
  EXPECT_NEAR(jump_score(Y), 1.45, 1e-12);
  // Even steps: 1. No motion at all: 1. Mostly still with a jump: inf.
  Eigen::MatrixXd even(5, 2);
  even << 0, 0, 1, 0, 2, 0, 3, 0, 4, 0;
  EXPECT_DOUBLE_EQ(jump_score(even), 1.0);
  EXPECT_EQ(jump_score(Eigen::MatrixXd::Zero(5, 2)), 1.0);
  Eigen::MatrixXd still = Eigen::MatrixXd::Zero(30, 2);
  still(29, 0) = 1.0;
  still(28, 0) = 2.0;
  EXPECT_TRUE(std::isinf(jump_score(still)));
}

TEST(EmbedMetrics, ErrorMessages) {
  const Eigen::MatrixXd Y = random_matrix(20, 2, 4);
  const Eigen::MatrixXd D = test::euclidean_distances(Y);
  try {
    neighborhood_quality(D, Y, 10);
    ADD_FAILURE();
  } catch (const ParameterError& e) {
    EXPECT_THAT(e.what(), HasSubstr("trustworthiness: k = 10 is out of range: with 20 frames it "
                                    "must satisfy 1 ≤ k < 20/2"));
  }
  try {
    neighborhood_quality(D, Y.topRows(19), 3);
    ADD_FAILURE();
  } catch (const ParameterError& e) {
    EXPECT_THAT(e.what(), HasSubstr("trustworthiness: the distance matrix is 20 by 20 and the "
                                    "map has 19 rows"));
  }
  Eigen::MatrixXd bad = Y;
  bad(2, 1) = NAN;
  try {
    neighborhood_quality(D, bad, 3);
    ADD_FAILURE();
  } catch (const ParameterError& e) {
    EXPECT_THAT(e.what(), HasSubstr("the distances and the map must be finite"));
  }
  try {
    normalized_stress(D.leftCols(3), Y);
    ADD_FAILURE();
  } catch (const ParameterError& e) {
    EXPECT_THAT(e.what(), HasSubstr("normalized_stress: the target distances are 20 by 3 and "
                                    "the map has 20 rows"));
  }
  try {
    jump_score(Y.topRows(1));
    ADD_FAILURE();
  } catch (const ParameterError& e) {
    EXPECT_THAT(e.what(), HasSubstr("jump_score: the map has 1 frames; it needs at least 2"));
  }
}

}  // namespace
}  // namespace motionmap::embed
