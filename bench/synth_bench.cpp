// Synthesis: map-point queries (weights + blend of a 31-joint pose), the blenders' set-up (local
// neighbourhood systems, the kriging LU) and a whole path. Synthetic data: a random-walk map of N
// samples over N frames of the built-in 31-joint walk.
//
//   build/bench/motionmap_bench --benchmark_filter='Synth'
//   build/bench/motionmap_bench --benchmark_filter='SynthKrigingFactor/10000'   # ~800 MB, minutes
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <random>
#include <utility>

#include <benchmark/benchmark.h>

#include "motionmap/embed/embed.h"
#include "motionmap/io/load.h"
#include "motionmap/sample/sample_clip.h"
#include "motionmap/synth/path_edit.h"
#include "motionmap/synth/synthesize.h"

namespace {

using motionmap::synth::BlendMode;
using motionmap::synth::MapBlender;

struct Data {
  motionmap::Clip clip;
  motionmap::features::FeatureSet set;
  Eigen::MatrixXd map;
};

// Built once per N and kept.
const Data& data(int n) {
  static std::map<int, std::unique_ptr<Data>> cache;
  auto& slot = cache[n];
  if (!slot) {
    slot = std::make_unique<Data>();
    motionmap::sample::SampleOptions so;
    so.seconds = n / so.fps;
    slot->clip = motionmap::sample::make_sample_clip(motionmap::sample::SampleKind::Walk, so);
    slot->set.segment_starts = {0};
    for (int f = 0; f < n; ++f) {
      slot->set.clip_of.push_back(0);
      slot->set.frame_of.push_back(f);
    }
    std::mt19937 rng(42);
    std::normal_distribution<double> step(0.0, 1.0);
    slot->map.resize(n, 2);
    slot->map.row(0).setZero();
    for (int i = 1; i < n; ++i)
      slot->map.row(i) = slot->map.row(i - 1) + Eigen::RowVector2d(step(rng), step(rng));
  }
  return *slot;
}

MapBlender make(int n, BlendMode mode) {
  const Data& d = data(n);
  motionmap::synth::BlendOptions opt;
  opt.mode = mode;
  return MapBlender(std::span<const motionmap::Clip>(&d.clip, 1), d.set, d.map, opt);
}

const MapBlender& blender(int n, BlendMode mode) {
  static std::map<std::pair<int, BlendMode>, std::unique_ptr<MapBlender>> cache;
  auto& slot = cache[{n, mode}];
  if (!slot) slot = std::make_unique<MapBlender>(make(n, mode));
  return *slot;
}

// Query points inside the data: a random sample's map point plus up to half a step.
std::vector<Eigen::Vector2d> queries(int n, int count) {
  const Data& d = data(n);
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> pick(0, n - 1);
  std::uniform_real_distribution<double> jitter(-0.5, 0.5);
  std::vector<Eigen::Vector2d> out;
  for (int i = 0; i < count; ++i)
    out.emplace_back(d.map.row(pick(rng)).transpose() + Eigen::Vector2d(jitter(rng), jitter(rng)));
  return out;
}

void run_pose_query(benchmark::State& state, BlendMode mode) {
  const int n = static_cast<int>(state.range(0));
  const MapBlender& b = blender(n, mode);
  const auto pts = queries(n, 1024);
  std::size_t i = 0;
  for (auto _ : state) {
    motionmap::Motion pose = b.pose_at(pts[i++ % pts.size()]);
    benchmark::DoNotOptimize(pose.rotations.data());
  }
  state.counters["joints"] = b.skeleton().num_joints();
}

// One pose query: weights at a map point + blend of the 31-joint pose (target: < 50 µs at 10 000).
void BM_SynthPoseLocal(benchmark::State& state) {
  run_pose_query(state, BlendMode::Local);
}
void BM_SynthPoseIdw(benchmark::State& state) {
  run_pose_query(state, BlendMode::Idw);
}
void BM_SynthPoseKriging(benchmark::State& state) {
  run_pose_query(state, BlendMode::Kriging);
}
BENCHMARK(BM_SynthPoseLocal)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SynthPoseIdw)->Arg(1000)->Arg(10000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SynthPoseKriging)->Arg(1000)->Arg(2000)->Unit(benchmark::kMicrosecond);

