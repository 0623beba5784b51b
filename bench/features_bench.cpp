// Features stages: the data matrix X (forward kinematics to the heading-local point cloud plus
// the sign-consistent rotation quaternions, per frame), the pose distances D (pairwise Euclidean
// distances of the point clouds, O(F²)), and the whole build_features() call that does both.
// Inputs as bench_inputs.h: the built-in sample swing at F = 500, 2000, 8000 frames, and the real
// CMU 64_08 + 64_09 swings (816 frames, T-poses left out; D of their first 500 frames).
//
//   build/bench/motionmap_bench --benchmark_filter='Features|Pairwise|FeatureMatrix'
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "bench_inputs.h"
#include "motionmap/features/features.h"
#include "motionmap/features/point_cloud.h"

namespace {

using motionmap::Clip;

enum class Source { Real, Sample };

// The clips of this run (cached per size), or nullptr after marking the run skipped.
const std::vector<Clip>* clips_for(benchmark::State& state, Source source) {
  if (source == Source::Real) {
    static const std::vector<Clip> real =
        motionmap::bench::load_clips(motionmap::bench::real_clip_paths());
    if (real.empty()) {
      state.SkipWithError(("no real clips in " + motionmap::bench::shared_data().string()).c_str());
      return nullptr;
    }
    return &real;
  }
  static std::map<int, std::vector<Clip>> cache;
  const int frames = static_cast<int>(state.range(0));
  auto& slot = cache[frames];
  if (slot.empty()) slot.push_back(motionmap::bench::sample_clip(frames));
  return &slot;
}

void set_frames(benchmark::State& state, const std::vector<Clip>& clips) {
  int frames = 0;
  for (const Clip& c : clips) frames += c.motion.num_frames;
  state.counters["frames"] = frames;
}

// X: per clip the heading-local point cloud (forward kinematics) and the rotation quaternions of
// the non-root joints; no distances.
void BM_FeatureMatrix(benchmark::State& state, Source source) {
  const std::vector<Clip>* clips = clips_for(state, source);
  if (clips == nullptr) return;
  for (auto _ : state) {
    for (const Clip& clip : *clips) {
      const auto cloud = motionmap::features::heading_local_points(clip.skeleton, clip.motion);
      std::vector<int> joints, frames(static_cast<std::size_t>(clip.motion.num_frames));
      for (int j = 0; j < clip.skeleton.num_joints(); ++j) {
        if (clip.skeleton.joints[j].parent >= 0) joints.push_back(j);
      }
      std::iota(frames.begin(), frames.end(), 0);
      const Eigen::MatrixXd X =
          motionmap::features::quaternion_features(clip.motion, joints, frames);
      benchmark::DoNotOptimize(cloud.data());
      benchmark::DoNotOptimize(X.data());
    }
  }
  set_frames(state, *clips);
}

// D: the pairwise point-cloud distances of F frames.
void BM_PairwiseDistances(benchmark::State& state, Source source) {
  const int frames = static_cast<int>(state.range(0));
  const std::vector<Clip>* clips = clips_for(state, source);
  if (clips == nullptr) return;
  std::vector<motionmap::features::RowMatrix> clouds;
  Eigen::Index rows = 0;
  for (const Clip& clip : *clips) {
    clouds.push_back(motionmap::features::heading_local_points(clip.skeleton, clip.motion));
    rows += clouds.back().rows();
  }
  motionmap::features::RowMatrix cloud(rows, clouds.front().cols());
  for (Eigen::Index r = 0; const auto& c : clouds) {
    cloud.middleRows(r, c.rows()) = c;
    r += c.rows();
  }
  if (frames > cloud.rows()) {
    state.SkipWithError(("only " + std::to_string(cloud.rows()) + " frames").c_str());
    return;
  }
  const auto points = cloud.topRows(frames);
  for (auto _ : state) {
    Eigen::MatrixXd D = motionmap::features::pairwise_distances(points);
    benchmark::DoNotOptimize(D.data());
  }
  state.counters["dims"] = static_cast<double>(points.cols());
}

// The whole build_features() call with the library's defaults (X and D).
void BM_BuildFeatures(benchmark::State& state, Source source) {
  const std::vector<Clip>* clips = clips_for(state, source);
  if (clips == nullptr) return;
  const motionmap::features::FeatureOptions options;
  int samples = 0;
  for (auto _ : state) {
    const auto set = motionmap::features::build_features(*clips, options);
    samples = set.num_samples();
    benchmark::DoNotOptimize(set.D.data());
  }
  state.counters["frames"] = samples;
}

void sample_sizes(benchmark::internal::Benchmark* b) {
  b->Arg(500)->Arg(2000)->Arg(8000)->Unit(benchmark::kMillisecond)->UseRealTime();
}

// Real: every frame of both clips (the argument is only a label for the X and whole-call runs).
void real_all(benchmark::internal::Benchmark* b) {
  b->Arg(816)->Unit(benchmark::kMillisecond)->UseRealTime();
}

void real_500(benchmark::internal::Benchmark* b) {
  b->Arg(500)->Unit(benchmark::kMillisecond)->UseRealTime();
}

BENCHMARK_CAPTURE(BM_FeatureMatrix, real, Source::Real)->Apply(real_all);
BENCHMARK_CAPTURE(BM_FeatureMatrix, sample, Source::Sample)->Apply(sample_sizes);
BENCHMARK_CAPTURE(BM_PairwiseDistances, real, Source::Real)->Apply(real_500);
BENCHMARK_CAPTURE(BM_PairwiseDistances, sample, Source::Sample)->Apply(sample_sizes);
BENCHMARK_CAPTURE(BM_BuildFeatures, real, Source::Real)->Apply(real_all);
BENCHMARK_CAPTURE(BM_BuildFeatures, sample, Source::Sample)->Apply(sample_sizes);

}  // namespace
