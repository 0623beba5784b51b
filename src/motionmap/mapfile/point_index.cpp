#include "motionmap/mapfile/point_index.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <nanoflann.hpp>

#include "motionmap/core/error.h"

namespace motionmap::mapfile {

namespace {

struct Points {
  std::vector<Eigen::Vector2d> xy;  ///< the finite points
  std::vector<int> row;             ///< their rows of the map
  std::size_t kdtree_get_point_count() const { return xy.size(); }
  double kdtree_get_pt(std::size_t i, std::size_t d) const {
    return xy[i][static_cast<Eigen::Index>(d)];
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Points>,
                                                   Points, 2, std::uint32_t>;

}  // namespace

// The tree refers to its point set: both live together on the heap, so a moved index stays valid.
struct PointIndex::Tree {
  Points points;
  int rows = 0;
  Eigen::Vector2d lo = Eigen::Vector2d::Zero(), hi = Eigen::Vector2d::Zero();
  KdTree tree;
  Tree(Points p, int n)
      : points(std::move(p)),
        rows(n),
        tree(2, points, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {
    if (!points.xy.empty()) {
      lo = hi = points.xy.front();
      for (const auto& q : points.xy) {
        lo = lo.cwiseMin(q);
        hi = hi.cwiseMax(q);
      }
    }
  }
};

PointIndex::PointIndex(const Eigen::MatrixXd& coords) {
  if (coords.cols() < 2) {
    throw ParameterError("point index: the map has " + std::to_string(coords.cols()) +
                         " columns, expected at least 2 (x, y)");
  }
  Points p;
  p.xy.reserve(static_cast<std::size_t>(coords.rows()));
  p.row.reserve(static_cast<std::size_t>(coords.rows()));
  for (Eigen::Index i = 0; i < coords.rows(); ++i) {
    const Eigen::Vector2d q(coords(i, 0), coords(i, 1));
    if (!q.allFinite()) continue;
    p.xy.push_back(q);
    p.row.push_back(static_cast<int>(i));
  }
  m = std::make_unique<Tree>(std::move(p), static_cast<int>(coords.rows()));
}

PointIndex::~PointIndex() = default;
PointIndex::PointIndex(PointIndex&&) noexcept = default;
PointIndex& PointIndex::operator=(PointIndex&&) noexcept = default;

int PointIndex::size() const {
  return m->rows;
}
int PointIndex::indexed() const {
  return static_cast<int>(m->points.xy.size());
}
Eigen::Vector2d PointIndex::lower() const {
  return m->lo;
}
Eigen::Vector2d PointIndex::upper() const {
  return m->hi;
}

Neighbor PointIndex::nearest(const Eigen::Vector2d& p) const {
  const std::vector<Neighbor> one = nearest(p, 1);
  return one.empty() ? Neighbor{} : one.front();
}

std::vector<Neighbor> PointIndex::nearest(const Eigen::Vector2d& p, int k) const {
  std::vector<Neighbor> out;
  if (k < 1 || !p.allFinite() || m->points.xy.empty()) return out;
  // Ask for a few more than k so that points tied with the k-th are all seen, then order by
  // (distance, row): the answer does not depend on the tree's internal order.
  const std::size_t want = std::min<std::size_t>(m->points.xy.size(), std::size_t(k) + 8);
  std::vector<std::uint32_t> idx(want);
  std::vector<double> d2(want);
  const double q[2] = {p.x(), p.y()};
  const std::size_t got = m->tree.knnSearch(q, want, idx.data(), d2.data());
  out.reserve(got);
  for (std::size_t i = 0; i < got; ++i) out.push_back({m->points.row[idx[i]], std::sqrt(d2[i])});
  std::sort(out.begin(), out.end(), [](const Neighbor& a, const Neighbor& b) {
    return a.distance != b.distance ? a.distance < b.distance : a.sample < b.sample;
  });
  if (out.size() > std::size_t(k)) out.resize(std::size_t(k));
  return out;
}

}  // namespace motionmap::mapfile