// Weights only, and the clamp of a point outside the data (radius searches over the segments).
void BM_SynthLocateLocal(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const MapBlender& b = blender(n, BlendMode::Local);
  const auto pts = queries(n, 1024);
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(b.locate(pts[i++ % pts.size()]).weights.data());
}
BENCHMARK(BM_SynthLocateLocal)->Arg(10000)->Unit(benchmark::kMicrosecond);

void BM_SynthLocateOutside(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const MapBlender& b = blender(n, BlendMode::Local);
  for (auto _ : state)
    benchmark::DoNotOptimize(b.locate(Eigen::Vector2d(1e4, -1e4)).weights.data());
}
BENCHMARK(BM_SynthLocateOutside)->Arg(10000)->Unit(benchmark::kMicrosecond);

// Set-up: per-sample data, merging, k-d tree and every local system (local mode).
void BM_SynthBuildLocal(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  data(n);
  for (auto _ : state) benchmark::DoNotOptimize(make(n, BlendMode::Local).num_points());
}
BENCHMARK(BM_SynthBuildLocal)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);

// Kriging set-up: dominated by the in-place LU of the dense (N+1)² system, (2/3)·N³ flops.
void BM_SynthKrigingFactor(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  data(n);
  for (auto _ : state) benchmark::DoNotOptimize(make(n, BlendMode::Kriging).num_points());
  state.counters["GFlop"] = 2.0 / 3.0 * std::pow(n + 1.0, 3) * 1e-9;
}
BENCHMARK(BM_SynthKrigingFactor)->Arg(1000)->Arg(2000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SynthKrigingFactor)->Arg(10000)->Iterations(1)->Unit(benchmark::kSecond);

// A 10 s path (1201 frames at 120 fps) through 100 samples spread over the map, local mode,
// the default options (the weights smoothed over σ 0.05 s, feet cleaned).
void BM_SynthPath(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const MapBlender& b = blender(n, BlendMode::Local);
  motionmap::synth::MapPath path;
  const Data& d = data(n);
  for (int i = 0; i < 100; ++i) {
    path.points.push_back(d.map.row(i * (n / 100)).transpose());
    path.times.push_back(i * 10.0 / 99.0);
  }
  for (auto _ : state)
    benchmark::DoNotOptimize(motionmap::synth::synthesize(b, path).motion.num_frames);
}
BENCHMARK(BM_SynthPath)->Arg(10000)->Unit(benchmark::kMillisecond);

// A local edit of the 10 s path above (synth::edit_path): its middle control point (of 100)
// moved half-way to the next one, the motion re-made from the previous one (feet cleaned, the
// default). Counters: frames re-made (the window with the clean-up's margins) and blended anew.
void BM_SynthPathEdit(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  const MapBlender& b = blender(n, BlendMode::Local);
  motionmap::synth::MapPath path;
  const Data& d = data(n);
  for (int i = 0; i < 100; ++i) {
    path.points.push_back(d.map.row(i * (n / 100)).transpose());
    path.times.push_back(i * 10.0 / 99.0);
  }
  const motionmap::synth::SynthResult previous = motionmap::synth::synthesize(b, path);
  motionmap::synth::MapPath edited = path;
  edited.points[50] += 0.5 * (path.points[51] - path.points[50]);
  int frames = 0, blended = 0;
  for (auto _ : state) {
    const motionmap::synth::PathEditResult e = motionmap::synth::edit_path(b, previous, edited);
    frames = e.end - e.first;
    blended = e.blend_end - e.blend_first;
    benchmark::DoNotOptimize(e.result.motion.num_frames);
  }
  state.counters["frames_remade"] = frames;
  state.counters["frames_blended"] = blended;
  state.counters["frames"] = previous.motion.num_frames;
}
BENCHMARK(BM_SynthPathEdit)->Arg(10000)->Unit(benchmark::kMillisecond);

