// Acceptance on real motion capture: map a clip with every embedding method, feed the clip's own
// map trajectory back as a path at its own timing, and compare the synthesized motion with the
// original: joint rotations (RMS, degrees) and root path (largest error, % of the distance
// travelled). The figures are printed for docs/synthesis.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include <gtest/gtest.h>

#include "motionmap/embed/embed.h"
#include "motionmap/features/features.h"
#include "motionmap/features/point_cloud.h"
#include "motionmap/io/bvh.h"
#include "motionmap/io/load.h"
#include "motionmap/skeleton/contacts.h"
#include "motionmap/synth/synthesize.h"
#include "support/test_data.h"

namespace motionmap::synth {
namespace {

struct Figures {
  double rms_degrees = 0.0;   // over every joint of every frame (root: after aligning the start)
  double root_percent = 0.0;  // largest root position error ÷ distance travelled, in %
  double travelled = 0.0;     // distance the original root travelled
};

// Compares original frame f ≥ first with the synthesized frame at the same time (frame
// (f − first)·ratio when the synthesized clip has `ratio` frames per original frame).
Figures compare(const Motion& orig, int first, const Motion& synth, int root) {
  const double h0 = features::heading_angle(orig.rotation(first, root));
  const Eigen::Quaterniond unturn = axis_rotation(Axis::Y, -h0);
  Eigen::Vector3d p0 = orig.translation(first, root);
  p0.y() = 0.0;
  const int ratio = static_cast<int>(std::lround(orig.frame_time / synth.frame_time));
  Figures out;
  double sum2 = 0.0, worst = 0.0;
  long count = 0;
  for (int f = first; f < orig.num_frames; ++f) {
    const int k = (f - first) * ratio;
    if (k >= synth.num_frames) break;
    for (int j = 0; j < orig.num_joints; ++j) {
      const Eigen::Quaterniond q = j == root ? unturn * orig.rotation(f, j) : orig.rotation(f, j);
      const double a = rad_to_deg(rotation_angle(q, synth.rotation(k, j)));
      sum2 += a * a;
      ++count;
    }
    const Eigen::Vector3d expected = unturn * (orig.translation(f, root) - p0);
    worst = std::max(worst, (synth.translation(k, root) - expected).norm());
    if (f > first) {
      Eigen::Vector3d d = orig.translation(f, root) - orig.translation(f - 1, root);
      d.y() = 0.0;
      out.travelled += d.norm();
    }
  }
  out.rms_degrees = std::sqrt(sum2 / static_cast<double>(count));
  out.root_percent = 100.0 * worst / out.travelled;
  return out;
}

// Bounds: rotation RMS (degrees) and root path error (% of the distance travelled); the local
// mode's own, where tighter.
void run_acceptance(const std::string& relative, int stride, double max_rms, double max_root,
                    double local_rms = INFINITY, double local_root = INFINITY) {
  const Clip clip = io::load_bvh(test::shared_file(relative));
  features::FeatureOptions fo;
  fo.stride = stride;
  const features::FeatureSet set = features::build_features(std::span<const Clip>(&clip, 1), fo);
  // The clip's own map trajectory at its own timing (stride > 1: the samples are 1/stride of the
  // frames; the synthesized clip still has every frame, interpolated in the map).
  const int first = set.frame_of.front();
  for (embed::Method method : embed::all_methods()) {
    // gplvm's full model is O(#frames³) per step: the golf swings (≤ 452 samples) retrace on it;
    // the longer walks would take minutes under the sanitizers.
    if (method == embed::Method::Gplvm && set.num_samples() > 500) continue;
    embed::EmbedOptions eo;
    eo.method = method;
    eo.max_iterations = 40;  // gplvm: a map to blend on, not its optimum (and fast under ASan)
    const embed::Embedding map = embed::embed({&set.X, &set.D}, eo);
    MapPath path;
    for (int i = 0; i < set.num_samples(); ++i) {
      path.points.emplace_back(map.coordinates(i, 0), map.coordinates(i, 1));
      path.times.push_back((set.frame_of[i] - first) * clip.motion.frame_time);
    }
    for (BlendMode mode : {BlendMode::Local, BlendMode::Kriging, BlendMode::Idw}) {
      BlendOptions bo;
      bo.mode = mode;
      const MapBlender blender(std::span<const Clip>(&clip, 1), set, map.coordinates, bo);
      // The blend itself: the feet's clean-up would hold them still, away from the clip's.
      SynthOptions so;
      so.clean_feet = false;
      const SynthResult r = synthesize(blender, path, so);
      ASSERT_EQ(r.motion.num_frames, set.frame_of.back() - first + 1);
      const Figures fig = compare(clip.motion, first, r.motion, blender.motion_root());
      std::printf(
          "[ figures  ] %s stride %d  %-6s %-7s  rotation RMS %.3g deg  root path %.3g %% of "
          "%.4g\n",
          relative.c_str(), stride, std::string(embed::method_name(method)).c_str(),
          std::string(blend_mode_name(mode)).c_str(), fig.rms_degrees, fig.root_percent,
          fig.travelled);
      const bool local = mode == BlendMode::Local;
      EXPECT_LT(fig.rms_degrees, local ? std::min(max_rms, local_rms) : max_rms)
          << embed::method_name(method) << " " << blend_mode_name(mode);
      EXPECT_LT(fig.root_percent, local ? std::min(max_root, local_root) : max_root)
          << embed::method_name(method) << " " << blend_mode_name(mode);
    }
  }
}

// The acceptance bounds: every frame is a sample, so retracing must reproduce the clip to < 1°
// RMS and a root path within 2 % of the distance travelled (every mode meets them; the
// figures are ~1e-11° and ~1e-11 %, but for the walks' local blends, whose registered gait
// phases set a pace 0.1–0.2 % off 1: ≤ 0.008°, ≤ 0.09 %).
TEST(SynthAcceptance, GolfSwingRetracedOnEveryMap) {
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
  run_acceptance("cmu/64_08.bvh", 1, 1.0, 2.0);
}

TEST(SynthAcceptance, WalkRetracedOnEveryMap) {
  MOTIONMAP_REQUIRE_SHARED("other/omimo_AV_8Walk_Meredith_HVHA_Rep1.bvh");
  run_acceptance("other/omimo_AV_8Walk_Meredith_HVHA_Rep1.bvh", 1, 1.0, 2.0);
}

TEST(SynthAcceptance, BandaiWalkKeepsItsRootMotionBelowAStaticRoot) {
  MOTIONMAP_REQUIRE_SHARED("other/BandaiNamcoResearchInc_dataset-1_walk_normal_001.bvh");
  run_acceptance("other/BandaiNamcoResearchInc_dataset-1_walk_normal_001.bvh", 1, 1.0, 2.0);
}

// Maps of every other frame: the frames between samples are blends, close but not exact. The
// swing visits each region of its map once. The walk's gait cycles overlap on the map, so a point
// between two samples also draws on the same phase of other cycles (a few degrees different) and
// the root path drifts with their speeds: only loose bounds, but for the local mode, which on the
// trajectory blends the two samples around the point alone (golf 2.0°, 0.87 %; walk 0.17°, 0.13 %:
// what interpolating between a frame's two neighbours costs).
TEST(SynthAcceptance, GolfSwingBetweenSamplesOfAHalfRateMap) {
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
  run_acceptance("cmu/64_08.bvh", 2, 5.0, 15.0, 2.5, 3.0);
}

TEST(SynthAcceptance, WalkBetweenSamplesOfAHalfRateMap) {
  MOTIONMAP_REQUIRE_SHARED("other/omimo_AV_8Walk_Meredith_HVHA_Rep1.bvh");
  run_acceptance("other/omimo_AV_8Walk_Meredith_HVHA_Rep1.bvh", 2, 15.0, 100.0, 0.5, 1.0);
}

// How far a root's direction of travel over the last third of `positions` turns from the first
// third's, in degrees (floor components x, z; Y up).
double turn_degrees(const std::vector<Eigen::Vector3d>& positions) {
  const std::size_t n = positions.size(), third = n / 3;
  const Eigen::Vector3d a = positions[third] - positions[0];
  const Eigen::Vector3d b = positions[n - 1] - positions[n - 1 - third];
  return std::abs(
      rad_to_deg(std::atan2(a.x() * b.z() - a.z() * b.x(), a.x() * b.x() + a.z() * b.z())));
}

// How far `positions` travel over the floor (Y up).
double travelled(const std::vector<Eigen::Vector3d>& positions) {
  double sum = 0.0;
  for (std::size_t k = 1; k < positions.size(); ++k) {
    Eigen::Vector3d d = positions[k] - positions[k - 1];
    d.y() = 0.0;
    sum += d.norm();
  }
  return sum;
}

// Takes sketched through a library, a point every third of a second of their curves (a stroke
// through the take's region, not round each loop: bench/traced_walks.py), play their takes.
// - The walks go as straight as captured. The blend moves its weights between the takes in step
//   with the gait; their pelvises swing a few degrees either way with each step, and integrated,
//   those swings did not cancel: the feminine walk turned 21° (its capture 1°). Blended as a sway
//   about each clip's turning, they turn nothing.
// - No foot stays up longer than a captured step's swing, and the run covers its capture's
//   distance. Along the straight lines between the points, which cut across each loop of the
//   curve, the old walk followed the tired walk at a third of its pace with a foot held up 0.83 s
//   (the capture 0.33 s), and the run became a walk in the middle and covered 1.0 m of the
//   capture's 2.0; each stroke now follows the curve it joins (detail/strokes.h).
TEST(SynthAcceptance, TakesSketchedThroughALibraryPlayTheirTakes) {
  std::vector<Clip> clips;
  for (const char* take :
       {"bow_normal", "bow_old", "dash_normal", "punch_normal", "run_angry", "run_normal",
        "run_old", "walk_angry", "walk_feminine", "walk_old", "walk_tired"}) {
    const std::string name = std::string("bandai/dataset-1_") + take + "_001.bvh";
    MOTIONMAP_REQUIRE_SHARED(name);
    clips.push_back(io::load_clip(test::shared_file(name)));
  }
  const features::FeatureSet set = features::build_features(clips, {});
  embed::EmbedOptions eo;
  eo.method = embed::Method::Isomap;
  const embed::Embedding map = embed::embed({&set.X, &set.D}, eo);
  const MapBlender blender(clips, set, map.coordinates);
  const Skeleton& skeleton = blender.skeleton();
  const Feet feet = find_feet(skeleton);
  for (const auto& [name, c] : {std::pair{"run_normal", 5}, std::pair{"walk_feminine", 8},
                                std::pair{"walk_old", 9}, std::pair{"walk_tired", 10}}) {
    SCOPED_TRACE(name);
    const Motion& capture = clips[static_cast<std::size_t>(c)].motion;
    MapPath path;
    int last = 0;
    for (int i = 0; i < set.num_samples(); ++i) {
      if (set.clip_of[i] != c) continue;
      last = set.frame_of[i];
      if (last % 10 != 0 && last != capture.num_frames - 1) continue;
      path.points.emplace_back(map.coordinates(i, 0), map.coordinates(i, 1));
      path.times.push_back(last * capture.frame_time);
    }
    ASSERT_EQ(last, capture.num_frames - 1);
    const SynthResult r = synthesize(blender, path);
    // The hips (joint 1, below Bandai's joint_Root) in the world.
    const std::vector<Eigen::Vector3d> captured = joint_trajectory(skeleton, capture, 1),
                                       made = joint_trajectory(skeleton, r.motion, 1);
    const LengthUnits units = detect_length_units(skeleton, capture);
    const Skating sc = measure_skating(skeleton, capture, feet, units);
    const Skating sr = measure_skating(skeleton, r.motion, feet, units);
    std::printf(
        "[ figures  ] the %s sketched through 11 Bandai takes: turns %.1f° (its capture %.1f°), "
        "travels %.0f (%.0f), a foot up %.2f s at most (%.2f), skates %.3f cleaned (%.3f)\n",
        name, turn_degrees(made), turn_degrees(captured), travelled(made), travelled(captured),
        sr.longest_raised_s, sc.longest_raised_s, sr.ratio, sc.ratio);
    EXPECT_LT(turn_degrees(made), turn_degrees(captured) + 5.0);
    EXPECT_NEAR(travelled(made), travelled(captured), 0.1 * travelled(captured));
    EXPECT_LE(sr.longest_raised_s, sc.longest_raised_s + 0.1);
    EXPECT_LE(sr.ratio, sc.ratio + 1.0 / sc.transitions + 1e-12);
  }
}

TEST(SynthAcceptance, SynthesizedMotionExportsAsBvh) {
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
  const Clip clip = io::load_bvh(test::shared_file("cmu/64_08.bvh"));
  const features::FeatureSet set = features::build_features(std::span<const Clip>(&clip, 1), {});
  embed::EmbedOptions eo;
  eo.method = embed::Method::Pca;
  const embed::Embedding map = embed::embed({&set.X, nullptr}, eo);
  const MapBlender blender(std::span<const Clip>(&clip, 1), set, map.coordinates);
  // A sketch across the map, drawn at the clip's median map speed.
  MapPath path;
  const Eigen::MatrixXd& c = map.coordinates;
  path.points = {c.row(10).transpose(), c.row(150).transpose(), c.row(300).transpose()};
  const SynthResult r = synthesize(blender, path);
  std::ostringstream text;
  io::write_bvh(io::from_motion(blender.skeleton(), r.motion), text);
  const Motion back = io::to_motion(io::parse_bvh(text.str()));
  ASSERT_EQ(back.num_frames, r.motion.num_frames);
  EXPECT_NEAR(back.frame_time, r.motion.frame_time, 1e-12);
  for (int f = 0; f < back.num_frames; f += 17) {
    for (int j = 0; j < back.num_joints; ++j) {
      EXPECT_LT(rotation_angle(back.rotation(f, j), r.motion.rotation(f, j)), 1e-9)
          << f << " " << j;
    }
    EXPECT_LT((back.translation(f, 0) - r.motion.translation(f, 0)).norm(), 1e-9);
  }
}

}  // namespace
}  // namespace motionmap::synth
