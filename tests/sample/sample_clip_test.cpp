#include "motionmap/sample/sample_clip.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/io/bvh.h"
#include "motionmap/skeleton/forward_kinematics.h"
#include "support/error_message.h"
#include "support/test_data.h"

namespace motionmap::sample {
namespace {

using Eigen::Vector3d;

// World positions of every joint, for every frame.
std::vector<std::vector<Vector3d>> joint_positions(const Clip& clip) {
  std::vector<std::vector<Vector3d>> out;
  WorldPose world;
  for (int f = 0; f < clip.motion.num_frames; ++f) {
    forward_kinematics(clip.skeleton, clip.motion.pose(f), world);
    out.push_back(world.positions);
  }
  return out;
}

int joint(const Clip& clip, const char* name) {
  const int j = clip.skeleton.find(name);
  EXPECT_GE(j, 0) << name;
  return j;
}

// Largest rotation of any joint between consecutive frames, and largest change of that per-frame
// rotation between consecutive frame pairs (a kink detector), degrees.
struct Smoothness {
  double max_step = 0.0;
  double max_step_change = 0.0;
};

Smoothness smoothness(const Motion& m) {
  Smoothness s;
  for (int f = 1; f < m.num_frames; ++f) {
    for (int j = 0; j < m.num_joints; ++j) {
      s.max_step =
          std::max(s.max_step, rad_to_deg(rotation_angle(m.rotation(f - 1, j), m.rotation(f, j))));
      if (f >= 2) {
        const Eigen::Quaterniond d1 = m.rotation(f - 2, j).conjugate() * m.rotation(f - 1, j);
        const Eigen::Quaterniond d2 = m.rotation(f - 1, j).conjugate() * m.rotation(f, j);
        s.max_step_change = std::max(s.max_step_change, rad_to_deg(rotation_angle(d1, d2)));
      }
    }
  }
  return s;
}

std::string parameter_error(SampleKind kind, double fps, double seconds) {
  return test::error_message<ParameterError>([&] { make_sample_clip(kind, {fps, seconds}); });
}

// The 31 joints of CMU's BVH conversions (64_08.bvh), in file order, with their parents.
struct NamedJoint {
  const char* name;
  const char* parent;
};
constexpr NamedJoint kCmuJoints[] = {
    {"Hips", ""},
    {"LHipJoint", "Hips"},
    {"LeftUpLeg", "LHipJoint"},
    {"LeftLeg", "LeftUpLeg"},
    {"LeftFoot", "LeftLeg"},
    {"LeftToeBase", "LeftFoot"},
    {"RHipJoint", "Hips"},
    {"RightUpLeg", "RHipJoint"},
    {"RightLeg", "RightUpLeg"},
    {"RightFoot", "RightLeg"},
    {"RightToeBase", "RightFoot"},
    {"LowerBack", "Hips"},
    {"Spine", "LowerBack"},
    {"Spine1", "Spine"},
    {"Neck", "Spine1"},
    {"Neck1", "Neck"},
    {"Head", "Neck1"},
    {"LeftShoulder", "Spine1"},
    {"LeftArm", "LeftShoulder"},
    {"LeftForeArm", "LeftArm"},
    {"LeftHand", "LeftForeArm"},
    {"LeftFingerBase", "LeftHand"},
    {"LeftHandIndex1", "LeftFingerBase"},
    {"LThumb", "LeftHand"},
    {"RightShoulder", "Spine1"},
    {"RightArm", "RightShoulder"},
    {"RightForeArm", "RightArm"},
    {"RightHand", "RightForeArm"},
    {"RightFingerBase", "RightHand"},
    {"RightHandIndex1", "RightFingerBase"},
    {"RThumb", "RightHand"},
};

// --- names ------------------------------------------------------------------------------------

TEST(SampleKindTest, NamesRoundTripAndUnknownNamesAreRejected) {
  EXPECT_EQ(sample_kind_name(SampleKind::Swing), "swing");
  EXPECT_EQ(sample_kind_name(SampleKind::Walk), "walk");
  EXPECT_EQ(parse_sample_kind("swing"), SampleKind::Swing);
  EXPECT_EQ(parse_sample_kind("walk"), SampleKind::Walk);
  EXPECT_EQ(parse_sample_kind("Swing"), SampleKind::Swing);
  EXPECT_EQ(parse_sample_kind("WALK"), SampleKind::Walk);
  EXPECT_EQ(parse_sample_kind(""), std::nullopt);
  EXPECT_EQ(parse_sample_kind("run"), std::nullopt);
  EXPECT_EQ(parse_sample_kind("swing "), std::nullopt);
  EXPECT_EQ(parse_sample_kind(std::string_view("walk\0", 5)), std::nullopt);
}

// --- skeleton ---------------------------------------------------------------------------------

TEST(CmuLikeSkeletonTest, HasCmuJointNamesParentsChannelsAndEndSites) {
  const Skeleton s = cmu_like_skeleton();
  ASSERT_EQ(s.num_joints(), 31);
  EXPECT_NO_THROW(s.validate());
  for (int j = 0; j < 31; ++j) {
    EXPECT_EQ(s.joints[j].name, kCmuJoints[j].name) << j;
    const std::string parent = s.joints[j].parent < 0 ? "" : s.joints[s.joints[j].parent].name;
    EXPECT_EQ(parent, kCmuJoints[j].parent) << kCmuJoints[j].name;
  }
  using C = ChannelType;
  EXPECT_EQ(s.joints[0].channels, (std::vector<C>{C::Xposition, C::Yposition, C::Zposition,
                                                  C::Zrotation, C::Yrotation, C::Xrotation}));
  for (int j = 1; j < 31; ++j) {
    EXPECT_EQ(s.joints[j].channels, (std::vector<C>{C::Zrotation, C::Yrotation, C::Xrotation}))
        << s.joints[j].name;
  }
  EXPECT_EQ(s.num_channels(), 6 + 30 * 3);
  std::vector<std::string> with_end_site;
  for (const Joint& j : s.joints) {
    if (!j.end_sites.empty()) with_end_site.push_back(j.name);
    EXPECT_LE(j.end_sites.size(), 1u);
  }
  EXPECT_EQ(with_end_site,
            (std::vector<std::string>{"LeftToeBase", "RightToeBase", "Head", "LeftHandIndex1",
                                      "LThumb", "RightHandIndex1", "RThumb"}));
}

TEST(CmuLikeSkeletonTest, MatchesTheHierarchyOfCmu64_08) {
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
  const io::BvhDocument cmu = io::read_bvh(test::shared_file("cmu/64_08.bvh"));
  const Skeleton s = cmu_like_skeleton();
  ASSERT_TRUE(s.same_hierarchy(cmu.skeleton));
  for (int j = 0; j < s.num_joints(); ++j) {
    EXPECT_EQ(s.joints[j].channels, cmu.skeleton.joints[j].channels) << s.joints[j].name;
    EXPECT_EQ(s.joints[j].end_sites.size(), cmu.skeleton.joints[j].end_sites.size())
        << s.joints[j].name;
    // Zero offsets (CMU's "joints" that only re-orient) are zero here too; the root differs on
    // purpose (ours stands on the floor at rest, CMU's rest pose is centred on the hips).
    if (j > 0) {
      EXPECT_EQ(s.joints[j].offset.isZero(), cmu.skeleton.joints[j].offset.isZero())
          << s.joints[j].name;
    }
  }
}

TEST(CmuLikeSkeletonTest, RestPoseIsAnAdultStandingOnTheFloorInCentimetres) {
  const Skeleton s = cmu_like_skeleton();
  Motion rest;
  rest.resize(1, s.num_joints());
  for (int j = 0; j < s.num_joints(); ++j) rest.translation(0, j) = s.joints[j].offset;
  const WorldPose w = forward_kinematics(s, rest, 0);
  EXPECT_NEAR(w.positions[s.find("Hips")].y(), 95.0, 1e-12);
  double lowest = 1e9, highest = -1e9;
  for (const auto& p : w.positions) lowest = std::min(lowest, p.y());
  for (const auto& p : w.end_sites) {
    lowest = std::min(lowest, p.y());
    highest = std::max(highest, p.y());
  }
  EXPECT_GE(lowest, 0.0);
  EXPECT_LE(lowest, 3.0);  // the balls of the feet
  EXPECT_GT(highest, 165.0);
  EXPECT_LT(highest, 180.0);  // the top of the head
  // Facing +Z: toes ahead of the ankles; the left side on +X; left and right mirror each other.
  EXPECT_GT(w.positions[s.find("LeftToeBase")].z(), w.positions[s.find("LeftFoot")].z() + 5.0);
  EXPECT_GT(w.positions[s.find("LeftUpLeg")].x(), 5.0);
  for (const Joint& j : s.joints) {
    std::string mirror;
    if (j.name.rfind("Left", 0) == 0) mirror = "Right" + j.name.substr(4);
    if (j.name == "LHipJoint" || j.name == "LThumb") mirror = "R" + j.name.substr(1);
    if (mirror.empty()) continue;
    const int m = s.find(mirror);
    ASSERT_GE(m, 0) << mirror;
    EXPECT_TRUE(
        s.joints[m].offset.isApprox(Vector3d(-j.offset.x(), j.offset.y(), j.offset.z()), 1e-12) ||
        (j.offset.isZero() && s.joints[m].offset.isZero()))
        << j.name;
  }
  // Arms straight out along ±X (a T-pose); upper arm + forearm ≈ 58 cm.
  const Vector3d arm = w.positions[s.find("LeftHand")] - w.positions[s.find("LeftArm")];
  EXPECT_NEAR(arm.x(), 58.0, 1e-9);
  EXPECT_NEAR(arm.y(), 0.0, 1e-9);
}

// --- clip shape and options -------------------------------------------------------------------

TEST(SampleClipTest, FrameCountIsRoundedSecondsTimesFps) {
  for (SampleKind kind : {SampleKind::Swing, SampleKind::Walk}) {
    const Clip natural = make_sample_clip(kind);
    EXPECT_EQ(natural.motion.num_frames, 480);
    EXPECT_EQ(natural.motion.num_joints, 31);
    EXPECT_DOUBLE_EQ(natural.motion.frame_time, 1.0 / 120.0);
    EXPECT_EQ(natural.path, "sample:" + std::string(sample_kind_name(kind)));
    EXPECT_TRUE(natural.warnings.empty());
    EXPECT_TRUE(natural.skeleton.same_hierarchy(cmu_like_skeleton()));
    EXPECT_EQ(natural.motion.rotations.size(), 480u * 31u);
    EXPECT_EQ(natural.motion.translations.size(), 480u * 31u);

    EXPECT_EQ(make_sample_clip(kind, {60.0, 2.5}).motion.num_frames, 150);
    EXPECT_EQ(make_sample_clip(kind, {30.0, 0.0}).motion.num_frames, 120);
    EXPECT_EQ(make_sample_clip(kind, {120.0, 1.0 / 120.0}).motion.num_frames, 1);
    EXPECT_EQ(make_sample_clip(kind, {29.97, 1.0}).motion.num_frames, 30);     // 29.97 → 30
    EXPECT_EQ(make_sample_clip(kind, {120.0, 0.1042}).motion.num_frames, 13);  // 12.504 → 13
    EXPECT_DOUBLE_EQ(make_sample_clip(kind, {24.0, 1.0}).motion.frame_time, 1.0 / 24.0);
  }
}

TEST(SampleClipTest, IsDeterministic) {
  for (SampleKind kind : {SampleKind::Swing, SampleKind::Walk}) {
    const Clip a = make_sample_clip(kind), b = make_sample_clip(kind);
    ASSERT_EQ(a.motion.rotations.size(), b.motion.rotations.size());
    for (std::size_t i = 0; i < a.motion.rotations.size(); ++i) {
      ASSERT_EQ(a.motion.rotations[i].coeffs(), b.motion.rotations[i].coeffs()) << i;
      ASSERT_EQ(a.motion.translations[i], b.motion.translations[i]) << i;
    }
  }
}

TEST(SampleClipTest, RotationsAreUnitAndNonRootTranslationsAreTheOffsets) {
  for (SampleKind kind : {SampleKind::Swing, SampleKind::Walk}) {
    const Clip c = make_sample_clip(kind);
    for (int f = 0; f < c.motion.num_frames; ++f) {
      for (int j = 0; j < 31; ++j) {
        ASSERT_NEAR(c.motion.rotation(f, j).norm(), 1.0, 1e-12) << f << " " << j;
        ASSERT_TRUE(c.motion.translation(f, j).allFinite());
        if (j > 0) {
          ASSERT_EQ(c.motion.translation(f, j), c.skeleton.joints[j].offset);
        }
        // Consecutive quaternions share a hemisphere (no sign flips for consumers).
        if (f > 0) {
          ASSERT_GE(c.motion.rotation(f, j).dot(c.motion.rotation(f - 1, j)), 0.0);
        }
      }
    }
  }
}

TEST(SampleClipTest, IsSmoothAt120Fps) {
  for (SampleKind kind : {SampleKind::Swing, SampleKind::Walk}) {
    SCOPED_TRACE(std::string(sample_kind_name(kind)));
    const Clip c = make_sample_clip(kind);
    const Smoothness s = smoothness(c.motion);
    EXPECT_LT(s.max_step, 5.0);         // < 600°/s for every joint, even in the downswing
    EXPECT_LT(s.max_step_change, 3.0);  // no kinks: the angular velocity changes gradually
    const auto p = joint_positions(c);
    double max_move = 0.0;
    for (std::size_t f = 1; f < p.size(); ++f) {
      for (int j = 0; j < 31; ++j) max_move = std::max(max_move, (p[f][j] - p[f - 1][j]).norm());
    }
    EXPECT_LT(max_move, 7.0);  // cm per frame: < 8.4 m/s
    EXPECT_GT(max_move, 1.0);  // and it does move
  }
}

TEST(SampleClipTest, LongerSwingIsTheSameSwingSlower) {
  const Clip natural = make_sample_clip(SampleKind::Swing);
  const Clip slow = make_sample_clip(SampleKind::Swing, {120.0, 8.0});
  ASSERT_EQ(slow.motion.num_frames, 960);
  for (int f = 0; f < natural.motion.num_frames; f += 7) {
    for (int j = 0; j < 31; ++j) {
      EXPECT_LT(rotation_angle(natural.motion.rotation(f, j), slow.motion.rotation(2 * f, j)),
                1e-9);
    }
  }
  EXPECT_LT(smoothness(slow.motion).max_step, 2.5);
}

TEST(SampleClipTest, LowerFrameRateSamplesTheSameWalk) {
  const Clip at120 = make_sample_clip(SampleKind::Walk);
  const Clip at60 = make_sample_clip(SampleKind::Walk, {60.0, 0.0});
  ASSERT_EQ(at60.motion.num_frames, 240);
  for (int f = 0; f < at60.motion.num_frames; f += 5) {
    for (int j = 0; j < 31; ++j) {
      EXPECT_LT(rotation_angle(at60.motion.rotation(f, j), at120.motion.rotation(2 * f, j)), 1e-9);
    }
    EXPECT_LT((at60.motion.translation(f, 0) - at120.motion.translation(2 * f, 0)).norm(), 1e-9);
  }
}

// --- swing ------------------------------------------------------------------------------------

// One clip of `kKind` and its joints' world positions, built once per suite.
template <SampleKind kKind>
class ClipFixture : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    s_clip = new Clip(make_sample_clip(kKind));
    s_pos = new std::vector<std::vector<Vector3d>>(joint_positions(*s_clip));
  }
  static void TearDownTestSuite() {
    delete s_clip;
    delete s_pos;
    s_clip = nullptr;
    s_pos = nullptr;
  }
  static Vector3d at(int frame, const char* name) { return (*s_pos)[frame][joint(*s_clip, name)]; }
  static int frame_at(double seconds) { return static_cast<int>(std::lround(seconds * 120.0)); }

