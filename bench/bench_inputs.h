#pragma once
// The inputs of the benchmarks and of motionmap_compare: real clips from ../shared/data, and the
// built-in procedural swing (src/motionmap/sample/) for sizes the real clips cannot reach.
//
//   const motionmap::bench::Input& in = motionmap::bench::sample_input(2000);  // X, D of 2000
//   frames const motionmap::bench::Input* real = motionmap::bench::real_input(500);   // nullptr:
//   no data
//
// Both go through the library's own pipeline: build_features() gives X (joint-rotation
// quaternions, #frames by 120 for the 31-joint CMU skeleton), P (the heading-local point clouds)
// and D (point-cloud distances, the Euclidean distances of P's rows).
//
// Real clips: CMU subject 64's golf swings 64_08 and 64_09 (one skeleton; their leading T-poses
// left out by build_features) hold 816 frames together, so real inputs exist up to that size (the
// first F rows of the two clips concatenated). Repeating clips to go further would add exact
// duplicate frames, whose k-NN ties make the graph methods a different, degenerate problem, so
// larger sizes use the sample swing instead: one swing of F frames at 120 fps (its choreography
// stretches to fill the clip; tiny smooth noise keeps every frame distinct).
#include <algorithm>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "motionmap/features/features.h"
#include "motionmap/io/load.h"
#include "motionmap/sample/sample_clip.h"

namespace motionmap::bench {

/// The neighbours per frame every benchmark and comparison uses (the library's default).
inline constexpr int kNeighbours = 20;

/// A benchmark input: the feature matrix X, the point clouds P and the pose distances D of
/// `frames` frames.
struct Input {
  std::string source;  ///< "sample:swing", or the clips' file names joined by '+'
  Eigen::MatrixXd X;   ///< #frames by 4·#joints: rotation quaternions (the default features)
  /// #frames by 3·#points: heading-local joint and end-site positions (FeatureKind::Positions);
  /// D is exactly the Euclidean distances of P's rows.
  Eigen::MatrixXd P;
  Eigen::MatrixXd D;  ///< #frames by #frames: point-cloud distances (the default distance)
  int frames() const { return static_cast<int>(X.rows()); }
};

/// The shared data folder (../shared/data beside the repository, set by CMake).
inline std::filesystem::path shared_data() {
  return MOTIONMAP_SHARED_DATA;
}

/// The CMU subject 64 swings used as real input, in order; empty when the data is absent.
inline std::vector<std::string> real_clip_paths() {
  std::vector<std::string> paths;
  for (const char* name : {"cmu/64_08.bvh", "cmu/64_09.bvh"}) {
    const std::filesystem::path p = shared_data() / name;
    if (!std::filesystem::exists(p)) return {};
    paths.push_back(p.string());
  }
  return paths;
}

/// Loads clips (they must share one joint hierarchy).
inline std::vector<Clip> load_clips(const std::vector<std::string>& paths) {
  std::vector<Clip> clips;
  for (const std::string& p : paths) clips.push_back(io::load_clip(p));
  return clips;
}

/// The sample swing of `frames` frames at 120 fps.
inline Clip sample_clip(int frames) {
  sample::SampleOptions options;
  options.seconds = frames / options.fps;
  return sample::make_sample_clip(sample::SampleKind::Swing, options);
}

/// X, P and D of `clips` by the library's defaults (quaternions, point-cloud distance), cut to
/// the first `frames` rows when `frames` > 0.
inline Input make_input(const std::vector<Clip>& clips, int frames = 0) {
  Input in;
  for (const Clip& c : clips) {
    if (!in.source.empty()) in.source += "+";
    in.source += c.path.substr(c.path.find_last_of('/') + 1);
  }
  // One build_features call with positions as X gives P and D; the quaternions of the same
  // samples are what the default call's X would be.
  features::FeatureOptions options;
  options.features = features::FeatureKind::Positions;
  features::FeatureSet set = features::build_features(clips, options);
  const int n = frames > 0 ? std::min(frames, set.num_samples()) : set.num_samples();
  in.X.resize(n, 4 * static_cast<Eigen::Index>(set.joints.size()));
  for (int r = 0; r < n;) {
    const int clip = set.clip_of[r];
    std::vector<int> rows;
    for (; r < n && set.clip_of[r] == clip; ++r) rows.push_back(set.frame_of[r]);
    in.X.middleRows(r - static_cast<int>(rows.size()), static_cast<Eigen::Index>(rows.size())) =
        features::quaternion_features(clips[clip].motion, set.joints, rows);
  }
  if (n < set.num_samples()) {
    in.P = set.X.topRows(n);
    in.D = set.D.topLeftCorner(n, n);
  } else {
    in.P = std::move(set.X);
    in.D = std::move(set.D);
  }
  return in;
}

/// The sample swing's input of `frames` frames, built once per size and kept (D at 8000 frames
/// is 512 MB).
inline const Input& sample_input(int frames) {
  static std::map<int, std::unique_ptr<Input>> cache;
  auto& slot = cache[frames];
  if (!slot) slot = std::make_unique<Input>(make_input({sample_clip(frames)}));
  return *slot;
}

/// The first `frames` frames of the real clips, built once per size; nullptr when the data is
/// absent or holds fewer frames.
inline const Input* real_input(int frames) {
  static std::map<int, std::unique_ptr<Input>> cache;
  auto& slot = cache[frames];
  if (!slot) {
    const std::vector<std::string> paths = real_clip_paths();
    if (paths.empty()) return nullptr;
    slot = std::make_unique<Input>(make_input(load_clips(paths), frames));
  }
  return slot->frames() == frames ? slot.get() : nullptr;
}

}  // namespace motionmap::bench
