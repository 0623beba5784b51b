// Clips of different skeletons in one map: the joint names they share, how hierarchies differ,
// and build_features() with FeatureOptions::joints = JointSelection::Common.
#include "motionmap/features/joint_match.h"

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/features/features.h"
#include "motionmap/io/load.h"
#include "support/error_message.h"
#include "support/small_clip.h"
#include "support/test_data.h"

namespace motionmap::features {
namespace {

using test::error_message;
using test::smooth_clip;

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// A clip of `skeleton` with smooth, joint-specific rotations and a walking, turning root.
Clip clip_of(Skeleton skeleton, const std::string& path, int frames = 40, double phase = 0.0) {
  Clip clip;
  clip.path = path;
  clip.skeleton = std::move(skeleton);
  const int joints = clip.skeleton.num_joints();
  clip.motion.resize(frames, joints);
  for (int f = 0; f < frames; ++f) {
    const double t = f / 30.0 + phase;
    for (int j = 0; j < joints; ++j) {
      clip.motion.translation(f, j) = clip.skeleton.joints[j].offset;
      clip.motion.rotation(f, j) =
          axis_rotation(static_cast<Axis>(j % 3), 0.2 * std::sin((j + 1) * t));
    }
    clip.motion.translation(f, 0) += Eigen::Vector3d(2 * t, 0, 3 * t);
    clip.motion.rotation(f, 0) = axis_rotation(Axis::Y, 0.4 * t);
  }
  return clip;
}

// The small clip's skeleton (Hips → Spine → {LeftThumb, Head}) under another root, without
// LeftThumb, with a Tail: shared names Hips (a root only in the first), Spine, Head.
Skeleton other_skeleton() {
  Skeleton s;
  s.joints.push_back({"Root", -1, {0, 0, 0}, {}, {}});
  s.joints.push_back({"Hips", 0, {0, 90, 0}, {}, {}});
  s.joints.push_back({"Tail", 1, {0, -5, -5}, {}, {{0, 0, -3}}});
  s.joints.push_back({"Spine", 1, {0, 12, 0}, {}, {}});
  s.joints.push_back({"Head", 3, {0, 9, 0}, {}, {{0, 4, 0}}});
  return s;
}

// Hips → {Head, Spine}: Head hangs from Hips here, from Spine in the small clip.
Skeleton reparented_skeleton() {
  Skeleton s;
  s.joints.push_back({"Hips", -1, {0, 0, 0}, {}, {}});
  s.joints.push_back({"Head", 0, {0, 20, 0}, {}, {{0, 3, 0}}});
  s.joints.push_back({"Spine", 0, {0, 10, 0}, {}, {}});
  s.joints.push_back({"LeftThumb", 2, {5, 5, 0}, {}, {{1, 0, 0}}});
  return s;
}

FeatureOptions common() {
  FeatureOptions opt;
  opt.joints = JointSelection::Common;
  opt.keep_first = true;
  return opt;
}

TEST(JointMatch, CommonNamesFollowTheFirstClipsOrder) {
  const std::vector<Clip> clips{smooth_clip(10, "a.bvh"), clip_of(other_skeleton(), "b.bvh")};
  EXPECT_EQ(common_joint_names(clips), (std::vector<std::string>{"Hips", "Spine", "Head"}));
  const std::vector<Clip> reversed{clips[1], clips[0]};
  EXPECT_EQ(common_joint_names(reversed), (std::vector<std::string>{"Hips", "Spine", "Head"}));
  const std::vector<Clip> one{clips[0]};
  EXPECT_EQ(common_joint_names(one),
            (std::vector<std::string>{"Hips", "Spine", "LeftThumb", "Head"}));
  EXPECT_TRUE(common_joint_names({}).empty());
  Clip upper = clips[1];
  for (auto& j : upper.skeleton.joints) j.name = "X" + j.name;  // names match exactly or not
  const std::vector<Clip> none{clips[0], upper};
  EXPECT_TRUE(common_joint_names(none).empty());
}

TEST(JointMatch, HierarchyDifferenceSaysWhatDiffers) {
  const Clip a = smooth_clip(10, "data/a.bvh");
  EXPECT_EQ(hierarchy_difference(a, smooth_clip(10, "b.bvh")), "");
  EXPECT_EQ(hierarchy_difference(a, clip_of(other_skeleton(), "b.bvh")),
            "it has 5 joints, a.bvh 4; the first that differs is joint 0: 'Root' (a root) where "
            "a.bvh has 'Hips' (a root)");
  EXPECT_EQ(hierarchy_difference(a, clip_of(reparented_skeleton(), "b.bvh")),
            "the first joint that differs is joint 1: 'Head' (parent 'Hips') where a.bvh has "
            "'Spine' (parent 'Hips')");
  Skeleton longer = test::chain_skeleton();
  longer.joints.push_back({"Hat", 3, {0, 2, 0}, {}, {}});
  EXPECT_EQ(hierarchy_difference(a, clip_of(longer, "b.bvh")),
            "it has 5 joints, a.bvh 4; its first 4 are a.bvh's, then comes 'Hat'");
  EXPECT_EQ(hierarchy_difference(clip_of(longer, "b.bvh"), a),
            "it has 4 joints, b.bvh 5; they are b.bvh's first 4, without 'Hat'");
  // Same joints and parents, but an End Site more: the point clouds would not line up.
  Skeleton extra_end = test::chain_skeleton();
  extra_end.joints[1].end_sites.push_back({0, 1, 0});
  EXPECT_FALSE(extra_end.same_hierarchy(test::chain_skeleton()));
  EXPECT_EQ(hierarchy_difference(a, clip_of(extra_end, "b.bvh")),
            "joint 'Spine' has " + std::to_string(extra_end.joints[1].end_sites.size()) +
                " End Site(s) where a.bvh has " +
                std::to_string(test::chain_skeleton().joints[1].end_sites.size()));
}

TEST(JointMatch, DifferentHierarchiesAreAnErrorThatOffersCommonJoints) {
  const std::vector<Clip> clips{smooth_clip(20, "a.bvh"), smooth_clip(20, "b.bvh"),
                                clip_of(other_skeleton(), "takes/c.bvh")};
  const std::string message =
      error_message<ParameterError>([&] { build_features(clips, FeatureOptions{}); });
  EXPECT_EQ(message.rfind("takes/c.bvh: its joint hierarchy differs from a.bvh's (it has 5", 0), 0u)
      << message;
  EXPECT_TRUE(contains(message, "--joints common")) << message;
  EXPECT_TRUE(
      contains(error_message<ParameterError>([&] { select_samples(clips, FeatureOptions{}); }),
               "--joints common"));
}

TEST(JointMatch, CommonJointsOfOneHierarchyGiveTheSameFeatures) {
  std::vector<Clip> clips{smooth_clip(30, "a.bvh"), smooth_clip(25, "b.bvh")};
  clips[1].skeleton.joints[1].offset *= 1.2;
  for (const DistanceKind d : all_distance_kinds()) {
    for (const FeatureKind k : all_feature_kinds()) {
      FeatureOptions all;
      all.distance = d;
      all.features = k;
      FeatureOptions shared = all;
      shared.joints = JointSelection::Common;
      const FeatureSet a = build_features(clips, all);
      const FeatureSet b = build_features(clips, shared);
      EXPECT_TRUE(a.X == b.X) << feature_kind_name(k);
      EXPECT_TRUE(a.D == b.D) << distance_kind_name(d);
      EXPECT_EQ(a.joints, b.joints);
      EXPECT_EQ(a.frame_of, b.frame_of);
      ASSERT_EQ(b.notes.size(), a.notes.size() + 1);
      EXPECT_EQ(b.notes.front(), "joints common: the 2 clips share all 4 joints");
    }
  }
}

TEST(JointMatch, EachClipUsesItsOwnJointsOfTheSharedNames) {
  const std::vector<Clip> clips{smooth_clip(30, "a.bvh"), clip_of(other_skeleton(), "b.bvh")};
  FeatureOptions opt = common();
  opt.distance = DistanceKind::PointCloud;
  const FeatureSet set = build_features(clips, opt, {}, Distances::Later);
  // X: Spine and Head (Hips is a root in a.bvh), each clip's own joints of those names.
  ASSERT_EQ(set.X.cols(), 8);
  EXPECT_EQ(set.joints, (std::vector<int>{1, 3}));
  ASSERT_EQ(set.num_samples(), 70);
  const std::vector<int> frames_b = [] {
    std::vector<int> f(40);
    for (int i = 0; i < 40; ++i) f[i] = i;
    return f;
  }();
  const std::vector<int> joints_b{3, 4};  // Spine, Head in b.bvh
  const Eigen::MatrixXd xb = quaternion_features(clips[1].motion, joints_b, frames_b);
  EXPECT_TRUE(set.X.bottomRows(40) == xb);

  // Point cloud: Hips, Spine, Head and Head's End Site (one in each clip), from each clip's own
  // forward kinematics and motion root; Tail's End Site, LeftThumb and Root are left out.
  ASSERT_EQ(set.distance_input.cols(), 12);
  const RowMatrix cloud_b = heading_local_points(clips[1].skeleton, clips[1].motion);
  const std::vector<int> points_b{1, 3, 4, 6};  // Hips, Spine, Head, Head's End Site
  for (int f = 0; f < 40; ++f) {
    for (std::size_t p = 0; p < points_b.size(); ++p) {
      const auto i = static_cast<Eigen::Index>(p);
      ASSERT_EQ(set.distance_input.row(30 + f).segment<3>(3 * i),
                cloud_b.row(f).segment<3>(3 * points_b[p]))
          << f << " " << p;
    }
  }
  const RowMatrix cloud_a = heading_local_points(clips[0].skeleton, clips[0].motion);
  const std::vector<int> points_a{0, 1, 3, 5};  // Hips, Spine, Head, Head's End Site
  for (std::size_t p = 0; p < points_a.size(); ++p) {
    const auto i = static_cast<Eigen::Index>(p);
    EXPECT_EQ(set.distance_input.row(7).segment<3>(3 * i),
              cloud_a.row(7).segment<3>(3 * points_a[p]));
  }

  ASSERT_FALSE(set.notes.empty());
  const std::string& kept = set.notes.front();
  EXPECT_TRUE(contains(kept,
                       "joints common: 3 joints shared by the 2 clips are kept (2 in X, the "
                       "root Hips only in the point cloud, 1 End Site): Hips, Spine, Head; "
                       "dropped: LeftThumb (a.bvh), Root, Tail (b.bvh)"))
      << kept;
}

TEST(JointMatch, ANoteNamesKeptJointsWhoseParentDiffers) {
  const std::vector<Clip> clips{smooth_clip(30, "a.bvh"),
                                clip_of(reparented_skeleton(), "dir/b.bvh")};
  const FeatureSet set = build_features(clips, common());
  EXPECT_EQ(set.X.cols(), 12);  // Spine, LeftThumb, Head
  std::string all;
  for (const auto& n : set.notes) all += n + "\n";
  EXPECT_TRUE(contains(all, "joints common: the 2 clips share all 4 joints")) << all;
  EXPECT_TRUE(contains(all,
                       "joints common: 1 kept joint has another parent in some clip, so its "
                       "local rotation is measured against another bone there (quaternion "
                       "features, geodesic distance): Head (parent 'Spine' in a.bvh, 'Hips' in "
                       "b.bvh)"))
      << all;
  // With the point cloud alone (positions and point-cloud distance) the note is not needed.
  FeatureOptions positions = common();
  positions.features = FeatureKind::Positions;
  for (const auto& n : build_features(clips, positions).notes)
    EXPECT_FALSE(contains(n, "another parent")) << n;
}

TEST(JointMatch, ExcludeAppliesToTheSharedJoints) {
  const std::vector<Clip> clips{smooth_clip(30, "a.bvh"), clip_of(other_skeleton(), "b.bvh")};
  FeatureOptions opt = common();
  opt.exclude = "He.*";
  const FeatureSet set = build_features(clips, opt, {}, Distances::Later);
  EXPECT_EQ(set.X.cols(), 4);                   // Spine only
  EXPECT_EQ(set.distance_input.cols(), 3 * 2);  // Hips (a root somewhere) and Spine
  opt.exclude = ".*";
  EXPECT_TRUE(contains(error_message<ParameterError>([&] { build_features(clips, opt); }),
                       "leaves no joint"));
}

TEST(JointMatch, ClipsSharingNoJointAreAClearError) {
  Skeleton alien;
  alien.joints.push_back({"base", -1, {0, 0, 0}, {}, {}});
  alien.joints.push_back({"child1", 0, {0, 1, 0}, {}, {{0, 1, 0}}});
  const std::vector<Clip> clips{smooth_clip(20, "a.bvh"), clip_of(alien, "b.bvh")};
  EXPECT_EQ(error_message<ParameterError>([&] { build_features(clips, common()); }),
            "joints common: the clips share no joint name (b.bvh has none of a.bvh's joints, "
            "e.g. 'Hips')");
  // Only a root in common: nothing for X.
  Skeleton rooted;
  rooted.joints.push_back({"Hips", -1, {0, 0, 0}, {}, {}});
  rooted.joints.push_back({"child1", 0, {0, 1, 0}, {}, {{0, 1, 0}}});
  const std::vector<Clip> only_root{smooth_clip(20, "a.bvh"), clip_of(rooted, "b.bvh")};
  EXPECT_EQ(error_message<ParameterError>([&] { build_features(only_root, common()); }),
            "joints common: the clips share only Hips, a root in some clip, which X never uses "
            "(it carries the heading)");
}

TEST(JointMatch, FeatureOptionsNameTheSelection) {
  EXPECT_EQ(joint_selection_name(JointSelection::All), "all");
  EXPECT_EQ(joint_selection_name(JointSelection::Common), "common");
  EXPECT_EQ(parse_joint_selection("common"), JointSelection::Common);
  EXPECT_EQ(parse_joint_selection("Common"), std::nullopt);
  EXPECT_EQ(all_joint_selections().size(), 2u);
  EXPECT_EQ(FeatureOptions{}.joints, JointSelection::All);
}

TEST(JointMatchRealData, CmuGolfAndAnotherSkeletonShareNineteenJoints) {
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
  MOTIONMAP_REQUIRE_SHARED("other/omimo_AV_8Walk_Meredith_HVHA_Rep1.bvh");
  const std::vector<Clip> clips{
      io::load_clip(test::shared_file("cmu/64_08.bvh")),
      io::load_clip(test::shared_file("other/omimo_AV_8Walk_Meredith_HVHA_Rep1.bvh"))};
  const std::string message =
      error_message<ParameterError>([&] { select_samples(clips, FeatureOptions{}); });
  EXPECT_EQ(message.rfind(clips[1].path + ": its joint hierarchy differs from " + clips[0].path +
                              "'s (it has 23 joints, 64_08.bvh 31; the first that differs is "
                              "joint 1: 'Spine' (parent 'Hips') where 64_08.bvh has 'LHipJoint' "
                              "(parent 'Hips'))",
                          0),
            0u)
      << message;
  EXPECT_EQ(common_joint_names(clips).size(), 19u);
  FeatureOptions opt;
  opt.joints = JointSelection::Common;
  const FeatureSet set = build_features(clips, opt, {}, Distances::Later);
  EXPECT_EQ(set.X.cols(), 4 * 18);                     // Hips is the root of both
  EXPECT_EQ(set.distance_input.cols(), 3 * (19 + 3));  // End Sites of the toes and head
  EXPECT_EQ(set.num_samples(), 364 + 1064);            // 64_08's T-pose left out
  std::string all;
  for (const auto& n : set.notes) all += n + "\n";
  EXPECT_TRUE(contains(all, "joints common: 19 joints shared by the 2 clips are kept (18 in X"))
      << all;
  EXPECT_TRUE(contains(all, "6 kept joints have another parent in some clip")) << all;
}

}  // namespace
}  // namespace motionmap::features
