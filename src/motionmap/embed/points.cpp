#include "motionmap/embed/points.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <memory>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include <hnswlib/hnswlib.h>
#include <Eigen/Eigenvalues>

#include "motionmap/core/error.h"
#include "motionmap/core/parallel.h"
#include "motionmap/embed/k_range.h"

namespace motionmap::embed {

namespace {

constexpr int kFramesPerChunk = 64;
// Above kExactNeighborLimit frames, NeighborSearch::Auto keeps the exact k-d tree when it scans at
// most this many points per query on average, measured on kScanSampleQueries frames. The tree
// costs ~0.02 µs of a core per point scanned, HNSW's build ~340 µs of its one thread per frame:
// on 10⁶ library frames the tree scanned 2 900 points per query and took 58 s, HNSW 341 s.
constexpr double kExactScanBudget = 8000.0;
constexpr int kScanSampleQueries = 1000;
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

}  // namespace

Eigen::MatrixXd principal_axes(const RowMatrix& points, Eigen::Index max_samples) {
  const Eigen::Index n = points.rows(), dims = points.cols();
  if (n < 1 || dims < 1 || max_samples < 1) {
    throw ParameterError("principal_axes: " + std::to_string(n) + " points of " +
                         std::to_string(dims) + " values, " + std::to_string(max_samples) +
                         " samples (need at least 1 of each)");
  }
  const Eigen::RowVectorXd mean = points.colwise().mean();
  const Eigen::Index samples = std::min<Eigen::Index>(n, max_samples);
  Eigen::MatrixXd sample(samples, dims);
  for (Eigen::Index s = 0; s < samples; ++s) sample.row(s) = points.row((s * n) / samples) - mean;
  Eigen::MatrixXd covariance = Eigen::MatrixXd::Zero(dims, dims);
  covariance.selfadjointView<Eigen::Lower>().rankUpdate(sample.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(covariance);
  return eigen.eigenvectors().rowwise().reverse();  // largest first
}

// An exact k-d tree over the points turned into their principal axes. A rotation keeps every
// distance, and mocap poses lie near a low-dimensional manifold: in the principal frame the
// splits fall on the few axes that separate poses, and a partial distance over the leading
// coordinates exceeds the k-th best after a few of them for most points. nanoflann on the raw
// coordinates splits on one of ~100 axes of similar spread and sums every coordinate of every
// point it meets (1.4.3 does not stop a leaf's sums early).
//
// Distances in the turned frame equal the metric's up to rounding, far below `slack` (see the
// constructor); each query's candidates are re-ranked by the metric itself and its k-th distance
// checked against the first candidate left out, with a radius search when they are too close to
// call, so the lists are those of every pair — knn_from_distances on D — ties included.
class PrincipalKdTree {
 public:
  PrincipalKdTree(const RowMatrix& points, const Control& control) {
    const Eigen::Index n = points.rows();
    m_dims = static_cast<int>(points.cols());
    // 1. The principal axes (any orthonormal axes keep the result exact; good ones make it
    //    fast).
    const Eigen::RowVectorXd mean = points.colwise().mean();
    const Eigen::MatrixXd axes = principal_axes(points, kAxisSamples);
    control.check();
    // 2. Every frame in those axes, stored as floats (half the memory: 456 MB at 10⁶ frames of
    //    114 values) and summed in double. Storing rounds each y = (p − mean)·axes by at most
    //    2⁻²⁴·‖y‖, the product and sums by ~√d·d·2⁻⁵³·‖p − mean‖; a pair's distance by at most
    //    2⁻²³ of the largest ‖p − mean‖. `slack` allows eight times that.
    m_turned.resize(n, m_dims);
    double radius = 0.0;
    const int chunks = static_cast<int>((n + kRowsPerChunk - 1) / kRowsPerChunk);
    std::vector<double> radii(static_cast<std::size_t>(chunks), 0.0);
    parallel_chunks(chunks, [&](int c, int) {
      const Eigen::Index r0 = Eigen::Index(c) * kRowsPerChunk;
      const Eigen::Index rows = std::min<Eigen::Index>(kRowsPerChunk, n - r0);
      const Eigen::MatrixXd centred = points.middleRows(r0, rows).rowwise() - mean;
      m_turned.middleRows(r0, rows) = (centred * axes).cast<float>();
      radii[c] = centred.rowwise().norm().maxCoeff();
    });
    for (double r : radii) radius = std::max(radius, r);
    const double orthogonality =
        (axes.transpose() * axes - Eigen::MatrixXd::Identity(m_dims, m_dims)).cwiseAbs().maxCoeff();
    m_relative = 1e-6 + 4.0 * std::sqrt(double(m_dims)) * orthogonality;
    m_radius = radius;
    m_slack = m_relative * 2.0 * radius + std::numeric_limits<double>::denorm_min();
    m_mean = mean;
    m_axes = axes;
    control.check();
    // 3. The tree: median splits on the axis of largest spread; then the rows in tree order,
    //    so a leaf's points are contiguous.
    m_order.resize(std::size_t(n));
    std::iota(m_order.begin(), m_order.end(), 0);
    build_tree(static_cast<int>(n), control);
    Rows ordered(n, m_dims);
    for (Eigen::Index p = 0; p < n; ++p) ordered.row(p) = m_turned.row(m_order[p]);
    m_turned.swap(ordered);
    m_position.resize(std::size_t(n));
    for (Eigen::Index p = 0; p < n; ++p) m_position[m_order[p]] = static_cast<int>(p);
  }

  int frames() const { return static_cast<int>(m_order.size()); }
  int frame(int position) const { return m_order[position]; }
  int position(int frame) const { return m_position[frame]; }
  const float* row(int position) const { return m_turned.row(position).data(); }
  /// Bound on |distance in the turned frame − metric distance| for any pair.
  double slack() const { return m_slack; }

  /// `point` (in the points' own coordinates) turned as the tree's rows are, in `turned`;
  /// returns the bound of slack() for the pairs of it and a tree point.
  double turn(PoseRow point, std::vector<float>& turned) const {
    const Eigen::RowVectorXd centred = point - m_mean;
    const Eigen::RowVectorXd y = centred * m_axes;
    turned.resize(std::size_t(m_dims));
    for (int j = 0; j < m_dims; ++j) turned[j] = static_cast<float>(y[j]);
    return m_relative * 2.0 * std::max(m_radius, centred.norm()) +
           std::numeric_limits<double>::denorm_min();
  }

  /// The `want` nearest positions to `query` (a turned row) by turned squared distance,
  /// ascending, in found/squared; returns how many (fewer only when the tree is smaller).
  /// `scanned`, when given, receives the number of points the search looked at.
  int nearest(const float* query, int want, int* found, double* squared,
              std::vector<double>& offsets, std::int64_t* scanned = nullptr) const {
    Search s{query, found, squared, want, 0, std::numeric_limits<double>::infinity(), false};
    offsets.assign(std::size_t(m_dims), 0.0);
    descend(0, 0.0, offsets, s);
    if (scanned) *scanned = s.scanned;
    return s.count;
  }

  /// Every position within turned squared distance `radius_squared` of `query`, in any order.
  void within(const float* query, double radius_squared, std::vector<int>& found,
              std::vector<double>& offsets) const {
    found.clear();
    Search s{query, nullptr, nullptr, 0, 0, radius_squared, true};
    s.all = &found;
    offsets.assign(std::size_t(m_dims), 0.0);
    descend(0, 0.0, offsets, s);
  }

 private:
  static constexpr int kLeafSize = 16;
  static constexpr Eigen::Index kAxisSamples = 32768;
  static constexpr Eigen::Index kRowsPerChunk = 4096;

  struct Node {
    int begin = 0, end = 0;
    int axis = -1;            // -1: a leaf
    int left = 0, right = 0;  // children
    double low = 0.0;         // largest value of `axis` on the left
    double high = 0.0;        // smallest on the right
  };

  struct Search {
    const float* query;
    int* found;
    double* squared;
    int want;
    int count;
    double worst;  // the want-th best so far (+inf until `want` found), or the radius²
    bool radius;
    std::vector<int>* all = nullptr;
    std::int64_t scanned = 0;
  };

  // Splits node.begin … node.end (positions in m_order) at the median of its axis of largest
  // spread, filling node.axis, low and high; false for a leaf. Reads the rows in memory order.
  bool split(Node& node, std::vector<float>& lo, std::vector<float>& hi) {
    const int begin = node.begin, end = node.end;
    if (end - begin <= kLeafSize) return false;
    lo.assign(std::size_t(m_dims), std::numeric_limits<float>::infinity());
    hi.assign(std::size_t(m_dims), -std::numeric_limits<float>::infinity());
    for (int p = begin; p < end; ++p) {
      const float* y = m_turned.row(m_order[p]).data();
      for (int a = 0; a < m_dims; ++a) {
        lo[a] = std::min(lo[a], y[a]);
        hi[a] = std::max(hi[a], y[a]);
      }
    }
    int axis = 0;
    double spread = -1.0;
    for (int a = 0; a < m_dims; ++a) {
      if (double(hi[a]) - double(lo[a]) > spread) {
        spread = double(hi[a]) - double(lo[a]);
        axis = a;
      }
    }
    const int mid = begin + (end - begin) / 2;
    auto value = [&](int f) { return m_turned(f, axis); };
    std::nth_element(
        m_order.begin() + begin, m_order.begin() + mid, m_order.begin() + end,
        [&](int a, int b) { return value(a) < value(b) || (value(a) == value(b) && a < b); });
    double low = -std::numeric_limits<double>::infinity();
    for (int p = begin; p < mid; ++p) low = std::max(low, double(value(m_order[p])));
    double high = std::numeric_limits<double>::infinity();
    for (int p = mid; p < end; ++p) high = std::min(high, double(value(m_order[p])));
    node.axis = axis;
    node.low = low;
    node.high = high;
    return true;
  }

  // The subtree over positions [begin, end) into `nodes` (its root first), depth first.
  int build(std::vector<Node>& nodes, int begin, int end, std::vector<float>& lo,
            std::vector<float>& hi) {
    const int id = static_cast<int>(nodes.size());
    Node node{begin, end};
    const bool inner = split(node, lo, hi);
    nodes.push_back(node);
    if (!inner) return id;
    const int mid = begin + (end - begin) / 2;
    const int left = build(nodes, begin, mid, lo, hi);
    const int right = build(nodes, mid, end, lo, hi);
    nodes[std::size_t(id)].left = left;
    nodes[std::size_t(id)].right = right;
    return id;
  }

  // The whole tree: the top levels breadth first on this thread, until there are enough
  // subtrees to share, then each subtree on a thread of its own, spliced in. The splits are
  // the same as one depth-first build's: only the nodes' numbering depends on the order.
  void build_tree(int n, const Control& control) {
    std::vector<float> lo, hi;
    m_nodes.clear();
    m_nodes.reserve(std::size_t(2 * n / kLeafSize + 2));
    m_nodes.push_back({0, n});
    std::vector<int> frontier{0};
    const std::size_t wanted = std::size_t(8 * std::max(1, worker_count()));
    while (frontier.size() < wanted) {
      std::vector<int> next;
      for (const int id : frontier) {
        Node node = m_nodes[std::size_t(id)];
        if (!split(node, lo, hi)) continue;
        const int mid = node.begin + (node.end - node.begin) / 2;
        node.left = static_cast<int>(m_nodes.size());
        node.right = node.left + 1;
        m_nodes[std::size_t(id)] = node;
        m_nodes.push_back({node.begin, mid});
        m_nodes.push_back({mid, node.end});
        next.push_back(node.left);
        next.push_back(node.right);
      }
      if (next.empty()) return;
      frontier.swap(next);
      control.check();
    }
    std::vector<std::vector<Node>> parts(frontier.size());
    parallel_chunks(static_cast<int>(frontier.size()), [&](int i, int) {
      std::vector<float> part_lo, part_hi;
      const Node& root = m_nodes[std::size_t(frontier[std::size_t(i)])];
      build(parts[std::size_t(i)], root.begin, root.end, part_lo, part_hi);
    });
    for (std::size_t i = 0; i < parts.size(); ++i) {
      // Local node j ≥ 1 becomes node offset + j − 1; local node 0 is the frontier's node.
      const int offset = static_cast<int>(m_nodes.size());
      auto global = [&](int j) { return j == 0 ? frontier[i] : offset + j - 1; };
      for (std::size_t j = 0; j < parts[i].size(); ++j) {
        Node node = parts[i][j];
        if (node.axis >= 0) {
          node.left = global(node.left);
          node.right = global(node.right);
        }
        if (j == 0) {
          m_nodes[std::size_t(frontier[i])] = node;
        } else {
          m_nodes.push_back(node);
        }
      }
    }
  }

  void descend(int id, double bound, std::vector<double>& offsets, Search& s) const {
    const Node& node = m_nodes[id];
    if (node.axis < 0) {
      scan(node, s);
      return;
    }
    const double v = s.query[node.axis];
    // The near side, then the far one if its box can still hold a better point.
    const bool go_left = v - node.low < node.high - v;
    descend(go_left ? node.left : node.right, bound, offsets, s);
    const double gap = go_left ? std::max(0.0, node.high - v) : std::max(0.0, v - node.low);
    const double old = offsets[node.axis];
    const double far_bound = bound - old * old + gap * gap;
    if (far_bound <= s.worst) {
      offsets[node.axis] = gap;
      descend(go_left ? node.right : node.left, far_bound, offsets, s);
      offsets[node.axis] = old;
    }
  }

  void scan(const Node& node, Search& s) const {
    const int d = m_dims;
    s.scanned += node.end - node.begin;
    for (int p = node.begin; p < node.end; ++p) {
      const float* y = m_turned.row(p).data();
      double sum = 0.0;
      int j = 0;
      // Leading axes first; stop as soon as the partial sum rules the point out.
      for (; j + 8 <= d; j += 8) {
        double part = 0.0;
        for (int t = 0; t < 8; ++t) {
          const double diff = double(s.query[j + t]) - double(y[j + t]);
          part += diff * diff;
        }
        sum += part;
        if (sum > s.worst) break;
      }
      if (sum > s.worst) continue;
      for (; j < d; ++j) {
        const double diff = double(s.query[j]) - double(y[j]);
        sum += diff * diff;
      }
      if (s.radius) {
        if (sum <= s.worst) s.all->push_back(p);
        continue;
      }
      if (!(sum < s.worst)) continue;  // (+inf until `want` are found)
      // Insert into the sorted list of the best `want`.
      int i = std::min(s.count, s.want - 1);
      while (i > 0 && s.squared[i - 1] > sum) {
        s.squared[i] = s.squared[i - 1];
        s.found[i] = s.found[i - 1];
        --i;
      }
      s.squared[i] = sum;
      s.found[i] = p;
      if (s.count < s.want) ++s.count;
      if (s.count == s.want) s.worst = s.squared[s.want - 1];
    }
  }

  int m_dims = 0;
  using Rows = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  Rows m_turned;  // the turned rows, in tree order once built
  std::vector<int> m_order;
  std::vector<int> m_position;
  std::vector<Node> m_nodes;
  double m_slack = 0.0;
  double m_relative = 0.0;  // slack per unit of distance from the mean
  double m_radius = 0.0;    // the largest distance of a point from the mean
  Eigen::RowVectorXd m_mean;
  Eigen::MatrixXd m_axes;
};

namespace {

// The average number of points the tree scans for one frame's k + 2 nearest, over `queries`
// frames spread evenly over the set: what an exact search of every frame will cost.
double scanned_per_query(const PrincipalKdTree& tree, int k, int queries) {
  const int n = tree.frames();
  queries = std::min(n, queries);
  std::vector<std::int64_t> scanned(static_cast<std::size_t>(queries), 0);
  parallel_chunks(queries, [&](int a, int) {
    const int want = std::min(n, k + 2);
    std::vector<int> found(static_cast<std::size_t>(want));
    std::vector<double> squared(static_cast<std::size_t>(want)), offsets;
    const int p = tree.position(static_cast<int>((std::int64_t(a) * n) / queries));
    tree.nearest(tree.row(p), want, found.data(), squared.data(), offsets, &scanned[a]);
  });
  std::int64_t total = 0;
  for (std::int64_t s : scanned) total += s;
  return double(total) / queries;
}

void exact_kd_tree(const PointSet& points, const PrincipalKdTree& tree, NeighborLists& out,
                   const Control& control) {
  const int n = points.frames(), k = out.k;
  // k + 2: the frame itself (usually), its k nearest, and the first one left out, which must be
  // clearly farther than the k-th for the lists to be known exact.
  const int want = std::min(n, k + 2);
  const double slack = tree.slack();
  const int chunks = (n + kFramesPerChunk - 1) / kFramesPerChunk;
  const Control& queries = control;
  // Queries in tree order: consecutive ones are close, and so are the leaves they read.
  parallel_chunks(
      chunks,
      [&](int c, int) {
        std::vector<int> found(static_cast<std::size_t>(want));
        std::vector<double> squared(static_cast<std::size_t>(want));
        std::vector<double> offsets;
        std::vector<int> inside;
        Candidates candidates;
        for (int p = c * kFramesPerChunk; p < std::min(n, (c + 1) * kFramesPerChunk); ++p) {
          const int i = tree.frame(p);
          const int got = tree.nearest(tree.row(p), want, found.data(), squared.data(), offsets);
          candidates.clear();
          for (int a = 0; a < got; ++a) candidates.emplace_back(0.0, tree.frame(found[a]));
          int* index = out.index.data() + std::size_t(i) * k;
          double* distance = out.distance.data() + std::size_t(i) * k;
          keep_nearest(points, candidates, i, k, index, distance);
          // Every frame left out is at least sqrt(squared[got − 1]) − slack away.
          if (got == n || std::sqrt(squared[got - 1]) > distance[k - 1] + slack) continue;
          const double radius = distance[k - 1] + slack;
          tree.within(tree.row(p), radius * radius, inside, offsets);
          candidates.clear();
          for (int q : inside) candidates.emplace_back(0.0, tree.frame(q));
          keep_nearest(points, candidates, i, k, index, distance);
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
  check_neighbor_count(k, max_neighbors(n), n, "frames");
  NeighborLists out;
  out.k = k;
  out.index.resize(std::size_t(n) * k);
  out.distance.resize(std::size_t(n) * k);
  NeighborSearchReport local;
  NeighborSearchReport& r = report ? *report : local;
  r = {};
  const bool euclidean = points.metric == Metric::Euclidean;
  bool approximate = search == NeighborSearch::Approximate ||
                     (search == NeighborSearch::Auto && n > kExactNeighborLimit && !euclidean);
  std::unique_ptr<PrincipalKdTree> tree;
  if (!approximate && euclidean) {
    tree = std::make_unique<PrincipalKdTree>(*points.rows, control.part(0.0, 0.1));
    if (search == NeighborSearch::Auto && n > kExactNeighborLimit) {
      approximate = scanned_per_query(*tree, k, kScanSampleQueries) > kExactScanBudget;
      if (approximate) tree.reset();
    }
  }
  if (approximate) {
    r.approximate = true;
    approximate_hnsw(points, out, control, r);
  } else if (tree) {
    exact_kd_tree(points, *tree, out, control.part(0.1, 1.0));
  } else {
    exact_all_pairs(points, out, control);
  }
  control.update(1.0);
  return out;
}

SampleSearch::SampleSearch(const PointSet& samples, const Control& control) : m_samples(samples) {
  if (samples.rows == nullptr) throw ParameterError("knn: no samples were given");
  if (samples.metric == Metric::Euclidean) {
    m_tree = std::make_unique<PrincipalKdTree>(*samples.rows, control);
  }
  control.update(1.0);
}

SampleSearch::~SampleSearch() = default;

NeighborLists SampleSearch::nearest(const PointSet& queries, std::span<const int> frames, int k,
                                    const Control& control) const {
  const PointSet& samples = m_samples;
  if (queries.rows == nullptr) throw ParameterError("knn: no queries were given");
  const int m = samples.frames();
  check_neighbor_count(k, m, m, "samples");
  if (samples.rows->cols() != queries.rows->cols() || samples.metric != queries.metric) {
    throw ParameterError("knn: the samples and the queries are points of different kinds");
  }
  NeighborLists out;
  out.k = k;
  out.index.resize(frames.size() * std::size_t(k));
  out.distance.resize(frames.size() * std::size_t(k));
  const int count = static_cast<int>(frames.size());
  const int chunks = (count + kFramesPerChunk - 1) / kFramesPerChunk;
  const PrincipalKdTree* tree = m_tree.get();
  const int want = std::min(m, k + 1);  // the k nearest and the first one left out
  parallel_chunks(
      chunks,
      [&](int c, int) {
        std::vector<int> found(static_cast<std::size_t>(want)), inside;
        std::vector<double> squared(static_cast<std::size_t>(want)), offsets;
        std::vector<float> turned;
        Candidates candidates;
        for (int q = c * kFramesPerChunk; q < std::min(count, (c + 1) * kFramesPerChunk); ++q) {
          const PoseRow query = queries.rows->row(frames[q]);
          auto rank = [&] {
            for (auto& [d, s] : candidates)
              d = pose_distance(query, samples.rows->row(s), samples.metric);
            std::sort(candidates.begin(), candidates.end());
            candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
          };
          candidates.clear();
          double slack = 0.0;
          int got = m;
          if (tree) {
            slack = tree->turn(query, turned);
            got = tree->nearest(turned.data(), want, found.data(), squared.data(), offsets);
            for (int a = 0; a < got; ++a) candidates.emplace_back(0.0, tree->frame(found[a]));
          } else {
            for (int s = 0; s < m; ++s) candidates.emplace_back(0.0, s);
          }
          rank();
          // Every sample left out is at least sqrt(squared[got − 1]) − slack away (see
          // exact_kd_tree); otherwise every sample within the k-th distance + slack.
          if (tree && got < m && !(std::sqrt(squared[got - 1]) > candidates[k - 1].first + slack)) {
            const double radius = candidates[k - 1].first + slack;
            tree->within(turned.data(), radius * radius, inside, offsets);
            candidates.clear();
            for (int p : inside) candidates.emplace_back(0.0, tree->frame(p));
            rank();
          }
          for (int a = 0; a < k; ++a) {
            out.index[std::size_t(q) * k + a] = candidates[a].second;
            out.distance[std::size_t(q) * k + a] = candidates[a].first;
          }
        }
      },
      [&](int done) { control.update(double(done) / chunks); });
  control.update(1.0);
  return out;
}

NeighborLists knn_to_samples(const PointSet& samples, const PointSet& queries,
                             std::span<const int> frames, int k, const Control& control) {
  const bool tree = samples.metric == Metric::Euclidean;
  const SampleSearch search(samples, tree ? control.part(0.0, 0.1) : Control());
  return search.nearest(queries, frames, k, tree ? control.part(0.1, 1.0) : control);
}

}  // namespace motionmap::embed
