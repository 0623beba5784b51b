// Posing by dragging a joint (synth/reach.h): on real maps, a target taken from a frame of the map
// (its own joint position, in its own placement) is reached within 1 % of the body's height; a
// held-out take's frames are reached at least as well as by the best single sample (the errors
// are printed); pins hold their joints; an unreachable target gives the best valid point; bad
// joints, targets and options are clear errors. A synthetic map checks a warm-started drag.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/core/stats.h"
#include "motionmap/embed/embed.h"
#include "motionmap/features/features.h"
#include "motionmap/io/bvh.h"
#include "motionmap/skeleton/forward_kinematics.h"
#include "motionmap/synth/reach.h"
#include "support/test_data.h"
#include "synth/synth_fixtures.h"

namespace motionmap::synth {
namespace {

struct RealMap {
  std::vector<Clip> clips;
  features::FeatureSet set;
  Eigen::MatrixXd coords;
  std::unique_ptr<MapBlender> blender;
  std::unique_ptr<Reacher> reacher;
};

// An isomap of `files` (default features and options), a local blender and a Reacher over it.
std::unique_ptr<RealMap> make_map(const std::vector<std::string>& files) {
  auto map = std::make_unique<RealMap>();
  for (const std::string& f : files)
    map->clips.push_back(io::load_bvh(motionmap::test::shared_file(f)));
  map->set = features::build_features(map->clips, {});
  embed::EmbedOptions eo;
  eo.method = embed::Method::Isomap;
  map->coords = embed::embed({&map->set.X, &map->set.D}, eo).coordinates;
  map->blender = std::make_unique<MapBlender>(map->clips, map->set, map->coords);
  map->reacher = std::make_unique<Reacher>(*map->blender);
  return map;
}

bool have(const std::vector<std::string>& files) {
  return std::all_of(files.begin(), files.end(), [](const std::string& f) {
    return std::filesystem::exists(motionmap::test::shared_file(f));
  });
}

const std::vector<std::string> kBandaiMap = {
    "bandai/dataset-1_walk_old_001.bvh",   "bandai/dataset-1_walk_proud_001.bvh",
    "bandai/dataset-1_walk_angry_001.bvh", "bandai/dataset-1_run_old_001.bvh",
    "bandai/dataset-1_bow_normal_001.bvh", "bandai/dataset-1_punch_normal_001.bvh"};
const std::string kBandaiHeldOut = "bandai/dataset-1_walk_tired_001.bvh";

// Built once: the tests below share it.
const RealMap* bandai() {
  static std::unique_ptr<RealMap> map = have(kBandaiMap) ? make_map(kBandaiMap) : nullptr;
  return map.get();
}

#define REQUIRE_BANDAI()                                        \
  do {                                                          \
    if (bandai() == nullptr || !have({kBandaiHeldOut}))         \
      GTEST_SKIP() << "shared Bandai Namco clips absent under " \
                   << motionmap::test::shared_file("bandai");   \
  } while (0)

// The goal of putting `joint` where it is in frame `frame` of `clip`, in that frame's own
// placement.
ReachGoal own_position(const MapBlender& blender, const Clip& clip, int frame, int joint) {
  ReachGoal goal;
  goal.joint = joint;
  goal.placement = root_placement(clip.motion, frame, blender.motion_root(), blender.options().up);
  goal.target = forward_kinematics(clip.skeleton, clip.motion, frame).positions[std::size_t(joint)];
  return goal;
}

std::vector<int> limbs(const Skeleton& skeleton) {
  std::vector<int> out;
  for (const char* name : {"Hand_L", "Foot_R", "Head", "LeftHand", "RightFoot"}) {
    if (const int j = skeleton.find(name); j >= 0) out.push_back(j);
  }
  return out;
}

// Every 20th sample of the map, each limb: within 1 % of the height (they are the samples' own
// positions, so the search should find those samples).
void expect_map_frames_reached(const RealMap& map, const char* label) {
  const Reacher& reacher = *map.reacher;
  const std::vector<int> joints = limbs(map.blender->skeleton());
  ASSERT_FALSE(joints.empty());
  double worst = 0.0;
  int count = 0;
  for (int i = 0; i < map.set.num_samples(); i += 20) {
    const Clip& clip = map.clips[std::size_t(map.set.clip_of[std::size_t(i)])];
    for (const int j : joints) {
      const ReachGoal goal = own_position(*map.blender, clip, map.set.frame_of[std::size_t(i)], j);
      const ReachResult r = reacher.reach(goal);
      EXPECT_LE(r.error_fraction, 0.01) << "sample " << i << " joint " << j;
      EXPECT_FALSE(r.validity.clamped);
      EXPECT_NEAR(r.error, (r.reached - goal.target).norm(), 1e-9 * r.height);
      worst = std::max(worst, r.error_fraction);
      ++count;
    }
  }
  std::printf(
      "[ figures  ] reach: %s: %d targets from the map's own frames, worst error %.3g %% of the "
      "height %.4g\n",
      label, count, 100 * worst, reacher.height());
}

TEST(SynthReach, TargetsFromTheMapsOwnFramesAreReachedBandai) {
  REQUIRE_BANDAI();
  expect_map_frames_reached(*bandai(), "Bandai (6 clips)");
}

TEST(SynthReach, TargetsFromTheMapsOwnFramesAreReachedCmu) {
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
  const auto map = make_map({"cmu/64_08.bvh"});
  expect_map_frames_reached(*map, "CMU 64_08");
}

// A take the map does not hold: not every pose is a blend of the map's, so the error is what it
// is (printed); the search never does worse than the best sample's own pose.
void held_out(const RealMap& map, const Clip& other, const char* label) {
  const MapBlender& blender = *map.blender;
  const std::vector<int> joints = limbs(blender.skeleton());
  std::vector<double> errors;
  WorldPose world;
  for (int f = 1; f < other.motion.num_frames; f += 15) {
    for (const int j : joints) {
      const ReachGoal goal = own_position(blender, other, f, j);
      const ReachResult r = map.reacher->reach(goal);
      double best_sample = std::numeric_limits<double>::infinity();
      for (int i = 0; i < blender.num_samples(); ++i) {
        forward_kinematics(blender.skeleton(),
                           blender.pose(MapWeights::of_sample(i), goal.placement).pose(0), world);
        best_sample = std::min(best_sample, (world.positions[std::size_t(j)] - goal.target).norm());
      }
      EXPECT_LE(r.error, best_sample + 1e-6 * r.height) << "frame " << f << " joint " << j;
      EXPECT_FALSE(r.validity.clamped);
      errors.push_back(100 * r.error_fraction);
    }
  }
  ASSERT_FALSE(errors.empty());
  std::printf(
      "[ figures  ] reach: %s: %zu held-out targets, error median %.3g %%, max %.3g %% of the "
      "height\n",
      label, errors.size(), median(errors), *std::max_element(errors.begin(), errors.end()));
}

TEST(SynthReach, HeldOutTakeIsReachedAtLeastAsWellAsByTheBestSampleBandai) {
  REQUIRE_BANDAI();
  held_out(*bandai(), io::load_bvh(motionmap::test::shared_file(kBandaiHeldOut)),
           "Bandai walk_tired");
}

TEST(SynthReach, HeldOutTakeIsReachedAtLeastAsWellAsByTheBestSampleCmu) {
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
  MOTIONMAP_REQUIRE_SHARED("cmu/64_09.bvh");
  const auto map = make_map({"cmu/64_08.bvh"});
  held_out(*map, io::load_bvh(motionmap::test::shared_file("cmu/64_09.bvh")),
           "CMU 64_09 on 64_08's map");
}

TEST(SynthReach, PinnedJointMovesLessThanWithoutThePin) {
  REQUIRE_BANDAI();
  const RealMap& map = *bandai();
  const Skeleton& skeleton = map.blender->skeleton();
  const int hand = find_joint(skeleton, "Hand_L"), foot = find_joint(skeleton, "Foot_R");
  double with_pin = 0.0, without_pin = 0.0;
  int better = 0, trials = 0;
  for (int i = 5; i < map.set.num_samples(); i += 97) {
    const Clip& clip = map.clips[std::size_t(map.set.clip_of[std::size_t(i)])];
    const int frame = map.set.frame_of[std::size_t(i)];
    // Drag the hand 20 % of the height forward and up from where it is in this frame.
    ReachGoal goal = own_position(*map.blender, clip, frame, hand);
    const double h = map.reacher->height();
    goal.target += Eigen::Vector3d(0.1 * h, 0.15 * h, 0.1 * h);
    goal.start = map.blender->sample_point(i);
    const Eigen::Vector3d foot_at =
        forward_kinematics(clip.skeleton, clip.motion, frame).positions[std::size_t(foot)];
    const ReachResult free = map.reacher->reach(goal);
    const double moved =
        (forward_kinematics(skeleton, free.pose, 0).positions[std::size_t(foot)] - foot_at).norm();
    goal.pins.push_back({foot, foot_at, 4.0});
    const ReachResult pinned = map.reacher->reach(goal);
    ASSERT_EQ(pinned.pin_errors.size(), 1u);
    with_pin += pinned.pin_errors[0];
    without_pin += moved;
    better += pinned.pin_errors[0] <= moved + 1e-9 * h ? 1 : 0;
    ++trials;
  }
  std::printf(
      "[ figures  ] reach: pins: the pinned foot moved %.3g %% of the height on average with its "
      "pin, "
      "%.3g %% without (%d of %d trials no worse)\n",
      100 * with_pin / trials / map.reacher->height(),
      100 * without_pin / trials / map.reacher->height(), better, trials);
  EXPECT_LT(with_pin, 0.5 * without_pin);
  EXPECT_GE(better, trials * 3 / 4);
}

TEST(SynthReach, UnreachableTargetGivesTheBestValidPoint) {
  REQUIRE_BANDAI();
  const RealMap& map = *bandai();
  const double h = map.reacher->height();
  ReachGoal goal;
  goal.joint = find_joint(map.blender->skeleton(), "Hand_R");
  goal.target = Eigen::Vector3d(0.0, 10 * h, 0.0);
  goal.start = Eigen::Vector2d(1e6, -1e6);  // far outside the data too
  const ReachResult r = map.reacher->reach(goal);
  EXPECT_TRUE(std::isfinite(r.error));
  EXPECT_GE(r.error, 8 * h);
  EXPECT_LE(r.validity.distance, map.blender->reach_distance() * (1 + 1e-9));
  EXPECT_EQ(r.point, r.validity.point);
  // The hand is as high as the map's poses hold it: no sample's own pose gets it higher.
  double highest = -std::numeric_limits<double>::infinity();
  for (int i = 0; i < map.blender->num_samples(); ++i) {
    const Motion pose = map.blender->pose(MapWeights::of_sample(i));
    highest = std::max(highest, forward_kinematics(map.blender->skeleton(), pose, 0)
                                    .positions[std::size_t(goal.joint)]
                                    .y());
  }
  EXPECT_GE(r.reached.y(), highest - 0.05 * h);
}

TEST(SynthReach, BadJointNamesTargetsAndOptionsAreClearErrors) {
  const Clip clip = test::walking_clip(60, 30.0);
  const MapBlender blender(std::span<const Clip>(&clip, 1), test::all_frames(60),
                           test::curve_map(60));
  const Reacher reacher(blender);
  EXPECT_EQ(find_joint(blender.skeleton(), "LeftArm"), 3);
  EXPECT_EQ(find_joint(blender.skeleton(), "leftarm"), 3);  // case ignored when unique
  try {
    find_joint(blender.skeleton(), "LeftArn");
    FAIL() << "no error for an unknown joint";
  } catch (const ParameterError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("'LeftArn'"), std::string::npos) << what;
    EXPECT_NE(what.find("did you mean LeftArm?"), std::string::npos) << what;
    EXPECT_NE(what.find("Hips, Spine, Head, LeftArm, RightArm"), std::string::npos) << what;
  }
  Skeleton bandai_like = blender.skeleton();
  bandai_like.joints[3].name = "Arm_L";
  try {
    find_joint(bandai_like, "LeftArm");
    FAIL() << "no error for an unknown joint";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean Arm_L?"), std::string::npos) << e.what();
  }
  ReachGoal goal;
  goal.joint = 2;
  goal.target = Eigen::Vector3d(0.0, std::nan(""), 0.0);
  EXPECT_THROW(reacher.reach(goal), ParameterError);
  goal.target = Eigen::Vector3d(0.0, 100.0, 0.0);
  goal.joint = 5;
  EXPECT_THROW(reacher.reach(goal), ParameterError);
  goal.joint = 2;
  goal.pins.push_back({1, Eigen::Vector3d::Zero(), -1.0});
  EXPECT_THROW(reacher.reach(goal), ParameterError);
  goal.pins.clear();
  goal.start = Eigen::Vector2d(std::numeric_limits<double>::infinity(), 0.0);
  EXPECT_THROW(reacher.reach(goal), ParameterError);
  goal.start.reset();
  ReachOptions options;
  options.max_evaluations = 2;
  try {
    reacher.reach(goal, options);
    FAIL() << "no error for max_evaluations = 2";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("max_evaluations = 2"), std::string::npos) << e.what();
  }
}

