#pragma once
// A 2-D nearest-neighbour index over a map's points (a k-d tree, nanoflann): which sample lies
// under a mouse position, and the k samples around a map point, in O(log N) per query on maps of
// millions of points. What MotionMap Studio hovers, clicks and blends with on a saved map
// (mapfile::SavedMap::index(); mapfile/point_index.h names it mapfile::PointIndex too), and
// what `motionmap pose/synth --map lib.mmap.h5` could reuse: no Qt. Its tree is the one the
// blender's map index and the routes search (detail/point_tree.h): one k-d tree of map points.
//
//   motionmap::synth::PointIndex index(map.coordinates);     // first two columns
//   const auto hit = index.nearest({0.3, -1.2});             // hit.sample, hit.distance
//   const auto around = index.nearest({0.3, -1.2}, 13);      // the 13 nearest, nearest first
#include <memory>
#include <vector>

#include <Eigen/Core>

namespace motionmap::synth {

/// One sample found: its row of the map and its distance (map units) from the query.
struct Neighbor {
  int sample = -1;
  double distance = 0.0;
};

class PointIndex {
 public:
  /// Indexes the first two columns of `coords` (copied). Non-finite rows are left out (never
  /// found). Building costs O(N log N).
  /// @throws ParameterError if coords has fewer than 2 columns.
  explicit PointIndex(const Eigen::MatrixXd& coords);
  ~PointIndex();
  PointIndex(PointIndex&&) noexcept;
  PointIndex& operator=(PointIndex&&) noexcept;

  /// Rows of the map (indexed or not).
  int size() const;
  /// Rows that can be found (the finite ones).
  int indexed() const;

  /// The sample nearest `p` (ties: the lower row); sample −1 when nothing is indexed or p is not
  /// finite.
  Neighbor nearest(const Eigen::Vector2d& p) const;
  /// The min(k, indexed()) samples nearest `p`, nearest first (ties: the lower row first); empty
  /// when p is not finite or k < 1.
  std::vector<Neighbor> nearest(const Eigen::Vector2d& p, int k) const;

  /// Smallest box holding every indexed point: {min x, min y}, {max x, max y} (zeros when none).
  Eigen::Vector2d lower() const;
  Eigen::Vector2d upper() const;

 private:
  struct Tree;
  std::unique_ptr<Tree> m;
};

}  // namespace motionmap::synth
