#include "motionmap/core/stats.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace motionmap {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

double median(std::vector<double> values) {
  if (values.empty()) return kNaN;
  // The upper middle value by selection; for an even count the lower middle one is then the
  // largest value before it.
  const std::size_t mid = values.size() / 2;
  const auto upper_it = values.begin() + static_cast<std::ptrdiff_t>(mid);
  std::nth_element(values.begin(), upper_it, values.end());
  const double upper = *upper_it;
  if (values.size() % 2 == 1) return upper;
  return 0.5 * (*std::max_element(values.begin(), upper_it) + upper);
}

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return kNaN;
  std::sort(values.begin(), values.end());
  const double pos = std::clamp(q, 0.0, 1.0) * static_cast<double>(values.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, values.size() - 1);
  return values[lo] + (pos - static_cast<double>(lo)) * (values[hi] - values[lo]);
}

double upper_median(std::vector<double> values) {
  if (values.empty()) return kNaN;
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

}  // namespace motionmap
