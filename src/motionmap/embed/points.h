#pragma once
// Frames given as points (the rows D would be computed from), and their k nearest neighbours
// found without the #frames² distance matrix: what the scalable maps (see embed.h, "Two paths")
// work on.
//
//   PointSet points{&cloud, Metric::Euclidean};
//   NeighborSearchReport report;
//   NeighborLists nn = knn_from_points(points, 20, NeighborSearch::Auto, control, &report);
//   // report.approximate: HNSW was used (above kExactNeighborLimit); report.recall measured
#include <memory>
#include <span>
#include <string>

#include "motionmap/core/control.h"
#include "motionmap/core/metric.h"
#include "motionmap/embed/neighbors.h"

namespace motionmap::embed {

/// Frames as points: row f of `rows` is frame f; distances by `metric` (core/metric.h), exactly
/// as the entries of D would be.
struct PointSet {
  const RowMatrix* rows = nullptr;
  Metric metric = Metric::Euclidean;

  int frames() const { return rows ? static_cast<int>(rows->rows()) : 0; }
  double distance(Eigen::Index i, Eigen::Index j) const {
    return pose_distance(rows->row(i), rows->row(j), metric);
  }
};

/// Orthonormal axes of `points` (#values by #values, a column per axis), the directions of
/// largest spread first: the eigenvectors of the covariance of at most `max_samples` rows spread
/// evenly over them. Any orthonormal axes keep a distance; these make the leading coordinates
/// separate the points most (k-d trees and bounds on distances search faster in them).
/// @throws ParameterError if points has no row or no column, or max_samples < 1.
Eigen::MatrixXd principal_axes(const RowMatrix& points, Eigen::Index max_samples = 32768);

/// How knn_from_points searches.
enum class NeighborSearch {
  /// Exact up to kExactNeighborLimit frames. Above, exact too for Euclidean points when the
  /// k-d tree scans few points per query (measured on 1 000 frames: poses near a
  /// low-dimensional manifold, as in motion libraries), approximate otherwise.
  Auto,
  /// Exact: a k-d tree over the points turned into their principal axes for Euclidean points
  /// (a copy of the points, #frames by #values), otherwise every pair (O(#frames²) time,
  /// O(#frames) memory). Either way the lists are those of knn_from_distances on D, bit for bit.
  Exact,
  /// Approximate: a hierarchical navigable small-world graph (hnswlib), built in frame order on
  /// one thread (so the result does not depend on the thread count), searched in parallel.
  Approximate,
};

/// Above this many frames NeighborSearch::Auto may search approximately (see Auto).
constexpr int kExactNeighborLimit = 100000;

/// What a search did.
struct NeighborSearchReport {
  bool approximate = false;
  /// Approximate only: the fraction of true k nearest neighbours found, measured on
  /// `recall_queries` frames spread evenly over the set against an exhaustive search; 1 when exact.
  double recall = 1.0;
  int recall_queries = 0;
  /// "exact (k-d tree)", "exact (all pairs)" or "approximate (HNSW, recall@20 0.987 on 200
  /// frames)".
  std::string description() const;
};

/// Each frame's k nearest other frames, nearest first, with their distances; of equal distances
/// the smaller frame index wins (approximate search: among the candidates found). Runs in parallel;
/// `control` hears the fraction done (index build and queries) and may throw Cancelled.
/// @throws ParameterError unless 1 ≤ k ≤ #frames − 1 and points.rows is set.
NeighborLists knn_from_points(const PointSet& points, int k,
                              NeighborSearch search = NeighborSearch::Auto,
                              const Control& control = {}, NeighborSearchReport* report = nullptr);

class PrincipalKdTree;

/// The samples prepared for many searches of their nearest to other points (knn_to_samples
/// builds one per call): a k-d tree over the samples in their principal axes for Euclidean points
/// (#samples by #values floats, built in parallel), nothing
/// for other metrics (every sample is compared). Reads `samples.rows`, which must outlive it and
/// not change. Searching is thread-safe.
class SampleSearch {
 public:
  /// `control` hears the fraction of the tree built and may throw Cancelled.
  /// @throws ParameterError if samples.rows is not set.
  explicit SampleSearch(const PointSet& samples, const Control& control = {});
  ~SampleSearch();
  SampleSearch(const SampleSearch&) = delete;
  SampleSearch& operator=(const SampleSearch&) = delete;

  /// The samples it searches.
  const PointSet& samples() const { return m_samples; }

  /// As knn_to_samples(samples(), queries, frames, k, control).
  NeighborLists nearest(const PointSet& queries, std::span<const int> frames, int k,
                        const Control& control = {}) const;

 private:
  PointSet m_samples;
  std::unique_ptr<PrincipalKdTree> m_tree;
};

/// The k nearest of `samples` to each of the rows `frames` of `queries` (points of the same
/// kind and metric), nearest first, of equal distances the smaller sample index: exactly what
/// every pair gives (a k-d tree over the samples for Euclidean points). A query equal to a sample
/// finds it at distance 0. List q (NeighborLists::of(q)) belongs to frames[q]. In parallel;
/// `control` hears the fraction done and may throw Cancelled.
/// @throws ParameterError unless 1 ≤ k ≤ #samples, both sets are given and alike.
NeighborLists knn_to_samples(const PointSet& samples, const PointSet& queries,
                             std::span<const int> frames, int k, const Control& control = {});

}  // namespace motionmap::embed