TEST(SynthReach, SetUpAndSearchAreCancellable) {
  const Clip clip = test::walking_clip(60, 30.0);
  const MapBlender blender(std::span<const Clip>(&clip, 1), test::all_frames(60),
                           test::curve_map(60));
  const Control cancel({}, [] { return true; });
  EXPECT_THROW(Reacher(blender, cancel), Cancelled);
  const Reacher reacher(blender);
  ReachGoal goal;
  goal.joint = 2;
  goal.target = Eigen::Vector3d(0.0, 100.0, 0.0);
  EXPECT_THROW(reacher.reach(goal, {}, cancel), Cancelled);
  EXPECT_NO_THROW(reacher.reach(goal));
}

// A drag on a synthetic map: targets are poses blended at points along the map, so each is
// reachable exactly; every step starts from the previous answer and moves the map point along.
TEST(SynthReach, WarmStartedDragFollowsTheTarget) {
  const Clip clip = test::walking_clip(80, 30.0);
  const Eigen::MatrixXd coords = test::curve_map(80);
  const MapBlender blender(std::span<const Clip>(&clip, 1), test::all_frames(80), coords);
  const Reacher reacher(blender);
  const int hand = find_joint(blender.skeleton(), "LeftArm");
  ReachGoal goal;
  goal.joint = hand;
  goal.placement = root_placement(clip.motion, 30, blender.motion_root());
  std::optional<Eigen::Vector2d> previous;
  int kept = 0;
  for (int step = 0; step <= 20; ++step) {
    const Eigen::Vector2d along =
        coords.row(30).transpose() + (step / 20.0) * (coords.row(34) - coords.row(30)).transpose();
    const Motion target_pose = blender.pose(blender.locate(along), goal.placement);
    goal.target =
        forward_kinematics(blender.skeleton(), target_pose, 0).positions[std::size_t(hand)];
    goal.start = previous;
    const ReachResult r = reacher.reach(goal);
    EXPECT_LE(r.error_fraction, 1e-3) << "step " << step;
    if (previous) {
      EXPECT_LT((r.point - *previous).norm(), 2 * blender.median_step()) << "step " << step;
      kept += r.from_start ? 1 : 0;
    }
    EXPECT_LE(r.evaluations, ReachOptions{}.max_evaluations);
    previous = r.point;
  }
  EXPECT_GE(kept, 18);
}

}  // namespace
}  // namespace motionmap::synth
