#include "motionmap/synth/point_index.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "motionmap/core/error.h"
#include "motionmap/synth/detail/point_tree.h"

namespace motionmap::synth {

// The finite points' tree (its points and tree live together: a moved index stays valid), their
// rows of the map and their bounding box.
struct PointIndex::Tree {
  detail::PointTree tree;
  std::vector<int> row;
  int rows = 0;
  Eigen::Vector2d lo = Eigen::Vector2d::Zero(), hi = Eigen::Vector2d::Zero();
  Tree(std::vector<Eigen::Vector2d> xy, std::vector<int> r, int n)
      : tree(std::move(xy)), row(std::move(r)), rows(n) {
    const std::vector<Eigen::Vector2d>& points = tree.set.points;
    if (!points.empty()) {
      lo = hi = points.front();
      for (const auto& q : points) {
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
  std::vector<Eigen::Vector2d> xy;
  std::vector<int> row;
  xy.reserve(static_cast<std::size_t>(coords.rows()));
  row.reserve(static_cast<std::size_t>(coords.rows()));
  for (Eigen::Index i = 0; i < coords.rows(); ++i) {
    const Eigen::Vector2d q(coords(i, 0), coords(i, 1));
    if (!q.allFinite()) continue;
    xy.push_back(q);
    row.push_back(static_cast<int>(i));
  }
  m = std::make_unique<Tree>(std::move(xy), std::move(row), static_cast<int>(coords.rows()));
}

PointIndex::~PointIndex() = default;
PointIndex::PointIndex(PointIndex&&) noexcept = default;
PointIndex& PointIndex::operator=(PointIndex&&) noexcept = default;

int PointIndex::size() const {
  return m->rows;
}
int PointIndex::indexed() const {
  return static_cast<int>(m->row.size());
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
  if (k < 1 || !p.allFinite() || m->row.empty()) return out;
  // Ask for a few more than k so that points tied with the k-th are all seen, then order by
  // (distance, row): the answer does not depend on the tree's internal order.
  const std::size_t want = std::min<std::size_t>(m->row.size(), std::size_t(k) + 8);
  std::vector<std::uint32_t> idx(want);
  std::vector<double> d2(want);
  const double q[2] = {p.x(), p.y()};
  const std::size_t got = m->tree.index.knnSearch(q, want, idx.data(), d2.data());
  out.reserve(got);
  for (std::size_t i = 0; i < got; ++i) out.push_back({m->row[idx[i]], std::sqrt(d2[i])});
  std::sort(out.begin(), out.end(), [](const Neighbor& a, const Neighbor& b) {
    return a.distance != b.distance ? a.distance < b.distance : a.sample < b.sample;
  });
  if (out.size() > std::size_t(k)) out.resize(std::size_t(k));
  return out;
}

}  // namespace motionmap::synth