  static inline Clip* s_clip = nullptr;
  static inline std::vector<std::vector<Vector3d>>* s_pos = nullptr;
};

using SwingTest = ClipFixture<SampleKind::Swing>;
using WalkTest = ClipFixture<SampleKind::Walk>;

TEST_F(SwingTest, HandsStayTogetherOnTheClub) {
  double max_gap = 0.0, min_gap = 1e9;
  for (int f = 0; f < s_clip->motion.num_frames; ++f) {
    const double gap = (at(f, "LeftHand") - at(f, "RightHand")).norm();
    max_gap = std::max(max_gap, gap);
    min_gap = std::min(min_gap, gap);
  }
  EXPECT_LT(max_gap, 10.0);
  EXPECT_GT(min_gap, 6.0);
}

TEST_F(SwingTest, HandsAreLowAtAddressAndImpactAndAboveTheShouldersAtTopAndFinish) {
  auto hands = [](int f) -> Vector3d { return 0.5 * (at(f, "LeftHand") + at(f, "RightHand")); };
  auto shoulders_top = [](int f) { return std::max(at(f, "LeftArm").y(), at(f, "RightArm").y()); };
  for (double t : {0.0, 0.5, 2.30}) {  // address, impact: hands below the hips, in front
    const int f = frame_at(t);
    EXPECT_LT(hands(f).y(), at(f, "Hips").y()) << t;
    EXPECT_GT(hands(f).z(), at(f, "Hips").z() + 20.0) << t;
  }
  for (double t : {1.80, 1.90, 3.02, 3.9}) {  // top of the backswing, finish
    const int f = frame_at(t);
    EXPECT_GT(hands(f).y(), shoulders_top(f) + 5.0) << t;
  }
  // At the top the hands are on the trail side (−X), at the finish on the target side (+X).
  EXPECT_LT(hands(frame_at(1.85)).x(), at(frame_at(1.85), "Hips").x() - 20.0);
  EXPECT_GT(hands(frame_at(2.45)).x(), at(frame_at(2.45), "Hips").x() + 20.0);
}

