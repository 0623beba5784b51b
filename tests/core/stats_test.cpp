#include "motionmap/core/stats.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace motionmap {
namespace {

TEST(StatsMedian, IsNumpysMedian) {
  // numpy.median: the middle value, or the mean of the two middle values.
  EXPECT_EQ(median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(median({4.0, 1.0, 3.0, 2.0}), 2.5);
  EXPECT_EQ(median({7.0}), 7.0);
  EXPECT_EQ(median({5.0, -1.0}), 2.0);
  EXPECT_EQ(median({1.0, 1.0, 2.0, 10.0}), 1.5);
  EXPECT_TRUE(std::isnan(median({})));
}

TEST(StatsMedian, UpperMedianIsTheUpperMiddleValue) {
  EXPECT_EQ(upper_median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(upper_median({4.0, 1.0, 3.0, 2.0}), 3.0);  // numpy.median: 2.5
  EXPECT_EQ(upper_median({7.0}), 7.0);
  EXPECT_TRUE(std::isnan(upper_median({})));
}

TEST(StatsMedian, QuantileIsNumpysLinearQuantile) {
  // numpy.quantile(v, q) (= numpy.percentile(v, 100 q)) with the default method "linear".
  const std::vector<double> v{10.0, 7.0, 4.0, 3.0, 2.0, 1.0};
  EXPECT_DOUBLE_EQ(quantile(v, 0.95), 9.25);
  EXPECT_DOUBLE_EQ(quantile(v, 0.5), 3.5);
  EXPECT_EQ(quantile(v, 0.0), 1.0);
  EXPECT_EQ(quantile(v, 1.0), 10.0);
  EXPECT_DOUBLE_EQ(quantile({1.0, 2.0, 3.0, 4.0}, 0.95), 3.85);
  EXPECT_EQ(quantile({5.0}, 0.3), 5.0);
  EXPECT_TRUE(std::isnan(quantile({}, 0.5)));
}

TEST(StatsMedian, MedianAgreesWithSortingAtRandom) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int n = 1; n < 40; ++n) {
    std::vector<double> v(static_cast<std::size_t>(n));
    for (double& x : v) x = u(rng);
    std::vector<double> sorted = v;
    std::sort(sorted.begin(), sorted.end());
    const std::size_t mid = sorted.size() / 2;
    const double expected = n % 2 ? sorted[mid] : 0.5 * (sorted[mid - 1] + sorted[mid]);
    EXPECT_EQ(median(v), expected) << n;
    EXPECT_EQ(upper_median(v), sorted[mid]) << n;
    EXPECT_NEAR(quantile(v, 0.5), expected, 1e-15) << n;
  }
}

}  // namespace
}  // namespace motionmap
