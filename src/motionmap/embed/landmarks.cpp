// Landmark MDS and landmark Isomap (de Silva & Tenenbaum, "Global versus local methods in
// nonlinear dimensionality reduction", NIPS 2002; "Sparse multidimensional scaling using landmark
// points", 2004): classical MDS of L landmarks, then every frame triangulated from its distances
// to them. O(#frames·L) time and memory instead of O(#frames²).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>

#include "motionmap/core/error.h"
#include "motionmap/core/parallel.h"
#include "motionmap/embed/detail/methods.h"
#include "motionmap/embed/detail/progress.h"
#include "motionmap/embed/detail/routines.h"
#include "motionmap/embed/eigen.h"
#include "motionmap/embed/metrics.h"

namespace motionmap::embed {

namespace {

constexpr int kFramesPerChunk = 1024;
// Landmarks whose shortest paths one task computes (see run_landmark_isomap).
constexpr int kBatch = 8;
// Frames whose distances to the landmarks fit_landmarks holds at once (landmark MDS computes
// them block by block, twice, instead of keeping L·#frames of them: 2 GB at 10⁶ frames).
constexpr int kFramesPerBlock = 8192;
// Axes the frames are triangulated into before the final PCA (fewer when the landmarks' distances
// have fewer positive dimensions).
constexpr int kLandmarkAxes = 20;

// The landmarks' rows of the points, in the order chosen.
RowMatrix landmark_rows(const PointSet& points, const std::vector<int>& landmarks) {
  RowMatrix rows(static_cast<Eigen::Index>(landmarks.size()), points.rows->cols());
  for (std::size_t l = 0; l < landmarks.size(); ++l) {
    rows.row(Eigen::Index(l)) = points.rows->row(landmarks[l]);
  }
  return rows;
}

int landmark_count(const EmbedOptions& options, int frames) {
  return std::min(frames, options.landmarks > 0 ? options.landmarks : kDefaultLandmarks);
}

// The k-NN graph as the landmark searches read it: renumbered in breadth-first order (from
// frame 0, then from the first frame not reached, …), so that the frames a search settles one
// after another, and their edges, lie close together in memory; each edge's target and length
// side by side.
struct SearchGraph {
  struct Arc {
    int to;
    double length;
  };
  std::vector<int> frame;     // position → frame
  std::vector<int> position;  // frame → position
  std::vector<int> offsets;   // #frames + 1, by position
  std::vector<Arc> arcs;

  explicit SearchGraph(const Graph& graph) {
    const int n = graph.frames();
    position.assign(std::size_t(n), -1);
    frame.reserve(std::size_t(n));
    for (int root = 0; root < n; ++root) {
      if (position[root] >= 0) continue;
      position[root] = static_cast<int>(frame.size());
      frame.push_back(root);
      for (std::size_t head = frame.size() - 1; head < frame.size(); ++head) {
        const int u = frame[head];
        for (int e = graph.offsets[u]; e < graph.offsets[u + 1]; ++e) {
          const int v = graph.targets[e];
          if (position[v] >= 0) continue;
          position[v] = static_cast<int>(frame.size());
          frame.push_back(v);
        }
      }
    }
    offsets.assign(std::size_t(n) + 1, 0);
    arcs.reserve(graph.targets.size());
    for (int p = 0; p < n; ++p) {
      const int u = frame[p];
      for (int e = graph.offsets[u]; e < graph.offsets[u + 1]; ++e) {
        arcs.push_back({position[graph.targets[e]], graph.weights[e]});
      }
      offsets[p + 1] = static_cast<int>(arcs.size());
    }
  }
  int frames() const { return static_cast<int>(frame.size()); }
};

// Dijkstra's shortest-path lengths from `source` (a position) to every position, written to
// dist (+inf where unreachable), with a 4-ary heap that holds each position once (decrease-key):
// fewer and shallower heap moves than a binary heap of every tentative distance. Any correct
// Dijkstra gives the same bits: a frame's distance is the smallest of d(u) + length(u, v) over
// its neighbours, each d(u) final before it is used.
class Dijkstra {
 public:
  explicit Dijkstra(int n) : m_slot(std::size_t(n), -1) { m_heap.reserve(std::size_t(n)); }