TEST_F(SwingTest, ShouldersTurnAboutNinetyDegreesAwayThenPastTheTarget) {
  // Heading of the shoulder line (right → left shoulder) projected on the floor, degrees.
  auto heading = [](int f) {
    const Vector3d d = at(f, "LeftArm") - at(f, "RightArm");
    return rad_to_deg(std::atan2(-d.z(), d.x()));  // 0: square to the target line, > 0: open
  };
  const double address = heading(0);
  EXPECT_NEAR(address, 0.0, 10.0);
  const double top = heading(frame_at(1.85));
  EXPECT_LT(top - address, -75.0);
  EXPECT_GT(top - address, -110.0);
  EXPECT_GT(heading(frame_at(3.5)) - address, 90.0);  // the chest faces the target at the finish
}

TEST_F(SwingTest, FeetStayPlantedAndTheBodyStaysInPlace) {
  const int frames = s_clip->motion.num_frames;
  for (const char* name : {"LeftFoot", "LeftToeBase", "RightToeBase"}) {
    double drift = 0.0;
    for (int f = 0; f < frames; ++f) drift = std::max(drift, (at(f, name) - at(0, name)).norm());
    EXPECT_LT(drift, 0.5) << name;
    EXPECT_GE(at(0, name).y(), 0.0) << name;
    EXPECT_LE(at(0, name).y(), 10.0) << name;
  }
  // The trail heel comes up in the finish (the foot rolls onto its ball), and only then.
  EXPECT_NEAR(at(frame_at(2.0), "RightFoot").y(), at(0, "RightFoot").y(), 0.5);
  EXPECT_GT(at(frame_at(3.5), "RightFoot").y(), at(0, "RightFoot").y() + 5.0);
  // The pelvis shifts weight a few centimetres, no more.
  double shift = 0.0;
  for (int f = 0; f < frames; ++f) shift = std::max(shift, (at(f, "Hips") - at(0, "Hips")).norm());
  EXPECT_GT(shift, 3.0);
  EXPECT_LT(shift, 15.0);
}

