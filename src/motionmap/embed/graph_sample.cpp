// The points path's Laplacian eigenmap and LLE on large libraries (embed.h, kGraphSampleLimit):
// the method on a strided sample of the frames, every other frame placed on the sample's map by
// place() (placement.h: le by the Nyström extension, lle by the barycentric weights of its k
// nearest samples), as new frames are placed on a saved map of it.
#include <algorithm>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "motionmap/embed/detail/methods.h"
#include "motionmap/embed/detail/progress.h"
#include "motionmap/embed/detail/routines.h"
#include "motionmap/embed/placement.h"
#include "motionmap/embed/points.h"

namespace motionmap::embed {

namespace {
// Frames placed per round (their rows are copied together).
constexpr int kPlaceChunk = 65536;
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
  // The sample's map as a model (placement.h), which places every other frame as place() places
  // new frames on a saved map of it: so placing a frame of this map again lands on its row.
  Embedding fit;
  fit.method = options.method;
  fit.coordinates = std::move(out.coordinates);
  fit.eigenvalues = out.eigenvalues;
  fit.k_used = out.k_used;
  fit.heat_used = out.heat_used;
  fit.from_points = true;
  EmbedInput sample_input;
  sample_input.features = lle ? &sample_features : nullptr;
  sample_input.points = &sample_points;
  sample_input.metric = points.metric;
  const MapModel model = make_model(sample_input, options, std::move(fit));

  // 2. Every other frame from its k nearest samples, a round of frames at a time.
  progress.stage("placing", 0.6, 1.0);
  const std::unique_ptr<SampleSearch> search = make_search(model, progress.control().part(0, 0.1));
  out.coordinates.resize(n, dims);
  for (int j = 0; j < m; ++j) out.coordinates.row(sample[j]) = model.coordinates.row(j);
  std::vector<int> others;
  others.reserve(std::size_t(n - m));
  for (int f = 0; f < n; ++f) {
    if (f % stride != 0) others.push_back(f);
  }
  const int rounds = (static_cast<int>(others.size()) + kPlaceChunk - 1) / kPlaceChunk;
  RowMatrix round_points;
  Eigen::MatrixXd round_features;
  for (int r = 0; r < rounds; ++r) {
    const std::size_t first = std::size_t(r) * kPlaceChunk;
    const std::span<const int> frames(others.data() + first,
                                      std::min<std::size_t>(kPlaceChunk, others.size() - first));
    const int count = static_cast<int>(frames.size());
    round_points.resize(count, points.rows->cols());
    for (int q = 0; q < count; ++q) round_points.row(q) = points.rows->row(frames[q]);
    if (lle) {
      round_features.resize(count, X->cols());
      for (int q = 0; q < count; ++q) round_features.row(q) = X->row(frames[q]);
    }
    const double from = 0.1 + 0.9 * r / rounds, to = 0.1 + 0.9 * (r + 1) / rounds;
    const Eigen::MatrixXd placed =
        place(model, PlaceInput{lle ? &round_features : nullptr, &round_points},
              progress.control().part(from, to), search.get());
    for (int q = 0; q < count; ++q) out.coordinates.row(frames[q]) = placed.row(q);
  }
  out.fitted_frames = std::move(sample);
  const int k = model.k;
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
