// Embedding stages and methods at F = 500, 2000, 8000 frames, k = 20, on the inputs of
// bench_inputs.h: X (joint-rotation quaternions) and D (point-cloud distances) from
// build_features, of the real CMU 64 swings ("real", F = 500 only: the clips hold 816 frames)
// and of the built-in sample swing ("sample", every size). Each method's benchmark runs the whole
// embed() call (input validation included) and reports its stage times as counters (seconds,
// last run). The features stages (X, D) are in features_bench.cpp.
//
//   build/bench/motionmap_bench --benchmark_filter='Embed|Knn|Shortest'
//   build/bench/motionmap_bench --benchmark_filter='Embed/isomap/sample/8000'
#include <string>

#include <benchmark/benchmark.h>

#include "bench_inputs.h"
#include "motionmap/embed/embed.h"
#include "motionmap/embed/graph.h"
#include "motionmap/embed/neighbors.h"

namespace {

using motionmap::bench::Input;
using motionmap::bench::kNeighbours;
using motionmap::embed::Method;

enum class Source { Real, Sample };

// The input of this run, or nullptr after marking the run skipped (no real data).
const Input* input_for(benchmark::State& state, Source source) {
  const int frames = static_cast<int>(state.range(0));
  const Input* in = source == Source::Real ? motionmap::bench::real_input(frames)
                                           : &motionmap::bench::sample_input(frames);
  if (in == nullptr) {
    state.SkipWithError(("no real input of " + std::to_string(frames) + " frames in " +
                         motionmap::bench::shared_data().string())
                            .c_str());
  }
  return in;
}

// Stage: the k-NN lists of D and the symmetric k-NN graph (Isomap, LE, LLE).
void BM_KnnGraph(benchmark::State& state, Source source) {
  const Input* in = input_for(state, source);
  if (in == nullptr) return;
  for (auto _ : state) {
    auto lists = motionmap::embed::knn_from_distances(in->D, kNeighbours);
    auto graph = motionmap::embed::knn_graph(lists, in->D);
    benchmark::DoNotOptimize(graph.targets.data());
  }
}

// Stage: all-pairs shortest paths along the k-NN graph (Isomap).
void BM_ShortestPaths(benchmark::State& state, Source source) {
  const Input* in = input_for(state, source);
  if (in == nullptr) return;
  const auto graph =
      motionmap::embed::knn_graph(motionmap::embed::knn_from_distances(in->D, kNeighbours), in->D);
  for (auto _ : state) {
    Eigen::MatrixXd geo = motionmap::embed::shortest_paths(graph);
    benchmark::DoNotOptimize(geo.data());
  }
}

// A whole method: embed() on X and/or D.
void BM_Embed(benchmark::State& state, Method method, Source source) {
  const Input* in = input_for(state, source);
  if (in == nullptr) return;
  motionmap::embed::EmbedOptions options;
  options.method = method;
  options.k = kNeighbours;
  motionmap::embed::Embedding map;
  for (auto _ : state) {
    map = motionmap::embed::embed({.features = &in->X, .distances = &in->D}, options);
    benchmark::DoNotOptimize(map.coordinates.data());
  }
  for (const auto& t : map.timings) state.counters[t.stage] = t.seconds;
}

void real_sizes(benchmark::internal::Benchmark* b) {
  b->Arg(500)->Unit(benchmark::kMillisecond)->UseRealTime();
}

void sample_sizes(benchmark::internal::Benchmark* b) {
  b->Arg(500)->Arg(2000)->Arg(8000)->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK_CAPTURE(BM_KnnGraph, real, Source::Real)->Apply(real_sizes);
BENCHMARK_CAPTURE(BM_KnnGraph, sample, Source::Sample)->Apply(sample_sizes);
BENCHMARK_CAPTURE(BM_ShortestPaths, real, Source::Real)->Apply(real_sizes);
BENCHMARK_CAPTURE(BM_ShortestPaths, sample, Source::Sample)->Apply(sample_sizes);

// Registered by hand so the name reads BM_Embed/<method>/<source>/<frames>.
const bool registered = [] {
  for (Method method : motionmap::embed::all_methods()) {
    const std::string name = "BM_Embed/" + std::string(motionmap::embed::method_name(method));
    benchmark::RegisterBenchmark((name + "/real").c_str(), BM_Embed, method, Source::Real)
        ->Apply(real_sizes);
    benchmark::RegisterBenchmark((name + "/sample").c_str(), BM_Embed, method, Source::Sample)
        ->Apply(sample_sizes);
  }
  return true;
}();

}  // namespace