TEST_F(SwingTest, DownswingIsFasterThanBackswingAndNoTwoFramesAreIdentical) {
  auto hand_speed = [](int f) {  // cm per frame
    return (at(f, "LeftHand") - at(f - 1, "LeftHand")).norm();
  };
  double back = 0.0, down = 0.0;
  for (int f = frame_at(0.6); f < frame_at(1.8); ++f) back = std::max(back, hand_speed(f));
  for (int f = frame_at(1.95); f < frame_at(2.3); ++f) down = std::max(down, hand_speed(f));
  EXPECT_GT(down, 2.0 * back);
  // Even during address and the final hold, frames differ (tiny natural variation).
  const Motion& m = s_clip->motion;
  for (int f = 1; f < m.num_frames; ++f) {
    double diff = 0.0;
    for (int j = 0; j < 31; ++j) {
      diff = std::max(diff, rotation_angle(m.rotation(f, j), m.rotation(f - 1, j)));
    }
    ASSERT_GT(diff, 1e-6) << f;
  }
}

// --- walk -------------------------------------------------------------------------------------

TEST_F(WalkTest, RootAdvancesAlongZAtWalkingSpeed) {
  const Motion& m = s_clip->motion;
  const Vector3d first = m.translation(0, 0), last = m.translation(m.num_frames - 1, 0);
  const double seconds = (m.num_frames - 1) * m.frame_time;
  EXPECT_NEAR((last.z() - first.z()) / seconds, 130.0, 2.0);  // cm/s
  double min_y = 1e9, max_y = -1e9, max_x = 0.0;
  for (int f = 0; f < m.num_frames; ++f) {
    min_y = std::min(min_y, m.translation(f, 0).y());
    max_y = std::max(max_y, m.translation(f, 0).y());
    max_x = std::max(max_x, std::abs(m.translation(f, 0).x()));
    if (f > 0) {
      ASSERT_GT(m.translation(f, 0).z(), m.translation(f - 1, 0).z());
    }
  }
  EXPECT_GT(max_y - min_y, 2.0);  // the pelvis bobs…
  EXPECT_LT(max_y - min_y, 7.0);
  EXPECT_GT(min_y, 85.0);
  EXPECT_LT(max_y, 96.0);
  EXPECT_LT(max_x, 4.0);  // …and sways a little
}

