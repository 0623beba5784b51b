// Synthesized clips are not mistaken for clips that start with a bind pose (issue #23 part 4):
// `motionmap info` warns of a leading bind pose, and `motionmap map` drops it, when frame 0 is far
// from frame 1 compared with the clip's steps. A sketch that leaves the data is blended at its
// edge, where the pose hardly changes, so most of such a clip stands nearly still while its
// first frames, still inside the data, move as the data does.
#include <cstdio>

#include <gtest/gtest.h>

#include "motionmap/embed/embed.h"
#include "motionmap/features/diagnostics.h"
#include "motionmap/features/features.h"
#include "motionmap/features/point_cloud.h"
#include "motionmap/io/load.h"
#include "motionmap/synth/synthesize.h"
#include "support/test_data.h"

namespace motionmap::synth {
namespace {

struct ClipSet {
  std::string name;
  std::vector<std::string> files;
};

void check_set(const ClipSet& c) {
  std::vector<Clip> clips;
  for (const auto& f : c.files) {
    if (!std::filesystem::exists(motionmap::test::shared_file(f)))
      GTEST_SKIP() << "shared data file absent: " << motionmap::test::shared_file(f);
    clips.push_back(io::load_clip(motionmap::test::shared_file(f)));
  }
  const features::FeatureSet set = features::build_features(clips, {});
  embed::EmbedOptions eo;  // isomap, as `motionmap map` and Studio by default
  const Eigen::MatrixXd map = embed::embed({&set.X, &set.D}, eo).coordinates;
  const MapBlender blender(clips, set, map);
  const double r = blender.reach_distance();
  // The map's leftmost sample: paths start there.
  Eigen::Index start = 0;
  map.col(0).minCoeff(&start);
  const Eigen::Vector2d p0 = map.row(start).transpose();
  std::vector<std::pair<std::string, MapPath>> paths;
  // The first clip's own trajectory at its own timing.
  MapPath own;
  for (int i = 0; i < set.num_samples(); ++i) {
    if (set.clip_of[i] != 0) continue;
    own.points.push_back(map.row(i).transpose());
    own.times.push_back(set.frame_of[i] * clips[0].motion.frame_time);
  }
  paths.emplace_back("own trajectory", own);
  // Out of the data at the data's own speed, then slowly on far outside it (the frames held at
  // its edge: the clip stands nearly still after its first frames).
  MapPath out;
  out.points = {p0, p0 + Eigen::Vector2d(-2 * r, 0), p0 + Eigen::Vector2d(-30 * r, r)};
  out.times = {0.0, 2 * r / blender.median_speed(), 2 * r / blender.median_speed() + 6.0};
  paths.emplace_back("leaving the data", out);
  // Sketched across the map at the default speed, untimed.
  Eigen::Index end = 0;
  map.col(0).maxCoeff(&end);
  MapPath across;
  across.points = {p0, 0.5 * (p0 + map.row(end).transpose()) + Eigen::Vector2d(0, 3 * r),
                   map.row(end).transpose()};
  paths.emplace_back("across", across);
  for (const bool clean : {true, false}) {
    for (const auto& [name, path] : paths) {
      SCOPED_TRACE(c.name + ", " + name + (clean ? "" : ", feet not cleaned"));
      SynthOptions options;
      options.clean_feet = clean;
      const SynthResult s = synthesize(blender, path, options);
      const features::BindPoseCheck check = features::check_leading_bind_pose(
          features::heading_local_points(blender.skeleton(), s.motion, blender.options().up));
      std::printf(
          "[ figures  ] %s, %s%s: %d frames (%d outside the data), frame 0→1 %.3g = %.3g× the "
          "median step, %.3g× the next steps\n",
          c.name.c_str(), name.c_str(), clean ? "" : " (feet not cleaned)", s.motion.num_frames,
          s.clamped_frames, check.distance, check.ratio, check.local_ratio);
      EXPECT_FALSE(check.detected);
      EXPECT_TRUE(features::clip_warnings(blender.skeleton(), s.motion).empty() ||
                  features::clip_warnings(blender.skeleton(), s.motion)[0].find("bind pose") ==
                      std::string::npos);
    }
  }
}

TEST(SynthBindPose, CmuGolfSwing) {
  check_set({"CMU 64_08", {"cmu/64_08.bvh"}});
}
TEST(SynthBindPose, CmuGolfSwings) {
  check_set({"CMU 64_08 + 64_09", {"cmu/64_08.bvh", "cmu/64_09.bvh"}});
}
TEST(SynthBindPose, CmuRun) {
  check_set({"CMU 02_03", {"cmu/02_03.bvh"}});
}
TEST(SynthBindPose, BandaiWalksAndRuns) {
  check_set({"Bandai walks and runs",
             {"bandai/dataset-1_walk_angry_001.bvh", "bandai/dataset-1_walk_proud_001.bvh",
              "bandai/dataset-1_run_normal_001.bvh", "bandai/dataset-1_run_angry_001.bvh"}});
}

// A real bind pose is still found: CMU's clips start with one.
TEST(SynthBindPose, CmuBindPosesStillFound) {
  for (const char* file : {"cmu/64_08.bvh", "cmu/64_09.bvh", "cmu/02_03.bvh"}) {
    MOTIONMAP_REQUIRE_SHARED(file);
    const Clip clip = io::load_clip(motionmap::test::shared_file(file));
    const features::BindPoseCheck check = features::check_leading_bind_pose(
        features::heading_local_points(clip.skeleton, clip.motion));
    std::printf("[ figures  ] %s: frame 0→1 %.3g× the median step, %.3g× the next steps\n", file,
                check.ratio, check.local_ratio);
    EXPECT_TRUE(check.detected) << file;
  }
}

}  // namespace
}  // namespace motionmap::synth
