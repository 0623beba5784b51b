// Reaching (synth/reach.h): drag steps on a 10 000-frame map of real motion. The clip is the
// synthetic library's (bench/library: CMU's clips from ../shared/data time-warped, mirrored, noised
// and chained, seed 1), mapped with PCA (the default quaternion features), blended locally.
//
//   build/bench/motionmap_bench --benchmark_filter='SynthReach'
//
// SynthReachDrag: one iteration is one step of a drag of the left hand (two paths, below), each
// step started from the previous answer (ReachGoal::start), as MotionMap Studio's 3-D drag calls
// it. Counters: the median and largest step time, wall and thread CPU (ms), the mean evaluations
// and error (% of the height). SynthReachCold: a target from a random frame's own hand position,
// no start. SynthReachSetup: the Reacher's set-up (every sample's pose blended once).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <ctime>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <Eigen/Geometry>

#include "bench_inputs.h"
#include "motionmap/core/stats.h"
#include "motionmap/embed/embed.h"
#include "motionmap/skeleton/forward_kinematics.h"
#include "motionmap/synth/reach.h"
#include "synthetic_library.h"

namespace {

using motionmap::synth::MapBlender;
using motionmap::synth::Reacher;

constexpr int kFrames = 10000;

struct ReachData {
  motionmap::Clip clip;
  motionmap::features::FeatureSet set;
  Eigen::MatrixXd map;
  std::unique_ptr<MapBlender> blender;
  std::unique_ptr<Reacher> reacher;
  int hand = 0;
};

// Built once; nullptr without the shared CMU clips.
const ReachData* reach_data() {
  static std::unique_ptr<ReachData> data;
  static bool tried = false;
  if (tried) return data.get();
  tried = true;
  const std::filesystem::path dir = motionmap::bench::shared_data() / "cmu";
  if (!std::filesystem::is_directory(dir)) return nullptr;
  std::vector<std::string> notes;
  const auto sources = motionmap::bench::load_sources(dir.string(), &notes);
  motionmap::bench::LibraryOptions options;
  options.frames = kFrames;
  options.clip_frames = kFrames;
  auto d = std::make_unique<ReachData>();
  d->clip = motionmap::bench::make_clip(sources, options, 0, kFrames).clip;
  d->clip.path = "library-clip-0";
  motionmap::features::FeatureOptions fo;
  fo.keep_first = true;
  d->set = motionmap::features::build_features(std::span<const motionmap::Clip>(&d->clip, 1), fo,
                                               {}, motionmap::features::Distances::Later);
  motionmap::embed::EmbedOptions eo;
  eo.method = motionmap::embed::Method::Pca;
  d->map = motionmap::embed::embed({&d->set.X, nullptr}, eo).coordinates;
  d->blender =
      std::make_unique<MapBlender>(std::span<const motionmap::Clip>(&d->clip, 1), d->set, d->map);
  d->reacher = std::make_unique<Reacher>(*d->blender);
  d->hand = motionmap::synth::find_joint(d->blender->skeleton(), "LeftHand");
  data = std::move(d);
  return data.get();
}

double thread_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

// Wall and CPU time of one reach, and what it found.
struct Steps {
  std::vector<double> wall, cpu;
  double evaluations = 0.0, error_percent = 0.0;

  motionmap::synth::ReachResult time(const Reacher& reacher,
                                     const motionmap::synth::ReachGoal& goal) {
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = thread_cpu_ms();
    motionmap::synth::ReachResult r = reacher.reach(goal);
    cpu.push_back(thread_cpu_ms() - cpu_start);
    wall.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count());
    evaluations += r.evaluations;
    error_percent += 100.0 * r.error_fraction;
    return r;
  }

  // Counters (ms, and the error in % of the height: read "1.2m" as 0.0012 %).
  void report(benchmark::State& state) const {
    const double steps = static_cast<double>(wall.size());
    state.counters["median_ms"] = motionmap::median(wall);
    state.counters["max_ms"] = *std::max_element(wall.begin(), wall.end());
    state.counters["cpu_median_ms"] = motionmap::median(cpu);
    state.counters["cpu_max_ms"] = *std::max_element(cpu.begin(), cpu.end());
    state.counters["evaluations"] = evaluations / steps;
    state.counters["error_%"] = error_percent / steps;
  }
};

