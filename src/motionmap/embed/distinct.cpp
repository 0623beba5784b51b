#include "motionmap/embed/detail/distinct.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "motionmap/core/parallel.h"

namespace motionmap::embed {

namespace {

// The parallel per-frame loops take frames in chunks of this many.
constexpr int kChunk = 4096;

// The points' scale s: sqrt(Σ_ij d_ij² / (2·F²)). For Euclidean points that is the RMS distance
// of the frames to their mean, computed so; for other metrics it is estimated over the pairs of
// at most 1 000 evenly spaced frames.
double points_scale(const PointSet& points, const Control& control) {
  const int n = points.frames();
  const RowMatrix& P = *points.rows;
  if (points.metric == Metric::Euclidean) {
    const Eigen::RowVectorXd mean = P.colwise().mean();
    const int chunks = (n + kChunk - 1) / kChunk;
    std::vector<double> sums(static_cast<std::size_t>(chunks), 0.0);
    parallel_for(
        chunks,
        [&](int c) {
          const int end = std::min(n, (c + 1) * kChunk);
          for (int f = c * kChunk; f < end; ++f) sums[c] += (P.row(f) - mean).squaredNorm();
        },
        control);
    double total = 0.0;
    for (const double s : sums) total += s;
    return std::sqrt(total / n);
  }
  const int m = std::min(n, 1000);
  double total = 0.0;
  for (int a = 0; a < m; ++a) {
    for (int b = 0; b < a; ++b) {
      const double d = points.distance(Eigen::Index(a) * n / m, Eigen::Index(b) * n / m);
      total += d * d;
    }
  }
  return std::sqrt(total / (double(m) * m));
}

// Frame f repeats the first occurrence r < f of smallest index with distance(r, f) ≤ τ
// (`within(r, f)`), if there is one; otherwise it is a first occurrence itself, and `added(f)`
// is told. `candidates(f, offer)` offers frames that may be within τ of f, among them every first
// occurrence that is; frames that are not first occurrences are passed over.
template <class Candidates, class Within, class Added>
DistinctPoses group(int n, const Candidates& candidates, const Within& within, const Added& added) {
  DistinctPoses out;
  out.pose_of.resize(static_cast<std::size_t>(n));
  std::vector<char> is_first(static_cast<std::size_t>(n), 0);
  for (int f = 0; f < n; ++f) {
    int first = -1;
    candidates(f, [&](int r) {
      if (r < f && is_first[r] && (first < 0 || r < first) && within(r, f)) first = r;
    });
    if (first >= 0) {
      out.pose_of[f] = out.pose_of[first];
    } else {
      out.pose_of[f] = static_cast<int>(out.first.size());
      out.first.push_back(f);
      is_first[f] = 1;
      added(f);
    }
  }
  return out;
}

}  // namespace

DistinctPoses distinct_rows(const PointSet& points, const Control& control) {
  const int n = points.frames();
  const RowMatrix& P = *points.rows;
  const double tolerance = kRepeatTolerance * points_scale(points, control.part(0.0, 0.3));
  // Candidates come from a projection onto a fixed random direction u: |u·(a − b)| ≤ ‖a − b‖, and
  // for rows of unit quaternions of one hemisphere ‖a − b‖ ≤ their angle distance, so every
  // frame within τ projects within τ. First occurrences are kept ordered by projection.
  Eigen::VectorXd u(P.cols());
  std::mt19937_64 random(20061127);
  std::normal_distribution<double> normal;
  for (Eigen::Index c = 0; c < u.size(); ++c) u[c] = normal(random);
  u /= u.norm();
  Eigen::VectorXd projection(n);
  const int chunks = (n + kChunk - 1) / kChunk;
  parallel_for(
      chunks,
      [&](int c) {
        const int end = std::min(n, (c + 1) * kChunk);
        for (int f = c * kChunk; f < end; ++f) projection[f] = P.row(f).dot(u);
      },
      control.part(0.3, 0.6));
  std::multimap<double, int> firsts;  // first occurrences by projection
  const Control grouping = control.part(0.6, 1.0);
  DistinctPoses out = group(
      n,
      [&](int f, const auto& offer) {
        if ((f & 0xfff) == 0) grouping.update(double(f) / n);
        const double p = projection[f];
        for (auto it = firsts.lower_bound(p - tolerance);
             it != firsts.end() && it->first <= p + tolerance; ++it) {
          offer(it->second);
        }
      },
      [&](int r, int f) { return points.distance(r, f) <= tolerance; },
      [&](int f) { firsts.emplace(projection[f], f); });
  grouping.update(1.0);
  return out;
}

DistinctPoses distinct_in_distances(const Eigen::MatrixXd& D, const Control& control) {
  const int n = static_cast<int>(D.rows());
  // s² = Σ_ij D_ij² / (2·F²), summed a column at a time, the columns in order.
  std::vector<double> column_sums(static_cast<std::size_t>(n), 0.0);
  parallel_for(
      n, [&](int j) { column_sums[j] = D.col(j).squaredNorm(); }, control.part(0.0, 0.4));
  double total = 0.0;
  for (const double s : column_sums) total += s;
  const double tolerance = kRepeatTolerance * std::sqrt(total / (2.0 * n * double(n)));
  // near[j]: whether some frame i < j is within τ of frame j (column j is contiguous; the scan
  // stops at the first). Only such frames can repeat a pose.
  std::vector<char> near(static_cast<std::size_t>(n), 0);
  parallel_for(
      n,
      [&](int j) {
        const double* column = D.col(j).data();
        for (int i = 0; i < j; ++i) {
          if (column[i] <= tolerance) {
            near[j] = 1;
            return;
          }
        }
      },
      control.part(0.4, 1.0));
  // Their candidates are the first occurrences so far, in increasing order: the first within τ
  // is the one they repeat.
  std::vector<int> firsts;
  return group(
      n,
      [&](int f, const auto& offer) {
        if (!near[f]) return;
        for (const int r : firsts) {
          if (D(r, f) <= tolerance) {
            offer(r);
            return;
          }
        }
      },
      [&](int r, int f) { return D(r, f) <= tolerance; }, [&](int f) { firsts.push_back(f); });
}

}  // namespace motionmap::embed