// The same on real clips: the Bandai Namco proud walk (331 frames, 11 s at 30 fps) and angry
// walk, PCA map of every frame, local blend; a sketch with a control point every 15 frames along
// the proud walk's trajectory, its middle point moved half-way to the angry walk's.
struct BandaiEdit {
  std::vector<motionmap::Clip> clips;
  motionmap::features::FeatureSet set;
  Eigen::MatrixXd map;
  std::unique_ptr<MapBlender> blender;
  motionmap::synth::MapPath path, edited;
  motionmap::synth::SynthResult previous;
};

const BandaiEdit* bandai_edit() {
  static const std::unique_ptr<BandaiEdit> cached = []() -> std::unique_ptr<BandaiEdit> {
    const std::filesystem::path dir = MOTIONMAP_SHARED_DATA;
    const auto proud = dir / "bandai/dataset-1_walk_proud_001.bvh";
    const auto angry = dir / "bandai/dataset-1_walk_angry_001.bvh";
    if (!std::filesystem::exists(proud) || !std::filesystem::exists(angry)) return nullptr;
    auto e = std::make_unique<BandaiEdit>();
    e->clips = {motionmap::io::load_clip(proud.string()), motionmap::io::load_clip(angry.string())};
    e->set = motionmap::features::build_features(e->clips, {});
    motionmap::embed::EmbedOptions eo;
    eo.method = motionmap::embed::Method::Pca;
    e->map = motionmap::embed::embed({&e->set.X, nullptr}, eo).coordinates;
    e->blender = std::make_unique<MapBlender>(e->clips, e->set, e->map);
    std::vector<Eigen::Vector2d> other;
    const double dt = e->clips[0].motion.frame_time;
    for (int i = 0; i < e->set.num_samples(); ++i) {
      const Eigen::Vector2d p = e->map.row(i).transpose();
      if (e->set.clip_of[i] == 1) other.push_back(p);
      if (e->set.clip_of[i] != 0) continue;
      const int f = e->set.frame_of[i];
      if (f % 15 == 0 || f + 1 == e->clips[0].motion.num_frames) {
        e->path.points.push_back(p);
        e->path.times.push_back(f * dt);
      }
    }
    e->previous = motionmap::synth::synthesize(*e->blender, e->path);
    e->edited = e->path;
    const std::size_t mid = e->path.points.size() / 2;
    e->edited.points[mid] += 0.5 * (other[other.size() / 2] - e->path.points[mid]);
    return e;
  }();
  return cached.get();
}

void BM_SynthPathEditBandai(benchmark::State& state) {
  const BandaiEdit* e = bandai_edit();
  if (!e) {
    state.SkipWithError("no Bandai Namco walks under " MOTIONMAP_SHARED_DATA);
    return;
  }
  int frames = 0, blended = 0;
  for (auto _ : state) {
    const motionmap::synth::PathEditResult r =
        motionmap::synth::edit_path(*e->blender, e->previous, e->edited);
    frames = r.end - r.first;
    blended = r.blend_end - r.blend_first;
    benchmark::DoNotOptimize(r.result.motion.num_frames);
  }
  state.counters["frames_remade"] = frames;
  state.counters["frames_blended"] = blended;
  state.counters["frames"] = e->previous.motion.num_frames;
}
BENCHMARK(BM_SynthPathEditBandai)->Unit(benchmark::kMillisecond);

// A full synthesis of that edited path, for comparison.
void BM_SynthPathBandai(benchmark::State& state) {
  const BandaiEdit* e = bandai_edit();
  if (!e) {
    state.SkipWithError("no Bandai Namco walks under " MOTIONMAP_SHARED_DATA);
    return;
  }
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        motionmap::synth::synthesize(*e->blender, e->edited).motion.num_frames);
  }
}
BENCHMARK(BM_SynthPathBandai)->Unit(benchmark::kMillisecond);

}  // namespace
