// Landmark MDS and landmark Isomap (de Silva & Tenenbaum, "Global versus local methods in
// nonlinear dimensionality reduction", NIPS 2002; "Sparse multidimensional scaling using landmark
// points", 2004): classical MDS of L landmarks, then every frame triangulated from its distances
// to them. O(#frames·L) time and memory instead of O(#frames²).
#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>

#include "motionmap/core/error.h"
#include "motionmap/core/parallel.h"
#include "motionmap/embed/detail/methods.h"
#include "motionmap/embed/detail/progress.h"
#include "motionmap/embed/eigen.h"
#include "motionmap/embed/metrics.h"

namespace motionmap::embed {

namespace {

constexpr int kFramesPerChunk = 1024;
// Axes the frames are triangulated into before the final PCA (fewer when the landmarks' distances
// have fewer positive dimensions).
constexpr int kLandmarkAxes = 20;

int landmark_count(const EmbedOptions& options, int frames) {
  return std::min(frames, options.landmarks > 0 ? options.landmarks : kDefaultLandmarks);
}

// Shortest-path lengths from `source` to every frame (Dijkstra, binary heap with lazy deletion),
// written to dist (#frames; +inf where unreachable).
void dijkstra(const Graph& graph, int source, std::vector<double>& dist,
              std::vector<std::pair<double, int>>& heap_storage) {
  const int n = graph.frames();
  dist.assign(std::size_t(n), std::numeric_limits<double>::infinity());
  heap_storage.clear();
  std::priority_queue<std::pair<double, int>, std::vector<std::pair<double, int>>, std::greater<>>
      heap(std::greater<>(), std::move(heap_storage));
  dist[source] = 0.0;
  heap.emplace(0.0, source);
  while (!heap.empty()) {
    const auto [d, u] = heap.top();
    heap.pop();
    if (d > dist[u]) continue;
    for (int e = graph.offsets[u]; e < graph.offsets[u + 1]; ++e) {
      const int v = graph.targets[e];
      const double candidate = d + graph.weights[e];
      if (candidate < dist[v]) {
        dist[v] = candidate;
        heap.emplace(candidate, v);
      }
    }
  }
}

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

}  // namespace

Eigen::MatrixXd triangulate(const LandmarkFit& fit, const Eigen::MatrixXd& distances) {
  const Eigen::Index L = fit.projection.cols(), dims = fit.projection.rows();
  if (distances.rows() != L) {
    throw ParameterError("triangulate: " + std::to_string(distances.rows()) +
                         " distances per frame given; the map has " + std::to_string(L) +
                         " landmarks");
  }
  const int n = static_cast<int>(distances.cols());
  Eigen::MatrixXd out(n, dims);
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
  return out;
}

std::vector<int> maxmin_landmarks(const PointSet& points, int count, Eigen::MatrixXd& distances,
                                  const Control& control) {
  const int n = points.frames();
  count = std::clamp(count, 1, n);
  distances.resize(count, n);
  std::vector<double> nearest(std::size_t(n), std::numeric_limits<double>::infinity());
  std::vector<int> landmarks;
  landmarks.reserve(std::size_t(count));
  int next = 0;
  const int chunks = (n + kFramesPerChunk - 1) / kFramesPerChunk;
  for (int l = 0; l < count; ++l) {
    control.update(double(l) / count);
    control.check();
    landmarks.push_back(next);
    const int from = next;
    parallel_chunks(chunks, [&](int c, int) {
      for (int f = c * kFramesPerChunk; f < std::min(n, (c + 1) * kFramesPerChunk); ++f) {
        const double d = f == from ? 0.0 : points.distance(from, f);
        distances(l, f) = d;
        nearest[f] = std::min(nearest[f], d);
      }
    });
    next = static_cast<int>(std::max_element(nearest.begin(), nearest.end()) - nearest.begin());
    if (!(nearest[next] > 0.0)) break;  // every frame is a landmark's duplicate
  }
  distances.conservativeResize(static_cast<Eigen::Index>(landmarks.size()), n);
  return landmarks;
}

void fit_landmarks(const Eigen::MatrixXd& T, const Eigen::MatrixXd& distances,
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
  progress.stage("triangulation", begin + 0.3 * (end - begin), begin + 0.8 * (end - begin));
  LandmarkFit wide;
  wide.mean_squared = fit.mean_squared;
  wide.projection =
      (top.vectors.leftCols(kept) * top.values.head(kept).cwiseSqrt().cwiseInverse().asDiagonal())
          .transpose();
  wide.offset = Eigen::VectorXd::Zero(kept);
  const Eigen::MatrixXd Z = triangulate(wide, distances);

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
  progress.stage("stress", begin + 0.8 * (end - begin), end);
  out.coordinates = triangulate(fit, distances);
  Eigen::MatrixXd at_landmarks(L, dims);
  for (Eigen::Index l = 0; l < L; ++l) at_landmarks.row(l) = out.coordinates.row(fit.frames[l]);
  out.stress = normalized_stress(T, at_landmarks, progress.control());
}

void run_landmark_mds(const PointSet& points, const EmbedOptions& options, Embedding& out,
                      Progress& progress) {
  const int L = landmark_count(options, points.frames());
  progress.stage("landmarks", 0.02, 0.7);
  out.landmarks.emplace();
  Eigen::MatrixXd distances;
  out.landmarks->frames = maxmin_landmarks(points, L, distances, progress.control());
  fit_landmarks(landmark_block(out.landmarks->frames, distances), distances, options, out, progress,
                0.7, 1.0);
}

void run_landmark_isomap(const PointSet& points, const EmbedOptions& options, Embedding& out,
                         Progress& progress) {
  const NeighborGraph ng = build_neighbor_graph(points, options, out, progress, 0.02, 0.3);
  const int n = points.frames();
  const int L = landmark_count(options, n);
  progress.stage("landmarks", 0.3, 0.35);
  out.landmarks.emplace();
  LandmarkFit& fit = *out.landmarks;
  {
    Eigen::MatrixXd unused;
    fit.frames = maxmin_landmarks(points, L, unused, progress.control());
  }
  progress.stage("shortest paths", 0.35, 0.85);
  fit.geodesic.resize(L, n);
  const int workers = worker_count(L);
  std::vector<std::vector<double>> dist(static_cast<std::size_t>(workers));
  std::vector<std::vector<std::pair<double, int>>> heaps(static_cast<std::size_t>(workers));
  parallel_chunks(
      L,
      [&](int l, int worker) {
        dijkstra(ng.graph, fit.frames[l], dist[worker], heaps[worker]);
        for (int f = 0; f < n; ++f) fit.geodesic(l, f) = dist[worker][f];
      },
      [&](int done) { progress.update(double(done) / L); });
  fit_landmarks(landmark_block(fit.frames, fit.geodesic), fit.geodesic, options, out, progress,
                0.85, 1.0);
}

}  // namespace motionmap::embed
