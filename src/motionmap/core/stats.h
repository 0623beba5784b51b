#pragma once
// Order statistics of a list of numbers: the one median of the library (numpy.median), linear
// quantiles (numpy.quantile), and the upper median that a few older call sites keep.
//
//   const double m = motionmap::median(steps);           // numpy.median(steps)
//   const double p95 = motionmap::quantile(steps, 0.95);  // numpy.quantile(steps, 0.95)
//
// Every function takes its values by value (it reorders its copy; move a vector in to avoid
// the copy), returns NaN for an empty list, and expects no NaN among the values.
#include <vector>

namespace motionmap {

/// numpy.median: the middle value of the sorted values for an odd count, the mean of the two
/// middle values for an even count (0.5·(lower + upper)). NaN if `values` is empty.
double median(std::vector<double> values);

/// numpy.quantile(values, q) with its default method "linear" (numpy.percentile(values, 100·q)):
/// position q·(n − 1) in the sorted values, interpolated linearly between its two neighbours,
/// lower + (pos − ⌊pos⌋)·(upper − lower). q in [0, 1] (clamped). NaN if `values` is empty.
/// Note quantile(v, 0.5) equals median(v) up to rounding, not bit for bit.
double quantile(std::vector<double> values, double q);

/// The ⌊n/2⌋-th smallest value (0-based): the median for an odd count, the upper of the two
/// middle values for an even count. Not numpy's median: kept by the call sites that have always
/// used it (the leading bind-pose test, the blender's median map step and speed), whose results
/// would otherwise change. NaN if `values` is empty.
double upper_median(std::vector<double> values);

}  // namespace motionmap