TEST_F(WalkTest, PoseRepeatsEveryCycle) {
  const Motion& m = s_clip->motion;
  for (int f = 0; f + 120 < m.num_frames; ++f) {
    for (int j = 0; j < 31; ++j) {
      ASSERT_LT(rotation_angle(m.rotation(f, j), m.rotation(f + 120, j)), 1e-9) << f << " " << j;
    }
    const Vector3d step = m.translation(f + 120, 0) - m.translation(f, 0);
    ASSERT_LT((step - Vector3d(0.0, 0.0, 130.0)).norm(), 1e-9) << f;
  }
  // …but not every half cycle: left and right alternate.
  EXPECT_GT(rotation_angle(m.rotation(0, joint(*s_clip, "LeftLeg")),
                           m.rotation(60, joint(*s_clip, "LeftLeg"))),
            deg_to_rad(10.0));
}

TEST_F(WalkTest, FeetAlternateAndDoNotSlide) {
  const int frames = s_clip->motion.num_frames;
  int both_moving = 0, left_planted = 0, right_planted = 0, lead_changes = 0;
  for (int f = 1; f < frames; ++f) {
    const Vector3d l = at(f, "LeftToeBase"), r = at(f, "RightToeBase");
    const bool lp = (l - at(f - 1, "LeftToeBase")).norm() < 1e-6;
    const bool rp = (r - at(f - 1, "RightToeBase")).norm() < 1e-6;
    left_planted += lp;
    right_planted += rp;
    both_moving += !lp && !rp;
    // A planted ball of the foot is on the floor.
    if (lp) {
      EXPECT_NEAR(l.y(), 2.0, 1e-6) << f;
    }
    if (rp) {
      EXPECT_NEAR(r.y(), 2.0, 1e-6) << f;
    }
    const double lead = l.z() - r.z(),
                 previous = at(f - 1, "LeftToeBase").z() - at(f - 1, "RightToeBase").z();
    lead_changes += (lead > 0) != (previous > 0);
  }
  EXPECT_EQ(both_moving, 0);  // always one foot on the ground
  EXPECT_NEAR(left_planted, 0.5 * frames, 0.06 * frames);
  EXPECT_NEAR(right_planted, 0.5 * frames, 0.06 * frames);
  EXPECT_NEAR(lead_changes, 8, 1);  // two steps per 1 s cycle
  // The swing foot clears the floor.
  double left_high = 0.0;
  for (int f = 0; f < frames; ++f) left_high = std::max(left_high, at(f, "LeftFoot").y());
  EXPECT_GT(left_high, 15.0);
}

