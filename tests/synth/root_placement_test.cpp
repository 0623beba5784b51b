// A blended pose placed at a frame's heading and floor position (what a viewer shows while the
// user drags over a map): the root turned and moved exactly, everything else as pose(weights).
#include <cmath>
#include <span>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/features/point_cloud.h"
#include "motionmap/synth/blender.h"
#include "synth/synth_fixtures.h"

namespace motionmap::synth {
namespace {

using test::all_frames;
using test::curve_map;
using test::walking_clip;

TEST(SynthRootPlacement, PlacedPoseHasTheFramesHeadingAndFloorPosition) {
  const Clip clip = walking_clip(80, 30.0);
  const Eigen::MatrixXd map = curve_map(80);
  const MapBlender blender(std::span<const Clip>(&clip, 1), all_frames(80), map);
  const int root = blender.motion_root();
  for (const int frame : {0, 17, 79}) {
    const RootPlacement at = root_placement(clip.motion, frame, root, Axis::Y);
    EXPECT_NEAR(at.floor.y(), 0.0, 0.0);
    EXPECT_NEAR(at.floor.x(), clip.motion.translation(frame, root).x(), 1e-12);
    // Inside the data, on a sample, and far off the trajectory (moved to its edge).
    for (const Eigen::Vector2d& p : {Eigen::Vector2d(map(40, 0), map(40, 1)),
                                     Eigen::Vector2d(3.3, 0.2), Eigen::Vector2d(50.0, -40.0)}) {
      const MapWeights w = blender.locate(p);
      const Motion plain = blender.pose(w);
      const Motion placed = blender.pose(w, at);
      const Eigen::Quaterniond q = placed.rotation(0, root);
      EXPECT_NEAR(std::remainder(features::heading_angle(q, Axis::Y) - at.heading, 2 * M_PI), 0.0,
                  1e-9);
      EXPECT_NEAR(placed.translation(0, root).x(), at.floor.x(), 1e-12);
      EXPECT_NEAR(placed.translation(0, root).z(), at.floor.z(), 1e-12);
      // Height, tilt and every other joint: the plain blend's.
      EXPECT_DOUBLE_EQ(placed.translation(0, root).y(), plain.translation(0, root).y());
      const Eigen::Quaterniond tilt =
          axis_rotation(Axis::Y, -at.heading) * q;  // the heading taken off again
      EXPECT_LT(rotation_angle(tilt, plain.rotation(0, root)), 1e-9);
      for (int j = 0; j < placed.num_joints; ++j) {
        if (j == root) continue;
        EXPECT_EQ(placed.rotation(0, j).coeffs(), plain.rotation(0, j).coeffs());
        EXPECT_EQ(placed.translation(0, j), plain.translation(0, j));
      }
    }
  }
}

TEST(SynthRootPlacement, ZeroPlacementIsThePlainPose) {
  const Clip clip = walking_clip(40, 30.0);
  const MapBlender blender(std::span<const Clip>(&clip, 1), all_frames(40), curve_map(40));
  const MapWeights w = blender.locate({1.05, 0.3});
  const Motion plain = blender.pose(w);
  const Motion placed = blender.pose(w, RootPlacement{});
  for (int j = 0; j < plain.num_joints; ++j) {
    EXPECT_LT(rotation_angle(placed.rotation(0, j), plain.rotation(0, j)), 1e-12);
    EXPECT_EQ(placed.translation(0, j), plain.translation(0, j));
  }
}

TEST(SynthRootPlacement, BadArgumentsAreRefused) {
  const Clip clip = walking_clip(20, 30.0);
  EXPECT_THROW(root_placement(clip.motion, 20, 0), ParameterError);
  EXPECT_THROW(root_placement(clip.motion, 0, 5), ParameterError);
  const MapBlender blender(std::span<const Clip>(&clip, 1), all_frames(20), curve_map(20));
  RootPlacement bad;
  bad.heading = NAN;
  EXPECT_THROW(blender.pose(blender.locate({0.5, 0.1}), bad), ParameterError);
  Motion pose = blender.pose(blender.locate({0.5, 0.1}));
  EXPECT_THROW(place_root(pose, 5, RootPlacement{}), ParameterError);
  EXPECT_THROW(place_root(pose, -1, RootPlacement{}), ParameterError);
}

}  // namespace
}  // namespace motionmap::synth
