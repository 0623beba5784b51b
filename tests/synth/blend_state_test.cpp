// The blend's arithmetic on its own (synth/blend_state.h): MapBlender::blend is blend_states over
// the samples' sample_state()s, bit for bit, and the functions refuse what they cannot blend.
#include "motionmap/synth/blend_state.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/features/point_cloud.h"
#include "motionmap/io/load.h"
#include "motionmap/skeleton/forward_kinematics.h"
#include "motionmap/synth/blender.h"
#include "support/test_data.h"
#include "synth/synth_fixtures.h"

namespace motionmap::synth {
namespace {

// The walking clip with a spine that stretches a little: joint 1's translation varies, so the
// blend averages it (ClipsSummary::moving = {1}).
Clip stretching_clip() {
  Clip clip = test::walking_clip(80);
  for (int f = 0; f < clip.motion.num_frames; ++f)
    clip.motion.translation(f, 1) = Eigen::Vector3d(0.0, 10.0 + 0.3 * std::sin(0.2 * f), 0.1);
  return clip;
}

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

TEST(SynthBlendState, BlendStatesIsTheBlendersArithmeticBitForBit) {
  const Clip clip = stretching_clip();
  const int n = clip.motion.num_frames;
  const features::FeatureSet set = test::all_frames(n);
  const Eigen::MatrixXd map = test::curve_map(n);
  const ClipsSummary summary = summarize_clips(std::span<const Clip>(&clip, 1), set);
  ASSERT_EQ(summary.moving, std::vector<int>{1});
  // What the blender keeps for the joints it does not average: sample 0's translations.
  std::vector<Eigen::Vector3d> fixed(std::size_t(clip.motion.num_joints));
  for (int j = 0; j < clip.motion.num_joints; ++j)
    fixed[std::size_t(j)] = clip.motion.translation(0, j);
  std::vector<SampleState> states;
  for (int f = 0; f < n; ++f)
    states.push_back(sample_state(clip.motion, f, summary.motion_root, Axis::Y, summary.moving));
  for (const BlendMode mode : {BlendMode::Kriging, BlendMode::Local, BlendMode::Idw}) {
    BlendOptions options;
    options.mode = mode;
    const MapBlender blender(std::span<const Clip>(&clip, 1), set, map, options);
    ASSERT_EQ(blender.motion_root(), summary.motion_root);
    for (const Eigen::Vector2d& p :
         {Eigen::Vector2d(map(30, 0), map(30, 1)), Eigen::Vector2d(2.05, 0.3),
          Eigen::Vector2d(5.51, -0.2), Eigen::Vector2d(40.0, 3.0)}) {
      const MapWeights w = blender.locate(p);
      std::vector<SampleStateView> views;
      for (const int s : w.samples) views.push_back(states[std::size_t(s)].view());
      const BlendedFrame a = blender.blend(w);
      const BlendedFrame b =
          blend_states(views, w.weights, fixed, summary.moving, summary.motion_root, Axis::Y);
      const std::string what = std::string(blend_mode_name(mode)) + " at (" +
                               std::to_string(p.x()) + ", " + std::to_string(p.y()) + ")";
      EXPECT_TRUE(same_bytes(a.rotations, b.rotations)) << what;
      EXPECT_TRUE(same_bytes(a.translations, b.translations)) << what;
      EXPECT_EQ(std::memcmp(a.velocity.data(), b.velocity.data(), sizeof(double) * 3), 0) << what;
      EXPECT_EQ(std::memcmp(&a.yaw_rate, &b.yaw_rate, sizeof(double)), 0) << what;
      EXPECT_EQ(std::memcmp(&a.heading_offset, &b.heading_offset, sizeof(double)), 0) << what;
    }
  }
}

TEST(SynthBlendState, AtOneSampleItIsThatSamplesState) {
  const Clip clip = stretching_clip();
  const std::vector<int> moving = {1};
  const SampleState s = sample_state(clip.motion, 12, 0, Axis::Y, moving);
  ASSERT_TRUE(s.finite());
  ASSERT_EQ(s.rotations.size(), 5u);
  ASSERT_EQ(s.translations.size(), 1u);
  EXPECT_EQ(s.translations[0], clip.motion.translation(12, 1));
  EXPECT_EQ(s.height, clip.motion.translation(12, 0).y());
  std::vector<Eigen::Vector3d> fixed(5, Eigen::Vector3d(7.0, 8.0, 9.0));
  const std::vector<SampleStateView> one = {s.view()};
  const std::vector<double> w = {1.0};
  const BlendedFrame b = blend_states(one, w, fixed, moving, 0, Axis::Y);
  for (int j = 1; j < 5; ++j)
    EXPECT_LE(rotation_angle(b.rotations[std::size_t(j)], s.rotations[std::size_t(j)]), 1e-15);
  EXPECT_EQ(b.translations[1], clip.motion.translation(12, 1));
  EXPECT_EQ(b.translations[2], Eigen::Vector3d(7.0, 8.0, 9.0));  // not averaged: kept
  // The motion root stands at the floor origin at the sample's height.
  EXPECT_EQ(b.translations[0], Eigen::Vector3d(0.0, s.height, 0.0));
  EXPECT_EQ(b.velocity, s.velocity);
  EXPECT_EQ(b.yaw_rate, s.yaw_rate);
  EXPECT_EQ(b.heading_offset, s.heading_offset);
}

TEST(SynthBlendState, AClipsHeadingIsItsTurningPlusItsSway) {
  // A captured walk's pelvis swings either way with each step; a sample's yaw rate is the turning
  // (its clip's heading averaged over a stride), the swing its heading offset. Integrated, the
  // turning plus the sway gives the clip's heading back.
  MOTIONMAP_REQUIRE_SHARED("bandai/dataset-1_walk_feminine_001.bvh");
  const Clip clip =
      io::load_clip(motionmap::test::shared_file("bandai/dataset-1_walk_feminine_001.bvh"));
  const Motion& m = clip.motion;
  const int root = motion_root(clip.skeleton, m);
  const std::vector<int> ancestors = root_ancestors(clip.skeleton, root);
  const double dt = m.frame_time;
  double base = 0.0, heading = 0.0, turning2 = 0.0, raw2 = 0.0, worst = 0.0, widest = 0.0;
  const auto heading_of = [&](int f) {
    return features::heading_angle(root_transform(m, f, root, ancestors).rotation.normalized());
  };
  const SampleState first = sample_state(m, 0, root, Axis::Y, {}, ancestors);
  for (int f = 0; f + 1 < m.num_frames; ++f) {
    const SampleState s = sample_state(m, f, root, Axis::Y, {}, ancestors);
    worst = std::max(worst, std::abs(base + s.heading_offset - first.heading_offset - heading));
    widest = std::max(widest, std::abs(s.heading_offset));
    const double step = wrap_angle(heading_of(f + 1) - heading_of(f));
    raw2 += (step / dt) * (step / dt);
    turning2 += s.yaw_rate * s.yaw_rate;
    base += s.yaw_rate * dt;
    heading += step;
  }
  EXPECT_LE(worst, 1e-9);
  // The sway is a few degrees; the turning changes far less from frame to frame than the heading.
  EXPECT_GT(widest, deg_to_rad(2.0));
  EXPECT_LT(widest, deg_to_rad(15.0));
  const double turning_rms = std::sqrt(turning2 / (m.num_frames - 1));
  const double raw_rms = std::sqrt(raw2 / (m.num_frames - 1));
  std::printf("feminine walk: heading rate RMS %.3f rad/s, turning %.3f; widest sway %.1f°\n",
              raw_rms, turning_rms, rad_to_deg(widest));
  EXPECT_LT(turning_rms, 0.3 * raw_rms);
}

TEST(SynthBlendState, TheSwayReadsNoFramesBeyondTheClipWhateverItsFrameTime) {
  // The turning's window is kTurnSeconds of frames, cut to the clip: a frame time so short that
  // the window would span 5e299 frames (past any integer) reads the clip's own 20 (no overflow, a
  // finite sway), and one so long that it spans none leaves the heading all turning (no sway).
  Clip clip = test::walking_clip(20);
  const std::vector<int> moving;
  clip.motion.frame_time = 1e-300;
  const SampleState fast = sample_state(clip.motion, 10, 0, Axis::Y, moving);
  EXPECT_TRUE(std::isfinite(fast.heading_offset));
  EXPECT_NE(fast.heading_offset, 0.0);  // the walk turns: its frames either side differ
  clip.motion.frame_time = 1e300;
  const SampleState slow = sample_state(clip.motion, 10, 0, Axis::Y, moving);
  EXPECT_EQ(slow.heading_offset, 0.0);
}

TEST(SynthBlendState, ALibraryWhoseClipsMoveDifferentJointsBlendsTheBodysRoot) {
  // Bandai Namco's run_normal carries its travel in joint_Root above the hips, walk_angry in the
  // hips (joint_Root at the origin): the blend folds joint_Root into the hips, so it blends the
  // hips' world transform and never averages the clips' world positions.
  MOTIONMAP_REQUIRE_SHARED("bandai/dataset-1_run_normal_001.bvh");
  MOTIONMAP_REQUIRE_SHARED("bandai/dataset-1_walk_angry_001.bvh");
  const std::vector<Clip> clips{
      io::load_clip(motionmap::test::shared_file("bandai/dataset-1_walk_angry_001.bvh")),
      io::load_clip(motionmap::test::shared_file("bandai/dataset-1_run_normal_001.bvh"))};
  ASSERT_EQ(motion_root(clips[0].skeleton, clips[0].motion), 1);
  ASSERT_EQ(motion_root(clips[1].skeleton, clips[1].motion), 0);
  features::FeatureSet set;
  for (int c = 0; c < 2; ++c) {
    for (int f = 0; f < clips[c].motion.num_frames; ++f) {
      set.clip_of.push_back(c);
      set.frame_of.push_back(f);
    }
  }
  const ClipsSummary summary = summarize_clips(clips, set);
  EXPECT_EQ(summary.motion_root, 1);
  const std::vector<int> ancestors = root_ancestors(clips[0].skeleton, summary.motion_root);
  EXPECT_EQ(ancestors, std::vector<int>{0});
  for (const int j : summary.moving) EXPECT_NE(j, 0);

  // Folding keeps the world: the run's frame folded has the same joint positions from the hips
  // down (joint_Root itself now rests at the origin).
  const int f = 12;  // run_normal has 24 frames
  Motion folded = clips[1].motion;
  fold_root(folded, f, 1, ancestors);
  const WorldPose before = forward_kinematics(clips[1].skeleton, clips[1].motion, f);
  const WorldPose after = forward_kinematics(clips[1].skeleton, folded, f);
  for (std::size_t j = 1; j < before.positions.size(); ++j)
    EXPECT_LE((before.positions[j] - after.positions[j]).norm(), 1e-9) << j;
  for (std::size_t e = 0; e < before.end_sites.size(); ++e)
    EXPECT_LE((before.end_sites[e] - after.end_sites[e]).norm(), 1e-9) << e;
  EXPECT_EQ(folded.translation(f, 0), Eigen::Vector3d::Zero());

  // The run's state moves at the run's speed (the hips' world velocity), the walk's at the walk's.
  const Axis up = Axis::Y;
  for (int c = 0; c < 2; ++c) {
    const Motion& m = clips[c].motion;
    const SampleState s = sample_state(m, f, 1, up, summary.moving, ancestors);
    const WorldPose a = forward_kinematics(clips[c].skeleton, m, f);
    const WorldPose b = forward_kinematics(clips[c].skeleton, m, f + 1);
    Eigen::Vector3d world = (b.positions[1] - a.positions[1]) / m.frame_time;
    world.y() = 0.0;
    EXPECT_NEAR(s.velocity.norm(), world.norm(), 1e-6 * world.norm()) << "clip " << c;
    EXPECT_NEAR(s.height, a.positions[1].y(), 1e-9) << "clip " << c;
    EXPECT_GT(world.norm(), 50.0) << "clip " << c;  // both travel (cm/s)
  }

  // Half the walk, half the run: joint_Root at rest, the hips on the floor origin at the mean
  // height — not half-way between the clips' places in the world.
  const SampleState w = sample_state(clips[0].motion, f, 1, up, summary.moving, ancestors);
  const SampleState r = sample_state(clips[1].motion, f, 1, up, summary.moving, ancestors);
  const std::vector<SampleStateView> views{w.view(), r.view()};
  const std::vector<double> half{0.5, 0.5};
  std::vector<Eigen::Vector3d> fixed(static_cast<std::size_t>(clips[0].motion.num_joints));
  for (int j = 0; j < clips[0].motion.num_joints; ++j) fixed[j] = clips[0].motion.translation(0, j);
  const BlendedFrame blend = blend_states(views, half, fixed, summary.moving, 1, up, ancestors);
  EXPECT_EQ(blend.translations[0], Eigen::Vector3d::Zero());
  EXPECT_TRUE(blend.rotations[0].isApprox(Eigen::Quaterniond::Identity(), 0.0));
  EXPECT_EQ(blend.translations[1].x(), 0.0);
  EXPECT_EQ(blend.translations[1].z(), 0.0);
  EXPECT_NEAR(blend.translations[1].y(), 0.5 * (w.height + r.height), 1e-9);
}

TEST(SynthBlendState, RefusesWhatItCannotBlend) {
  const Clip clip = stretching_clip();
  const std::vector<int> moving = {1};
  EXPECT_THROW(sample_state(clip.motion, 80, 0, Axis::Y, moving), ParameterError);
  EXPECT_THROW(sample_state(clip.motion, -1, 0, Axis::Y, moving), ParameterError);
  EXPECT_THROW(sample_state(clip.motion, 0, 5, Axis::Y, moving), ParameterError);
  EXPECT_THROW(sample_state(clip.motion, 0, 0, Axis::Y, std::vector<int>{5}), ParameterError);
  const SampleState s = sample_state(clip.motion, 3, 0, Axis::Y, moving);
  const std::vector<SampleStateView> two = {s.view(), s.view()};
  const std::vector<Eigen::Vector3d> fixed(5, Eigen::Vector3d::Zero());
  const auto blend = [&](std::vector<double> w, int root = 0, std::vector<int> mv = {1}) {
    return blend_states(two, w, fixed, mv, root, Axis::Y);
  };
  EXPECT_NO_THROW(blend({0.5, 0.5}));
  EXPECT_THROW(blend({1.0}), ParameterError);
  EXPECT_THROW(blend_states({}, {}, fixed, moving, 0, Axis::Y), ParameterError);
  EXPECT_THROW(blend({0.5, std::nan("")}), ParameterError);
  EXPECT_THROW(blend({1.0, -1.0}), ParameterError);
  EXPECT_THROW(blend({0.5, 0.5}, 5), ParameterError);
  EXPECT_THROW(blend({0.5, 0.5}, 0, {-1}), ParameterError);
  // The motion root's ancestors: named, and each a joint.
  EXPECT_THROW(blend_states(two, std::vector<double>{0.5, 0.5}, fixed, moving, 1, Axis::Y,
                            std::vector<int>{7}),
               ParameterError);
  EXPECT_THROW(root_ancestors(clip.skeleton, 5), ParameterError);
  EXPECT_THROW(root_ancestors(clip.skeleton, -1), ParameterError);
  EXPECT_EQ(root_ancestors(clip.skeleton, 0), std::vector<int>{});
  EXPECT_THROW(root_transform(clip.motion, 80, 1, std::vector<int>{0}), ParameterError);
  EXPECT_THROW(root_transform(clip.motion, 0, 1, std::vector<int>{9}), ParameterError);
  Motion m = clip.motion;
  EXPECT_THROW(fold_root(m, 0, 5, std::vector<int>{}), ParameterError);
  EXPECT_THROW(sample_state(clip.motion, 0, 1, Axis::Y, {}, std::vector<int>{-2}), ParameterError);
}

// The clips are summarised on the pool's threads; of several clips it cannot use, the error
// names the first, whichever thread read it.
TEST(SynthBlendState, SummarisingClipsNamesTheFirstClipItCannotUse) {
  std::vector<Clip> clips;
  features::FeatureSet set;
  for (int c = 0; c < 6; ++c) {
    clips.push_back(test::walking_clip(20));
    clips.back().path = "c" + std::to_string(c) + ".bvh";
    for (int f = 0; f < 20; ++f) {
      set.clip_of.push_back(c);
      set.frame_of.push_back(f);
    }
  }
  const auto message = [&] {
    try {
      summarize_clips(clips, set);
    } catch (const ParameterError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NO_THROW(summarize_clips(clips, set));
  // A sample past its clip's end in clips 3 and 5.
  set.frame_of[3 * 20 + 7] = 25;
  set.frame_of[5 * 20 + 1] = 30;
  EXPECT_EQ(message(), "map: sample 67 is frame 25 of c3.bvh, which has 20 frames");
  // Another skeleton in clips 2 and 4.
  clips[2].skeleton.joints[2].name = "Neck";
  clips[4].skeleton.joints[2].name = "Neck";
  EXPECT_EQ(message(),
            "c2.bvh: its joint hierarchy differs from c0.bvh's; clips blended together must share "
            "one");
}

}  // namespace
}  // namespace motionmap::synth