TEST_F(WalkTest, KneesFlexLikeAGaitAndArmsSwingAgainstTheLegs) {
  const Motion& m = s_clip->motion;
  const int knee = joint(*s_clip, "LeftLeg");
  double min_knee = 180.0, max_knee = 0.0;
  for (int f = 0; f < 120; ++f) {
    const double flex =
        rad_to_deg(rotation_angle(m.rotation(f, knee), Eigen::Quaterniond::Identity()));
    min_knee = std::min(min_knee, flex);
    max_knee = std::max(max_knee, flex);
  }
  EXPECT_LT(min_knee, 20.0);  // nearly straight in stance
  EXPECT_GT(max_knee, 50.0);  // well bent in swing
  EXPECT_LT(max_knee, 75.0);
  // Left hand forward when the left foot is back: negative correlation of their z offsets from
  // the pelvis.
  double sxy = 0.0, sxx = 0.0, syy = 0.0;
  std::vector<double> hand, foot;
  for (int f = 0; f < 120; ++f) {
    hand.push_back(at(f, "LeftHand").z() - at(f, "Hips").z());
    foot.push_back(at(f, "LeftFoot").z() - at(f, "Hips").z());
  }
  const double mh = std::accumulate(hand.begin(), hand.end(), 0.0) / 120.0;
  const double mf = std::accumulate(foot.begin(), foot.end(), 0.0) / 120.0;
  for (int f = 0; f < 120; ++f) {
    sxy += (hand[f] - mh) * (foot[f] - mf);
    sxx += (hand[f] - mh) * (hand[f] - mh);
    syy += (foot[f] - mf) * (foot[f] - mf);
  }
  EXPECT_LT(sxy / std::sqrt(sxx * syy), -0.8);
}