  void run(const SearchGraph& graph, int source, std::vector<double>& dist) {
    dist.assign(std::size_t(graph.frames()), std::numeric_limits<double>::infinity());
    dist[source] = 0.0;
    push(source, 0.0);
    const int* offsets = graph.offsets.data();
    const SearchGraph::Arc* arcs = graph.arcs.data();
    while (!m_heap.empty()) {
      const auto [du, u] = pop();
      for (int e = offsets[u]; e < offsets[u + 1]; ++e) {
        const int v = arcs[e].to;
        const double candidate = du + arcs[e].length;
        if (!(candidate < dist[v])) continue;
        dist[v] = candidate;
        if (m_slot[v] >= 0) {
          sift_up(m_slot[v], {candidate, v});
        } else {
          push(v, candidate);
        }
      }
    }
  }

 private:
  using Item = std::pair<double, int>;  // (distance, position)
  static constexpr int kArity = 4;

  void push(int v, double key) {
    m_heap.emplace_back();
    sift_up(static_cast<int>(m_heap.size()) - 1, {key, v});
  }
  Item pop() {
    const Item top = m_heap.front();
    m_slot[top.second] = -1;
    const Item last = m_heap.back();
    m_heap.pop_back();
    if (!m_heap.empty()) sift_down(last);
    return top;
  }
  void place(int i, const Item& item) {
    m_heap[i] = item;
    m_slot[item.second] = i;
  }
  void sift_up(int i, const Item& item) {
    while (i > 0) {
      const int parent = (i - 1) / kArity;
      if (!(item.first < m_heap[parent].first)) break;
      place(i, m_heap[parent]);
      i = parent;
    }
    place(i, item);
  }
  void sift_down(const Item& item) {
    const int size = static_cast<int>(m_heap.size());
    int i = 0;
    while (true) {
      const int first = kArity * i + 1;
      if (first >= size) break;
      int best = first;
      for (int c = first + 1; c < std::min(first + kArity, size); ++c) {
        if (m_heap[c].first < m_heap[best].first) best = c;
      }
      if (!(m_heap[best].first < item.first)) break;
      place(i, m_heap[best]);
      i = best;
    }
    place(i, item);
  }

