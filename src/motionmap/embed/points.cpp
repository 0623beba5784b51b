#include "motionmap/embed/points.h"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <hnswlib/hnswlib.h>
#include <nanoflann.hpp>

#include "motionmap/core/error.h"
#include "motionmap/core/parallel.h"

namespace motionmap::embed {

namespace {

constexpr int kFramesPerChunk = 64;
// Frames the recall of an approximate search is measured on.
constexpr int kRecallQueries = 200;

using Candidates = std::vector<std::pair<double, int>>;

// Keeps the k nearest candidates other than `self` by (exact distance, index) — the order of
// k_nearest — in index[0…k), distance[0…k). Candidates hold indices; their distances are
// recomputed here with the metric, so every search reports the distances D would hold.
void keep_nearest(const PointSet& points, Candidates& candidates, int self, int k, int* index,
                  double* distance) {
  for (auto& [d, j] : candidates) d = points.distance(self, j);
  std::erase_if(candidates, [&](const auto& c) { return c.second == self; });
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  for (int a = 0; a < k; ++a) {
    index[a] = candidates[a].second;
    distance[a] = candidates[a].first;
  }
}

// Every pair: the distances from `self` to all frames, then k_nearest as for a column of D.
void all_pairs_nearest(const PointSet& points, int self, int k, std::vector<double>& buffer,
                       int* index, double* distance) {
  const int n = points.frames();
  buffer.resize(std::size_t(n));
  for (int j = 0; j < n; ++j) buffer[j] = j == self ? 0.0 : points.distance(self, j);
  k_nearest(buffer.data(), n, self, k, index, distance);
}

void exact_all_pairs(const PointSet& points, NeighborLists& out, const Control& control) {
  const int n = points.frames(), k = out.k;
  const int chunks = (n + kFramesPerChunk - 1) / kFramesPerChunk;
  std::vector<std::vector<double>> buffers(static_cast<std::size_t>(worker_count(chunks)));
  parallel_chunks(
      chunks,
      [&](int c, int worker) {
        for (int i = c * kFramesPerChunk; i < std::min(n, (c + 1) * kFramesPerChunk); ++i) {
          all_pairs_nearest(points, i, k, buffers[worker], out.index.data() + std::size_t(i) * k,
                            out.distance.data() + std::size_t(i) * k);
        }
      },
      [&](int done) { control.update(double(done) / chunks); });
}

// nanoflann's view of the rows.
struct RowsAdaptor {
  const RowMatrix& rows;
  std::size_t kdtree_get_point_count() const { return static_cast<std::size_t>(rows.rows()); }
  double kdtree_get_pt(std::size_t i, std::size_t d) const {
    return rows(Eigen::Index(i), Eigen::Index(d));
  }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};
using KdTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Adaptor<double, RowsAdaptor, double>,
                                        RowsAdaptor, -1, std::uint32_t>;

void exact_kd_tree(const PointSet& points, NeighborLists& out, const Control& control) {
  const int n = points.frames(), k = out.k;
  const RowsAdaptor adaptor{*points.rows};
  const Control build = control.part(0.0, 0.1);
  build.check();
  KdTree tree(static_cast<int>(points.rows->cols()), adaptor,
              nanoflann::KDTreeSingleIndexAdaptorParams(16));
  // k + 1: the frame itself is usually among them (unless it has duplicates).
  const int want = std::min(n, k + 1);
  const int chunks = (n + kFramesPerChunk - 1) / kFramesPerChunk;
  const Control queries = control.part(0.1, 1.0);
  parallel_chunks(
      chunks,
      [&](int c, int) {
        std::vector<std::uint32_t> found(static_cast<std::size_t>(want));
        std::vector<double> squared(static_cast<std::size_t>(want));
        Candidates candidates;
        for (int i = c * kFramesPerChunk; i < std::min(n, (c + 1) * kFramesPerChunk); ++i) {
          const std::size_t got =
              tree.knnSearch(points.rows->row(i).data(), want, found.data(), squared.data());
          candidates.clear();
          for (std::size_t a = 0; a < got; ++a) candidates.emplace_back(0.0, int(found[a]));
          if (int(std::count_if(candidates.begin(), candidates.end(),
                                [&](const auto& p) { return p.second != i; })) < k) {
            throw NumericalError("knn: the k-d tree returned fewer than k neighbours");
          }
          keep_nearest(points, candidates, i, k, out.index.data() + std::size_t(i) * k,
                       out.distance.data() + std::size_t(i) * k);
        }
      },
      [&](int done) { queries.update(double(done) / chunks); });
}

// hnswlib space for Metric::QuaternionAngles on float copies of the rows: the squared distance
// (a monotone function of it is all the graph needs).
class QuaternionAngleSpace : public hnswlib::SpaceInterface<float> {
 public:
  explicit QuaternionAngleSpace(std::size_t dims) : m_dims(dims) {}
  std::size_t get_data_size() override { return m_dims * sizeof(float); }
  hnswlib::DISTFUNC<float> get_dist_func() override { return &distance; }
  void* get_dist_func_param() override { return &m_dims; }