// Arg 0: the hand follows its own path of 1 s (frames 2000–2120, every second frame), seen from
// the body (each frame's hand position relative to its root placement, put in frame 2000's):
// reachable targets. Arg 1: a loop of radius 0.15 × height around the hand (60 steps of 1.6 %),
// partly out of reach. Both warm-started, each step from the previous answer.
void BM_SynthReachDrag(benchmark::State& state) {
  const ReachData* d = reach_data();
  if (d == nullptr) {
    state.SkipWithError("shared CMU clips absent");
    return;
  }
  const motionmap::Clip& clip = d->clip;
  const int root = d->blender->motion_root();
  const auto placement = [&](int frame) {
    return motionmap::synth::root_placement(clip.motion, frame, root);
  };
  const auto hand_at = [&](int frame) {
    return motionmap::forward_kinematics(clip.skeleton, clip.motion, frame)
        .positions[std::size_t(d->hand)];
  };
  // The placed frame of `p` as a rigid map (turn about Y, then move along the floor).
  const auto frame_of = [](const motionmap::synth::RootPlacement& p) {
    Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
    t.linear() = motionmap::axis_rotation(motionmap::Axis::Y, p.heading).toRotationMatrix();
    t.translation() = Eigen::Vector3d(p.floor.x(), 0.0, p.floor.z());
    return t;
  };
  constexpr int kFirst = 2000;
  std::vector<Eigen::Vector3d> targets;
  const Eigen::Isometry3d body = frame_of(placement(kFirst));
  const double h = d->reacher->height();
  for (int k = 0; k < 60; ++k) {
    if (state.range(0) == 0) {
      const int f = kFirst + 2 * k;
      targets.push_back(body * (frame_of(placement(f)).inverse() * hand_at(f)));
    } else {
      const double a = 2.0 * M_PI * k / 60.0;
      targets.push_back(hand_at(kFirst) +
                        0.15 * h *
                            Eigen::Vector3d(std::sin(a), 1.0 - std::cos(a), 0.5 * std::sin(a)));
    }
  }
  motionmap::synth::ReachGoal goal;
  goal.joint = d->hand;
  goal.placement = placement(kFirst);
  goal.start = d->blender->sample_point(kFirst);
  Steps steps;
  std::size_t step = 0;
  for (auto _ : state) {
    goal.target = targets[step++ % targets.size()];
    goal.start = steps.time(*d->reacher, goal).point;
  }
  steps.report(state);
}
BENCHMARK(BM_SynthReachDrag)->Arg(0)->Arg(1)->Iterations(600)->Unit(benchmark::kMillisecond);

void BM_SynthReachCold(benchmark::State& state) {
  const ReachData* d = reach_data();
  if (d == nullptr) {
    state.SkipWithError("shared CMU clips absent");
    return;
  }
  Steps steps;
  std::uint64_t i = 0;
  for (auto _ : state) {
    const int sample = static_cast<int>((7919 * ++i) % std::uint64_t(d->set.num_samples()));
    const int frame = d->set.frame_of[std::size_t(sample)];
    motionmap::synth::ReachGoal goal;
    goal.joint = d->hand;
    goal.placement =
        motionmap::synth::root_placement(d->clip.motion, frame, d->blender->motion_root());
    goal.target = motionmap::forward_kinematics(d->clip.skeleton, d->clip.motion, frame)
                      .positions[std::size_t(d->hand)];
    steps.time(*d->reacher, goal);
  }
  steps.report(state);
}
BENCHMARK(BM_SynthReachCold)->Iterations(200)->Unit(benchmark::kMillisecond);

void BM_SynthReachSetup(benchmark::State& state) {
  const ReachData* d = reach_data();
  if (d == nullptr) {
    state.SkipWithError("shared CMU clips absent");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(Reacher(*d->blender).num_candidates());
}
BENCHMARK(BM_SynthReachSetup)->Unit(benchmark::kMillisecond);

}  // namespace