// --- BVH --------------------------------------------------------------------------------------

TEST(SampleClipTest, RoundTripsThroughBvh) {
  for (SampleKind kind : {SampleKind::Swing, SampleKind::Walk}) {
    SCOPED_TRACE(std::string(sample_kind_name(kind)));
    const Clip c = make_sample_clip(kind);
    std::ostringstream text;
    io::write_bvh(io::from_motion(c.skeleton, c.motion), text);
    const io::BvhDocument doc = io::parse_bvh(text.str(), "sample.bvh");
    EXPECT_TRUE(doc.warnings.empty());
    ASSERT_TRUE(doc.skeleton.same_hierarchy(c.skeleton));
    for (int j = 0; j < 31; ++j) {
      EXPECT_EQ(doc.skeleton.joints[j].channels, c.skeleton.joints[j].channels);
      EXPECT_EQ(doc.skeleton.joints[j].offset, c.skeleton.joints[j].offset);
      EXPECT_EQ(doc.skeleton.joints[j].end_sites, c.skeleton.joints[j].end_sites);
    }
    ASSERT_EQ(doc.num_frames, c.motion.num_frames);
    EXPECT_NEAR(doc.frame_time, c.motion.frame_time, 1e-15);
    const Motion back = io::to_motion(doc);
    double worst = 0.0;
    for (int f = 0; f < back.num_frames; ++f) {
      for (int j = 0; j < 31; ++j) {
        worst = std::max(worst, rotation_angle(back.rotation(f, j), c.motion.rotation(f, j)));
        ASSERT_LT((back.translation(f, j) - c.motion.translation(f, j)).norm(), 1e-9);
      }
    }
    EXPECT_LT(worst, 1e-9);
  }
}

