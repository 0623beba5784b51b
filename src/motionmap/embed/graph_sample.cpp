// The points path's Laplacian eigenmap and LLE on large libraries (embed.h, kGraphSampleLimit):
// the method on a strided sample of the frames, every other frame placed by the method's
// out-of-sample rule over its k nearest samples, as placement.cpp places new frames:
//   le   the Nyström extension (Bengio et al. 2004): x_c = Σ w_s·y_s,c ÷ ((1 − λ_c)·Σ w_s), w the
//        heat kernel (shifted by the nearest distance: the ratio is the same, nothing underflows);
//   lle  the barycentric weights of the k nearest samples in X, regularised as the fit's.
// A frame at distance 0 from a sample lands on it.
#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Cholesky>

#include "motionmap/core/parallel.h"
#include "motionmap/embed/detail/methods.h"
#include "motionmap/embed/detail/progress.h"

namespace motionmap::embed {

namespace {
// Frames placed per round (their k-NN lists are held together).
constexpr int kPlaceChunk = 65536;
constexpr int kFramesPerTask = 256;
}  // namespace

void run_sampled_graph_method(const Eigen::MatrixXd* X, const PointSet& points,
                              const EmbedOptions& options, Embedding& out, Progress& progress,
                              int sample_limit) {
  const bool lle = options.method == Method::Lle;
  const int n = points.frames(), dims = options.dimensions;
  const int stride = (n + sample_limit - 1) / sample_limit;
  std::vector<int> sample;
  for (int f = 0; f < n; f += stride) sample.push_back(f);
  const int m = static_cast<int>(sample.size());
  RowMatrix sample_points(m, points.rows->cols());
  for (int j = 0; j < m; ++j) sample_points.row(j) = points.rows->row(sample[j]);
  const PointSet samples{&sample_points, points.metric};
  Eigen::MatrixXd sample_features;
  if (lle) {
    sample_features.resize(m, X->cols());
    for (int j = 0; j < m; ++j) sample_features.row(j) = X->row(sample[j]);
  }

  // 1. The fit on the sample.
  const NeighborGraph ng = build_neighbor_graph(samples, options, out, progress, 0.02, 0.15);
  if (lle) {
    lle_on(sample_features, ng, options, out, progress, 0.15, 0.6);
  } else {
    laplacian_eigenmap_on(ng, options, out, progress, 0.15, 0.6);
  }
  const Eigen::MatrixXd fitted = std::move(out.coordinates);

  // 2. Every other frame from its k nearest samples.
  progress.stage("placing", 0.6, 1.0);
  out.coordinates.resize(n, dims);
  for (int j = 0; j < m; ++j) out.coordinates.row(sample[j]) = fitted.row(j);
  std::vector<int> others;
  others.reserve(std::size_t(n - m));
  for (int f = 0; f < n; ++f) {
    if (f % stride != 0) others.push_back(f);
  }
  const int k = std::min(options.k, m);
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> sample_rows =
      sample_features;
  const int rounds = (static_cast<int>(others.size()) + kPlaceChunk - 1) / kPlaceChunk;
  for (int r = 0; r < rounds; ++r) {
    const std::size_t first = std::size_t(r) * kPlaceChunk;
    const std::span<const int> frames(others.data() + first,
                                      std::min<std::size_t>(kPlaceChunk, others.size() - first));
    const Control round = progress.control().part(double(r) / rounds, double(r + 1) / rounds);
    const NeighborLists nn = knn_to_samples(samples, points, frames, k, round.part(0.0, 0.9));
    const int count = static_cast<int>(frames.size());
    const int tasks = (count + kFramesPerTask - 1) / kFramesPerTask;
    parallel_chunks(tasks, [&](int t, int) {
      Eigen::MatrixXd Z, C;
      for (int q = t * kFramesPerTask; q < std::min(count, (t + 1) * kFramesPerTask); ++q) {
        const int f = frames[q];
        const auto nb = nn.of(q);
        const auto nd = nn.distances_of(q);
        double value[3] = {0.0, 0.0, 0.0};
        if (nd[0] == 0.0) {
          for (int c = 0; c < dims; ++c) value[c] = fitted(nb[0], c);
        } else if (lle) {
          Z.resize(k, X->cols());
          for (int a = 0; a < k; ++a) Z.row(a) = sample_rows.row(nb[a]) - X->row(f);
          C.setZero(k, k);
          C.selfadjointView<Eigen::Lower>().rankUpdate(Z);
          const double trace = C.trace();
          C.diagonal().array() += trace > 0.0 ? options.reg * trace : options.reg;
          Eigen::VectorXd w = C.llt().solve(Eigen::VectorXd::Ones(k));
          w /= w.sum();
          for (int a = 0; a < k; ++a) {
            for (int c = 0; c < dims; ++c) value[c] += w[a] * fitted(nb[a], c);
          }
        } else {
          const double heat = out.heat_used;
          double total = 0.0;
          for (int a = 0; a < k; ++a) {
            const double w = heat > 0.0 ? std::exp(-(nd[a] * nd[a] - nd[0] * nd[0]) / heat) : 1.0;
            total += w;
            for (int c = 0; c < dims; ++c) value[c] += w * fitted(nb[a], c);
          }
          for (int c = 0; c < dims; ++c) value[c] /= total * (1.0 - out.eigenvalues[c]);
        }
        for (int c = 0; c < dims; ++c) out.coordinates(f, c) = value[c];
      }
    });
    round.update(1.0);
  }
  out.warnings.push_back(std::string(method_name(options.method)) + " on " + std::to_string(n) +
                         " frames: the eigenproblem was solved on " + std::to_string(m) +
                         " of them (every " + std::to_string(stride) +
                         (stride == 2   ? "nd"
                          : stride == 3 ? "rd"
                                        : "th") +
                         " frame), the others placed by " +
                         (lle ? "the barycentric weights of" : "the Nyström extension over") +
                         " their " + std::to_string(k) + " nearest of those (above " +
                         std::to_string(sample_limit) +
                         " frames the whole graph's factorization grows out of memory)");
}

}  // namespace motionmap::embed