  std::vector<Item> m_heap;
  std::vector<int> m_slot;  // position → its index in m_heap, −1 when not queued
};

// The landmarks' distances to each other from the L by #frames distances (lower triangle of the
// L by L result, both directions averaged: the graph's two searches may round differently).
Eigen::MatrixXd landmark_block(const std::vector<int>& landmarks,
                               const Eigen::MatrixXd& distances) {
  const Eigen::Index L = static_cast<Eigen::Index>(landmarks.size());
  Eigen::MatrixXd T(L, L);
  for (Eigen::Index a = 0; a < L; ++a) {
    for (Eigen::Index b = 0; b < L; ++b) {
      T(a, b) = 0.5 * (distances(a, landmarks[b]) + distances(b, landmarks[a]));
    }
    T(a, a) = 0.0;
  }
  return T;
}

// triangulate() into `out` (#frames by dims): row f from column f of `distances` alone.
void triangulate_into(const LandmarkFit& fit, const Eigen::Ref<const Eigen::MatrixXd>& distances,
                      Eigen::Ref<Eigen::MatrixXd> out) {
  const Eigen::Index L = fit.projection.cols(), dims = fit.projection.rows();
  const int n = static_cast<int>(distances.cols());
  const int chunks = (n + kFramesPerChunk - 1) / kFramesPerChunk;
  parallel_chunks(chunks, [&](int c, int) {
    for (int f = c * kFramesPerChunk; f < std::min(n, (c + 1) * kFramesPerChunk); ++f) {
      const double* delta = distances.col(f).data();
      for (Eigen::Index a = 0; a < dims; ++a) {
        double sum = 0.0;
        for (Eigen::Index l = 0; l < L; ++l) {
          sum += fit.projection(a, l) * (delta[l] * delta[l] - fit.mean_squared[l]);
        }
        out(f, a) = -0.5 * sum + fit.offset[a];
      }
    }
  });
}

// Every frame triangulated by `fit` (#frames by dims), kFramesPerBlock frames at a time, their
// distances from `distances`. `control` hears the fraction done.
Eigen::MatrixXd triangulate_all(const LandmarkFit& fit, int frames,
                                const LandmarkDistances& distances, const Control& control) {
  Eigen::MatrixXd out(frames, fit.projection.rows());
  Eigen::MatrixXd scratch;
  for (int first = 0; first < frames; first += kFramesPerBlock) {
    control.update(double(first) / frames);
    control.check();
    const int count = std::min(kFramesPerBlock, frames - first);
    triangulate_into(fit, distances(first, count, scratch), out.middleRows(first, count));
  }
  return out;
}

}  // namespace

EuclideanToLandmarks::EuclideanToLandmarks(const RowMatrix& landmarks)
    : m_by_value(landmarks), m_norms(landmarks.rows()) {
  for (Eigen::Index l = 0; l < landmarks.rows(); ++l) {
    double sum = 0.0;
    for (Eigen::Index c = 0; c < landmarks.cols(); ++c) sum += landmarks(l, c) * landmarks(l, c);
    m_norms[l] = sum;
  }
}

namespace {

// Two doubles in one register (GCC and Clang vector extensions: SSE2 on x86-64, NEON on arm64);
// the arithmetic is lane by lane, the same as on scalars.
typedef double Pair __attribute__((vector_size(16)));

Pair load_pair(const double* at) {
  Pair v;
  std::memcpy(&v, at, sizeof v);
  return v;
}

void store_pair(double* at, Pair v) {
  std::memcpy(at, &v, sizeof v);
}

// out_j[l] = Σ_c p_j[c]·q[c·L + l] for the 8 landmarks l0 … l0 + 7 and two frames p_0, p_1
// (p_1 = p_0 for one frame), each sum over c in order: the sixteen sums stay in eight registers
// through the pass over the values (a GEMM micro-kernel); an entry's arithmetic does not depend
// on the frame beside it.
void dot_block(const double* p0, const double* p1, const double* q, Eigen::Index L,
               Eigen::Index values, Eigen::Index l0, double* out0, double* out1) {
  Pair a0 = {}, a1 = {}, a2 = {}, a3 = {}, b0 = {}, b1 = {}, b2 = {}, b3 = {};
  for (Eigen::Index c = 0; c < values; ++c) {
    const double* qc = q + c * L + l0;
    const Pair q0 = load_pair(qc), q1 = load_pair(qc + 2), q2 = load_pair(qc + 4),
               q3 = load_pair(qc + 6);
    const Pair x = {p0[c], p0[c]}, y = {p1[c], p1[c]};
    a0 += x * q0;
    a1 += x * q1;
    a2 += x * q2;
    a3 += x * q3;
    b0 += y * q0;
    b1 += y * q1;
    b2 += y * q2;
    b3 += y * q3;
  }
  store_pair(out0 + l0, a0);
  store_pair(out0 + l0 + 2, a1);
  store_pair(out0 + l0 + 4, a2);
  store_pair(out0 + l0 + 6, a3);
  store_pair(out1 + l0, b0);
  store_pair(out1 + l0 + 2, b1);
  store_pair(out1 + l0 + 4, b2);
  store_pair(out1 + l0 + 6, b3);
}

// The same for one landmark l0.
void dot_one(const double* p0, const double* p1, const double* q, Eigen::Index L,
             Eigen::Index values, Eigen::Index l0, double* out0, double* out1) {
  double a = 0.0, b = 0.0;
  for (Eigen::Index c = 0; c < values; ++c) {
    a += p0[c] * q[c * L + l0];
    b += p1[c] * q[c * L + l0];
  }
  out0[l0] = a;
  out1[l0] = b;
}

}  // namespace

void EuclideanToLandmarks::compute(const RowMatrix& points, Eigen::Index first, Eigen::Index count,
                                   Eigen::Ref<Eigen::MatrixXd> out) const {
  const Eigen::Index L = m_by_value.rows(), values = m_by_value.cols();
  const double* q = m_by_value.data();
  Eigen::VectorXd spare(L);  // the second frame's sums when `count` is odd
  for (Eigen::Index j = 0; j < count; j += 2) {
    const bool two = j + 1 < count;
    const double* p0 = points.row(first + j).data();
    const double* p1 = two ? points.row(first + j + 1).data() : p0;
    double* out0 = out.col(j).data();
    double* out1 = two ? out.col(j + 1).data() : spare.data();
    Eigen::Index l0 = 0;
    for (; l0 + 8 <= L; l0 += 8) dot_block(p0, p1, q, L, values, l0, out0, out1);
    for (; l0 < L; ++l0) dot_one(p0, p1, q, L, values, l0, out0, out1);
  }
  for (Eigen::Index j = 0; j < count; ++j) {
    const double* p = points.row(first + j).data();
    double norm = 0.0;
    for (Eigen::Index c = 0; c < values; ++c) norm += p[c] * p[c];
    double* o = out.col(j).data();
    for (Eigen::Index l = 0; l < L; ++l) {
      o[l] = std::sqrt(std::max(0.0, norm + m_norms[l] - 2.0 * o[l]));
    }
  }
}

Eigen::MatrixXd triangulate(const LandmarkFit& fit, const Eigen::MatrixXd& distances) {
  const Eigen::Index L = fit.projection.cols(), dims = fit.projection.rows();
  if (distances.rows() != L) {
    throw ParameterError("triangulate: " + std::to_string(distances.rows()) +
                         " distances per frame given; the map has " + std::to_string(L) +
                         " landmarks");
  }
  Eigen::MatrixXd out(distances.cols(), dims);
  triangulate_into(fit, distances, out);
  return out;
}

std::vector<int> maxmin_landmarks(const PointSet& points, int count, const Control& control) {
  const int n = points.frames();
  count = std::clamp(count, 1, n);
  // nearest[f]: f's distance to the first seen[f] landmarks, an upper bound of its distance to
  // all those chosen. The queue's top is the farthest frame (ties: the smaller index) once its
  // entry is up to date; stale entries are brought up to date as they reach the top, which is
  // all most frames ever need.
  std::vector<double> nearest(static_cast<std::size_t>(n));
  std::vector<int> seen(std::size_t(n), 1);
  const int chunks = (n + kFramesPerChunk - 1) / kFramesPerChunk;
  parallel_chunks(chunks, [&](int c, int) {
    for (int f = c * kFramesPerChunk; f < std::min(n, (c + 1) * kFramesPerChunk); ++f) {
      nearest[f] = f == 0 ? 0.0 : points.distance(0, f);
    }
  });
  using Entry = std::pair<double, int>;
  const auto before = [](const Entry& a, const Entry& b) {
    return a.first < b.first || (a.first == b.first && a.second > b.second);
  };
  std::vector<Entry> queue;
  queue.reserve(std::size_t(n));
  for (int f = 1; f < n; ++f) queue.emplace_back(nearest[f], f);
  std::make_heap(queue.begin(), queue.end(), before);
  std::vector<int> landmarks{0};
  landmarks.reserve(std::size_t(count));
  for (std::int64_t pops = 0; int(landmarks.size()) < count && !queue.empty(); ++pops) {
    if (pops % 4096 == 0) {
      control.update(double(landmarks.size()) / count);
      control.check();
    }
    std::pop_heap(queue.begin(), queue.end(), before);
    const int f = queue.back().second;
    queue.pop_back();
    const int chosen = static_cast<int>(landmarks.size());
    if (seen[f] < chosen) {
      for (int l = seen[f]; l < chosen; ++l) {
        nearest[f] = std::min(nearest[f], points.distance(landmarks[l], f));
      }
      seen[f] = chosen;
      queue.emplace_back(nearest[f], f);
      std::push_heap(queue.begin(), queue.end(), before);
      continue;
    }
    if (!(nearest[f] > 0.0)) break;  // every frame is a landmark's duplicate
    landmarks.push_back(f);
  }
  return landmarks;
}

std::vector<int> maxmin_landmarks(const PointSet& points, int count, Eigen::MatrixXd& distances,
                                  const Control& control) {
  const int n = points.frames();
  std::vector<int> landmarks = maxmin_landmarks(points, count, control.part(0.0, 0.2));
  // Every frame's distances to the landmarks, a block of frames at a time against all of them
  // (the landmarks' rows stay in cache).
  const Eigen::Index L = static_cast<Eigen::Index>(landmarks.size());
  distances.resize(L, n);
  const int chunks = (n + kFramesPerChunk - 1) / kFramesPerChunk;
  const Control fill = control.part(0.2, 1.0);
  parallel_chunks(
      chunks,
      [&](int c, int) {
        for (int f = c * kFramesPerChunk; f < std::min(n, (c + 1) * kFramesPerChunk); ++f) {
          for (Eigen::Index l = 0; l < L; ++l) {
            distances(l, f) = f == landmarks[l] ? 0.0 : points.distance(landmarks[l], f);
          }
        }
      },
      [&](int done) { fill.update(double(done) / chunks); });
  return landmarks;
}

void fit_landmarks(const Eigen::MatrixXd& T, const Eigen::MatrixXd& distances,
                   const EmbedOptions& options, Embedding& out, Progress& progress, double begin,
                   double end) {
  fit_landmarks(
      T, static_cast<int>(distances.cols()),
      [&](int first, int count, Eigen::MatrixXd&) -> Eigen::Ref<const Eigen::MatrixXd> {
        return distances.middleCols(first, count);
      },
      options, out, progress, begin, end);
}

void fit_landmarks(const Eigen::MatrixXd& T, int frames, const LandmarkDistances& distances,
                   const EmbedOptions& options, Embedding& out, Progress& progress, double begin,
                   double end) {
  const std::string what(method_name(options.method));
  const int dims = options.dimensions;
  const Eigen::Index L = T.rows();
  LandmarkFit& fit = *out.landmarks;
  progress.stage("eigen", begin, begin + 0.3 * (end - begin));
  // 1. Classical MDS of the landmarks, in r ≥ dims axes: B = −½·J·S·J, S = T².
  const Eigen::MatrixXd S = T.selfadjointView<Eigen::Lower>().toDenseMatrix().array().square();
  fit.mean_squared = S.colwise().mean().transpose();
  const Eigen::VectorXd row_mean = S.rowwise().mean();
  const Eigen::MatrixXd B =
      -0.5 * ((S.colwise() - row_mean).rowwise() - row_mean.transpose()).array() -
      0.5 * fit.mean_squared.mean();
  const int r = static_cast<int>(std::min<Eigen::Index>(L - 1, std::max(dims, kLandmarkAxes)));
  const EigenPairs top = largest_eigenpairs(B, r, what);
  const double largest = std::max(top.values[0], 0.0);
  int kept = 0;
  while (kept < r && top.values[kept] > 1e-12 * largest) ++kept;
  out.negative.most_negative = top.smallest_ritz < -1e-9 * largest ? top.smallest_ritz : 0.0;
  out.negative.relative = largest > 0.0 ? -out.negative.most_negative / largest : 0.0;

  // 2. Every frame triangulated into those r axes: z = −½·P_r·(δ² − μ), P_r = (V ÷ √λ)ᵀ.
  progress.stage("triangulation", begin + 0.3 * (end - begin), begin + 0.9 * (end - begin));
  LandmarkFit wide;
  wide.mean_squared = fit.mean_squared;
  wide.projection =
      (top.vectors.leftCols(kept) * top.values.head(kept).cwiseSqrt().cwiseInverse().asDiagonal())
          .transpose();
  wide.offset = Eigen::VectorXd::Zero(kept);
  const Eigen::MatrixXd Z =
      triangulate_all(wide, frames, distances, progress.control().part(0, 0.5));

  // 3. PCA of the triangulated frames: their top `dims` axes. (de Silva & Tenenbaum's optional
  // last step; with r > dims it also corrects most of the landmarks' bias, since max-min
  // landmarks cover the poses evenly where the frames do not.) With every frame a landmark, Z
  // is classical MDS in r axes, whose principal axes are its own: the dense map.
  const Eigen::RowVectorXd mean = Z.colwise().mean();
  const Eigen::MatrixXd centred = Z.rowwise() - mean;
  const Eigen::MatrixXd C = centred.transpose() * centred;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> pca(C);
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(kept, dims);
  out.eigenvalues = Eigen::VectorXd::Zero(dims);
  for (int a = 0; a < std::min(dims, kept); ++a) {
    W.col(a) = pca.eigenvectors().col(kept - 1 - a);
    out.eigenvalues[a] = pca.eigenvalues()[kept - 1 - a];
  }
  for (int a = 0; a < dims; ++a) {
    if (!(out.eigenvalues[a] > 1e-12 * std::max(out.eigenvalues[0], 0.0))) {
      out.warnings.push_back("axis " + std::to_string(a + 1) +
                             " is flat (all 0): the landmarks' distances have fewer than " +
                             std::to_string(dims) + " positive dimensions");
    }
  }
  // 4. One linear map from δ² to the map: x = Wᵀ·(z − mean).
  fit.projection = W.transpose() * wide.projection;
  fit.offset = -(W.transpose() * mean.transpose());
  out.coordinates = triangulate_all(fit, frames, distances, progress.control().part(0.5, 1.0));
  progress.stage("stress", begin + 0.9 * (end - begin), end);
  Eigen::MatrixXd at_landmarks(L, dims);
  for (Eigen::Index l = 0; l < L; ++l) at_landmarks.row(l) = out.coordinates.row(fit.frames[l]);
  out.stress = normalized_stress(T, at_landmarks, progress.control());
}

void run_landmark_mds(const PointSet& points, const EmbedOptions& options, Embedding& out,
                      Progress& progress) {
  const int n = points.frames();
  progress.stage("landmarks", 0.02, 0.1);
  out.landmarks.emplace();
  const std::vector<int>& landmarks = out.landmarks->frames =
      maxmin_landmarks(points, landmark_count(options, n), progress.control());
  const Eigen::Index L = static_cast<Eigen::Index>(landmarks.size());
  // The frames' distances to the landmarks are computed a block at a time when the fit reads them
  // (twice), never all kept: the same values as maxmin_landmarks' matrix, and T as
  // landmark_block of it.
  Eigen::MatrixXd T(L, L);
  for (Eigen::Index a = 0; a < L; ++a) {
    for (Eigen::Index b = 0; b < L; ++b) {
      T(a, b) = a == b ? 0.0
                       : 0.5 * (points.distance(landmarks[a], landmarks[b]) +
                                points.distance(landmarks[b], landmarks[a]));
    }
  }
  // Euclidean points: the landmarks' distances by EuclideanToLandmarks, which placing new frames
  // uses as well (so the map's own frames land on their coordinates).
  std::optional<EuclideanToLandmarks> euclidean;
  if (points.metric == Metric::Euclidean) euclidean.emplace(landmark_rows(points, landmarks));
  const LandmarkDistances distances =
      [&](int first, int count, Eigen::MatrixXd& block) -> Eigen::Ref<const Eigen::MatrixXd> {
    block.resize(L, count);
    const int chunks = (count + kFramesPerChunk - 1) / kFramesPerChunk;
    parallel_chunks(chunks, [&](int c, int) {
      const int begin = c * kFramesPerChunk, end = std::min(count, (c + 1) * kFramesPerChunk);
      if (euclidean) {
        euclidean->compute(*points.rows, first + begin, end - begin,
                           block.middleCols(begin, end - begin));
        return;
      }
      for (int j = begin; j < end; ++j) {
        const int f = first + j;
        for (Eigen::Index l = 0; l < L; ++l) {
          block(l, j) = f == landmarks[l] ? 0.0 : points.distance(landmarks[l], f);
        }
      }
    });
    return block;
  };
  fit_landmarks(T, n, distances, options, out, progress, 0.1, 1.0);
}

void run_landmark_isomap(const PointSet& points, const EmbedOptions& options, Embedding& out,
                         Progress& progress) {
  NeighborGraph ng = build_neighbor_graph(points, options, out, progress, 0.02, 0.3);
  const int n = points.frames();
  progress.stage("landmarks", 0.3, 0.35);
  out.landmarks.emplace();
  LandmarkFit& fit = *out.landmarks;
  fit.frames = maxmin_landmarks(points, landmark_count(options, n), progress.control());
  const int L = static_cast<int>(fit.frames.size());
  progress.stage("shortest paths", 0.35, 0.85);
  const SearchGraph graph(ng.graph);
  ng = NeighborGraph();  // the searches read their own copy (0.6 GB at 10⁶ frames)
  fit.geodesic.resize(L, n);
  // A few landmarks per task: their distances are written to the L by #frames matrix together,
  // kBatch consecutive entries of each column at once, instead of one strided entry per cache
  // line per landmark.
  const int batches = (L + kBatch - 1) / kBatch;
  const int workers = worker_count(batches);
  std::vector<Dijkstra> searches;
  for (int w = 0; w < workers; ++w) searches.emplace_back(n);
  std::vector<std::vector<double>> dist(static_cast<std::size_t>(workers) * kBatch);
  parallel_chunks(
      batches,
      [&](int b, int worker) {
        const int l0 = b * kBatch, count = std::min(kBatch, L - l0);
        std::vector<double>* d = dist.data() + std::size_t(worker) * kBatch;
        for (int a = 0; a < count; ++a) {
          searches[worker].run(graph, graph.position[fit.frames[l0 + a]], d[a]);
        }
        for (int p = 0; p < n; ++p) {
          double* column = fit.geodesic.col(graph.frame[p]).data() + l0;
          for (int a = 0; a < count; ++a) column[a] = d[a][p];
        }
      },
      [&](int done) { progress.update(double(done) / batches); });
  fit_landmarks(landmark_block(fit.frames, fit.geodesic), fit.geodesic, options, out, progress,
                0.85, 1.0);
}

}  // namespace motionmap::embed