// --- errors -----------------------------------------------------------------------------------

TEST(SampleClipTest, RejectsBadFps) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(parameter_error(SampleKind::Swing, 0.0, 0.0), "sample fps must be in (0, 1000], got 0");
  EXPECT_EQ(parameter_error(SampleKind::Walk, -30.0, 0.0),
            "sample fps must be in (0, 1000], got -30");
  EXPECT_EQ(parameter_error(SampleKind::Walk, 1000.5, 0.0),
            "sample fps must be in (0, 1000], got 1000.5");
  EXPECT_EQ(parameter_error(SampleKind::Swing, nan, 0.0),
            "sample fps must be in (0, 1000], got nan");
  EXPECT_EQ(parameter_error(SampleKind::Swing, inf, 0.0),
            "sample fps must be in (0, 1000], got inf");
  EXPECT_EQ(make_sample_clip(SampleKind::Walk, {1000.0, 0.01}).motion.num_frames, 10);
}

TEST(SampleClipTest, RejectsBadSeconds) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(parameter_error(SampleKind::Swing, 120.0, -1.0),
            "sample seconds must be in [0, 600] (0: the natural length), got -1");
  EXPECT_EQ(parameter_error(SampleKind::Walk, 120.0, 600.25),
            "sample seconds must be in [0, 600] (0: the natural length), got 600.25");
  EXPECT_EQ(parameter_error(SampleKind::Walk, 120.0, nan),
            "sample seconds must be in [0, 600] (0: the natural length), got nan");
  EXPECT_EQ(parameter_error(SampleKind::Walk, 120.0, -std::numeric_limits<double>::infinity()),
            "sample seconds must be in [0, 600] (0: the natural length), got -inf");
}

TEST(SampleClipTest, RejectsFrameCountsOutsideTheLimits) {
  EXPECT_EQ(parameter_error(SampleKind::Swing, 120.0, 0.004),
            "sample of 0.004 s at 120 fps has 0 frames; the frame count must be in [1, 144000]");
  EXPECT_EQ(parameter_error(SampleKind::Walk, 1000.0, 600.0),
            "sample of 600 s at 1000 fps has 600000 frames; the frame count must be in "
            "[1, 144000]");
  EXPECT_EQ(parameter_error(SampleKind::Walk, 1000.0, 144.001),
            "sample of 144.001 s at 1000 fps has 144001 frames; the frame count must be in "
            "[1, 144000]");
}

}  // namespace
}  // namespace motionmap::sample