 private:
  static float distance(const void* a, const void* b, const void* param) {
    const auto* x = static_cast<const float*>(a);
    const auto* y = static_cast<const float*>(b);
    const std::size_t dims = *static_cast<const std::size_t*>(param);
    float sum = 0.0f;
    for (std::size_t j = 0; j + 4 <= dims; j += 4) {
      const float dot =
          std::abs(x[j] * y[j] + x[j + 1] * y[j + 1] + x[j + 2] * y[j + 2] + x[j + 3] * y[j + 3]);
      const float theta = 2.0f * std::acos(std::min(dot, 1.0f));
      sum += theta * theta;
    }
    return sum;
  }
  std::size_t m_dims;
};

void approximate_hnsw(const PointSet& points, NeighborLists& out, const Control& control,
                      NeighborSearchReport& report) {
  const int n = points.frames(), k = out.k;
  const std::size_t dims = static_cast<std::size_t>(points.rows->cols());
  std::unique_ptr<hnswlib::SpaceInterface<float>> space;
  if (points.metric == Metric::Euclidean) {
    space = std::make_unique<hnswlib::L2Space>(dims);
  } else {
    space = std::make_unique<QuaternionAngleSpace>(dims);
  }
  // M = 16 links per node and ef_construction = 100: recall@20 ≥ 0.95 on mocap point clouds
  // (measured and printed every time). One thread adds the frames in order, so the graph, and
  // the map, are the same on every machine; the level generator is seeded.
  constexpr std::size_t kLinks = 16, kEfConstruction = 100, kSeed = 100;
  hnswlib::HierarchicalNSW<float> index(space.get(), std::size_t(n), kLinks, kEfConstruction,
                                        kSeed);
  const Control build = control.part(0.0, 0.7);
  std::vector<float> row(dims);
  auto to_float = [&](int i, float* dst) {
    const double* src = points.rows->row(i).data();
    for (std::size_t d = 0; d < dims; ++d) dst[d] = static_cast<float>(src[d]);
  };
  for (int i = 0; i < n; ++i) {
    to_float(i, row.data());
    index.addPoint(row.data(), static_cast<hnswlib::labeltype>(i));
    if (i % 1024 == 0) build.update(double(i) / n);
  }
  index.setEf(std::max<std::size_t>(std::size_t(2 * k + 1), 64));
  const int want = std::min(n, k + 1);
  const int chunks = (n + kFramesPerChunk - 1) / kFramesPerChunk;
  const Control queries = control.part(0.7, 0.95);
  parallel_chunks(
      chunks,
      [&](int c, int) {
        std::vector<float> query(dims);
        Candidates candidates;
        for (int i = c * kFramesPerChunk; i < std::min(n, (c + 1) * kFramesPerChunk); ++i) {
          to_float(i, query.data());
          auto found = index.searchKnn(query.data(), std::size_t(want));
          candidates.clear();
          while (!found.empty()) {
            candidates.emplace_back(0.0, static_cast<int>(found.top().second));
            found.pop();
          }
          if (int(std::count_if(candidates.begin(), candidates.end(),
                                [&](const auto& p) { return p.second != i; })) < k) {
            throw NumericalError("knn: the HNSW search returned fewer than k neighbours");
          }
          keep_nearest(points, candidates, i, k, out.index.data() + std::size_t(i) * k,
                       out.distance.data() + std::size_t(i) * k);
        }
      },
      [&](int done) { queries.update(double(done) / chunks); });

  // Recall on frames spread evenly over the set, against every pair.
  const int q = std::min(n, kRecallQueries);
  std::vector<int> hits(static_cast<std::size_t>(q), 0);
  const Control recall = control.part(0.95, 1.0);
  std::vector<std::vector<double>> buffers(static_cast<std::size_t>(worker_count(q)));
  parallel_chunks(
      q,
      [&](int a, int worker) {
        const int i = static_cast<int>((std::int64_t(a) * n) / q);
        std::vector<int> index_exact(static_cast<std::size_t>(k));
        std::vector<double> distance_exact(static_cast<std::size_t>(k));
        all_pairs_nearest(points, i, k, buffers[worker], index_exact.data(), distance_exact.data());
        const auto approx = out.of(i);
        std::sort(index_exact.begin(), index_exact.end());
        for (int j : approx) {
          hits[a] += std::binary_search(index_exact.begin(), index_exact.end(), j) ? 1 : 0;
        }
      },
      [&](int done) { recall.update(double(done) / q); });
  std::int64_t total = 0;
  for (int h : hits) total += h;
  report.recall = double(total) / (double(q) * k);
  report.recall_queries = q;
}

}  // namespace

std::string NeighborSearchReport::description() const {
  if (!approximate) return "exact";
  char text[128];
  std::snprintf(text, sizeof text, "approximate (HNSW), recall %.3f measured on %d frames", recall,
                recall_queries);
  return text;
}

NeighborLists knn_from_points(const PointSet& points, int k, NeighborSearch search,
                              const Control& control, NeighborSearchReport* report) {
  if (points.rows == nullptr) throw ParameterError("knn: no points were given");
  const int n = points.frames();
  if (k < 1 || k > n - 1) {
    throw ParameterError("k = " + std::to_string(k) + " neighbours is out of range: with " +
                         std::to_string(n) + " frames it must be in [1, " + std::to_string(n - 1) +
                         "]");
  }
  NeighborLists out;
  out.k = k;
  out.index.resize(std::size_t(n) * k);
  out.distance.resize(std::size_t(n) * k);
  NeighborSearchReport local;
  NeighborSearchReport& r = report ? *report : local;
  r = {};
  const bool approximate = search == NeighborSearch::Approximate ||
                           (search == NeighborSearch::Auto && n > kExactNeighborLimit);
  if (approximate) {
    r.approximate = true;
    approximate_hnsw(points, out, control, r);
  } else if (points.metric == Metric::Euclidean) {
    exact_kd_tree(points, out, control);
  } else {
    exact_all_pairs(points, out, control);
  }
  control.update(1.0);
  return out;
}

}  // namespace motionmap::embed
