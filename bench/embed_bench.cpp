// Embedding stages and methods at F = 500, 2000, 8000 frames of a synthetic smooth trajectory
// (120 dims, D = Euclidean distances), k = 20. Each method's benchmark runs the whole embed()
// call (validation included) and reports its stage times as counters (seconds, last run).
//
//   build/bench/motionmap_bench --benchmark_filter='Embed|Knn|Shortest'
#include <cmath>
#include <map>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "motionmap/embed/embed.h"
#include "motionmap/embed/graph.h"
#include "motionmap/embed/neighbors.h"

namespace {

using motionmap::embed::Method;

constexpr int kDims = 120;
constexpr int kNeighbours = 20;

// The same formula as tests/embed/embed_test_util.h and the scikit-learn timing script.
Eigen::MatrixXd smooth_trajectory(int frames, int dims) {
  Eigen::MatrixXd X(frames, dims);
  const double two_pi = 2.0 * M_PI;
  for (int i = 0; i < frames; ++i) {
    const double s = double(i) / double(frames - 1);
    for (int j = 0; j < dims; ++j) {
      const double f = 1.0 + (j % 5) * 0.5 + 0.1 * (j % 3);
      const double amp = 1.0 / (1.0 + 0.1 * j);
      X(i, j) = amp * std::sin(two_pi * 4.0 * f * s + 0.37 * j) +
                0.3 * amp * s * std::cos(0.5 * j) + 0.01 * amp * std::sin(12.9898 * i + 78.233 * j);
    }
  }
  return X;
}

struct Input {
  Eigen::MatrixXd X;
  Eigen::MatrixXd D;
};

// Inputs are built once per size and kept (D at 8000 frames is 512 MB).
const Input& input(int frames) {
  static std::map<int, std::unique_ptr<Input>> cache;
  auto& slot = cache[frames];
  if (!slot) {
    slot = std::make_unique<Input>();
    slot->X = smooth_trajectory(frames, kDims);
    const Eigen::VectorXd sq = slot->X.rowwise().squaredNorm();
    Eigen::MatrixXd d2 = -2.0 * slot->X * slot->X.transpose();
    d2.colwise() += sq;
    d2.rowwise() += sq.transpose();
    slot->D = d2.cwiseMax(0.0).cwiseSqrt();
    slot->D = 0.5 * (slot->D + slot->D.transpose()).eval();
    slot->D.diagonal().setZero();
  }
  return *slot;
}

void BM_KnnGraph(benchmark::State& state) {
  const Input& in = input(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    auto lists = motionmap::embed::knn_from_distances(in.D, kNeighbours);
    auto graph = motionmap::embed::knn_graph(lists, in.D);
    benchmark::DoNotOptimize(graph.targets.data());
  }
}

void BM_ShortestPaths(benchmark::State& state) {
  const Input& in = input(static_cast<int>(state.range(0)));
  const auto graph =
      motionmap::embed::knn_graph(motionmap::embed::knn_from_distances(in.D, kNeighbours), in.D);
  for (auto _ : state) {
    Eigen::MatrixXd geo = motionmap::embed::shortest_paths(graph);
    benchmark::DoNotOptimize(geo.data());
  }
}

void BM_Embed(benchmark::State& state, Method method) {
  const Input& in = input(static_cast<int>(state.range(0)));
  motionmap::embed::EmbedOptions options;
  options.method = method;
  options.k = kNeighbours;
  motionmap::embed::Embedding map;
  for (auto _ : state) {
    map = motionmap::embed::embed({.features = &in.X, .distances = &in.D}, options);
    benchmark::DoNotOptimize(map.coordinates.data());
  }
  for (const auto& t : map.timings) state.counters[t.stage] = t.seconds;
}

void sizes(benchmark::internal::Benchmark* b) {
  b->Arg(500)->Arg(2000)->Arg(8000)->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK(BM_KnnGraph)->Apply(sizes);
BENCHMARK(BM_ShortestPaths)->Apply(sizes);
BENCHMARK_CAPTURE(BM_Embed, pca, Method::Pca)->Apply(sizes);
BENCHMARK_CAPTURE(BM_Embed, svd, Method::Svd)->Apply(sizes);
BENCHMARK_CAPTURE(BM_Embed, mds, Method::Mds)->Apply(sizes);
BENCHMARK_CAPTURE(BM_Embed, isomap, Method::Isomap)->Apply(sizes);
BENCHMARK_CAPTURE(BM_Embed, le, Method::LaplacianEigenmap)->Apply(sizes);
BENCHMARK_CAPTURE(BM_Embed, lle, Method::Lle)->Apply(sizes);

}  // namespace
