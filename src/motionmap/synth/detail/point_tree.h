#pragma once
// A k-d tree over 2-D map points (nanoflann) with the point set it indexes: what the map index
// (detail/map_index.h), routes (route.h) and the public PointIndex (point_index.h: a saved map's
// samples under the mouse, mapfile::SavedMap::index()) search — MotionMap's one 2-D index. Tree and
// points live together, so an owner holding it by pointer can be moved and its tree stays valid.
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <nanoflann.hpp>

namespace motionmap::synth::detail {

struct PointTree {
  struct PointSet {
    std::vector<Eigen::Vector2d> points;
    std::size_t kdtree_get_point_count() const { return points.size(); }
    double kdtree_get_pt(std::size_t i, std::size_t d) const {
      return points[i][static_cast<Eigen::Index>(d)];
    }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
      return false;
    }
  };
  using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointSet>,
                                                     PointSet, 2, std::uint32_t>;

  PointSet set;
  KdTree index;
  explicit PointTree(std::vector<Eigen::Vector2d> points)
      : set{std::move(points)}, index(2, set, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {}
};

}  // namespace motionmap::synth::detail
