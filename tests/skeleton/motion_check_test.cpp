// check_motion at every public entry point that takes a skeleton and motion: each bad Clip below
// goes through every such function and must end in a motionmap::Error naming the problem — never
// an out-of-bounds read (this file runs under ASan in the sanitizer build) or NaN output.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/features/diagnostics.h"
#include "motionmap/features/features.h"
#include "motionmap/features/point_cloud.h"
#include "motionmap/io/bvh.h"
#include "motionmap/io/load.h"
#include "motionmap/skeleton/forward_kinematics.h"
#include "motionmap/skeleton/skeleton.h"
#include "support/small_clip.h"

namespace motionmap {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kFrames = 10;

// Hips → Spine → {LeftThumb (End Site), Head (End Site)}, kFrames frames of smooth motion.
Clip good_clip() {
  return test::smooth_clip(kFrames, "bad.bvh");
}

enum class Found { Sizes, Values };        // the MotionCheck level that finds the problem
enum class Kind { Parameter, Numerical };  // ParameterError or NumericalError
enum class Needs { Motion, Skeleton };     // whether check_motion(motion) alone sees the problem

struct BadClip {
  const char* name;
  std::function<void(Clip&)> spoil;
  Found found;
  Kind kind;
  Needs needs;
  std::vector<std::string> says;  // substrings of the message (after "who: ")
};

const std::vector<BadClip>& bad_clips() {
  static const std::vector<BadClip> cases = {
      {"TooFewRotations",
       [](Clip& c) { c.motion.rotations.pop_back(); },
       Found::Sizes,
       Kind::Parameter,
       Needs::Motion,
       {"the motion (10 frames of 4 joints, 39 rotations, 40 translations) is inconsistent",
        "40 rotations and 40 translations were expected"}},
      {"TooManyTranslations",
       [](Clip& c) { c.motion.translations.emplace_back(0, 0, 0); },
       Found::Sizes,
       Kind::Parameter,
       Needs::Motion,
       {"40 rotations, 41 translations", "were expected"}},
      {"NumJointsBelowTheSkeletons",
       [](Clip& c) { c.motion.num_joints = 3; },
       Found::Sizes,
       Kind::Parameter,
       Needs::Skeleton,
       {"the motion (10 frames of 3 joints, 40 rotations, 40 translations) does not fit the "
        "skeleton of 4 joints"}},
      {"SkeletonWithAnExtraJoint",
       [](Clip& c) {
         c.skeleton.joints.push_back({"RightThumb", 1, {-5, 5, 0}, {}, {}});
       },
       Found::Sizes,
       Kind::Parameter,
       Needs::Skeleton,
       {"(10 frames of 4 joints", "does not fit the skeleton of 5 joints"}},
      {"NumFramesBeyondTheStorage",
       [](Clip& c) { c.motion.num_frames = 12; },
       Found::Sizes,
       Kind::Parameter,
       Needs::Motion,
       {"(12 frames of 4 joints, 40 rotations, 40 translations) is inconsistent",
        "#frames·#joints = 48"}},
      {"NegativeNumFrames",
       [](Clip& c) { c.motion.num_frames = -1; },
       Found::Sizes,
       Kind::Parameter,
       Needs::Motion,
       {"(-1 frames of 4 joints", "negative frame or joint count"}},
      {"FrameTimeZero",
       [](Clip& c) { c.motion.frame_time = 0.0; },
       Found::Sizes,
       Kind::Parameter,
       Needs::Motion,
       {"frame time 0.000000 is not a finite number > 0"}},
      {"FrameTimeNegative",
       [](Clip& c) { c.motion.frame_time = -0.01; },
       Found::Sizes,
       Kind::Parameter,
       Needs::Motion,
       {"frame time -0.010000 is not a finite number > 0"}},
      {"FrameTimeNaN",
       [](Clip& c) { c.motion.frame_time = kNaN; },
       Found::Sizes,
       Kind::Parameter,
       Needs::Motion,
       {"frame time nan is not a finite number > 0"}},
      {"FrameTimeInfinite",
       [](Clip& c) { c.motion.frame_time = kInf; },
       Found::Sizes,
       Kind::Parameter,
       Needs::Motion,
       {"frame time inf is not a finite number > 0"}},
      {"ParentOutOfRange",
       [](Clip& c) { c.skeleton.joints[2].parent = 7; },
       Found::Sizes,
       Kind::Parameter,
       Needs::Skeleton,
       {"joint 'LeftThumb' (index 2) has parent index 7",
        "expected -1 (a root) or the index of an earlier joint"}},
      {"ParentAfterItsChild",
       [](Clip& c) { c.skeleton.joints[1].parent = 3; },
       Found::Sizes,
       Kind::Parameter,
       Needs::Skeleton,
       {"joint 'Spine' (index 1) has parent index 3", "parents must come before their children"}},
      {"ParentIsItself",
       [](Clip& c) { c.skeleton.joints[3].parent = 3; },
       Found::Sizes,
       Kind::Parameter,
       Needs::Skeleton,
       {"joint 'Head' (index 3) has parent index 3"}},
      {"ParentBelowMinusOne",
       [](Clip& c) { c.skeleton.joints[2].parent = -2; },
       Found::Sizes,
       Kind::Parameter,
       Needs::Skeleton,
       {"joint 'LeftThumb' (index 2) has parent index -2"}},
      {"NoJoint",
       [](Clip& c) {
         c.skeleton.joints.clear();
         c.motion.resize(kFrames, 0);
       },
       Found::Sizes,
       Kind::Parameter,
       Needs::Skeleton,
       {"the skeleton has no joint"}},
      {"NaNRotation",
       [](Clip& c) { c.motion.rotation(7, 2).x() = kNaN; },
       Found::Values,
       Kind::Numerical,
       Needs::Motion,
       {"frame 7, joint",
        "holds a NaN or infinite value (rotation w x y z = ", "; expected finite numbers)"}},
      {"InfiniteTranslation",
       [](Clip& c) { c.motion.translation(3, 0).y() = kInf; },
       Found::Values,
       Kind::Numerical,
       Needs::Motion,
       {"frame 3, joint", "holds a NaN or infinite value (translation (", ", inf, 0.5)"}},
      {"ZeroRotation",
       [](Clip& c) { c.motion.rotation(5, 1).coeffs().setZero(); },
       Found::Values,
       Kind::Numerical,
       Needs::Motion,
       {"frame 5, joint", "has a rotation of norm 0 (rotation w x y z = 0 0 0 0",
        "expected a unit quaternion"}},
      {"NaNOffset",
       [](Clip& c) { c.skeleton.joints[1].offset.z() = kNaN; },
       Found::Values,
       Kind::Numerical,
       Needs::Skeleton,
       {"joint 'Spine' has a non-finite offset (0, 10, nan)"}},
      {"InfiniteEndSite",
       [](Clip& c) { c.skeleton.joints[3].end_sites[0].x() = -kInf; },
       Found::Values,
       Kind::Numerical,
       Needs::Skeleton,
       {"End Site 0 of joint 'Head' has a non-finite offset (-inf, 3, 0)"}},
  };
  return cases;
}

// A public function taking a skeleton and motion, driven with a whole clip.
struct EntryPoint {
  const char* name;
  const char* who;  // the start of its messages; nullptr: the clip's path
  MotionCheck depth;
  std::function<void(const Clip&)> call;
};

const std::vector<EntryPoint>& entry_points() {
  static const std::vector<EntryPoint> entries = {
      {"check_clip", nullptr, MotionCheck::Values, [](const Clip& c) { check_clip(c); }},
      {"forward_kinematics(frame)", "forward_kinematics", MotionCheck::Sizes,
       [](const Clip& c) { forward_kinematics(c.skeleton, c.motion, 0); }},
      {"world_points", "world_points", MotionCheck::Values,
       [](const Clip& c) { world_points(c.skeleton, c.motion); }},
      {"motion_root", "motion_root", MotionCheck::Sizes,
       [](const Clip& c) { motion_root(c.skeleton, c.motion); }},
      {"heading_local_points", "heading_local_points", MotionCheck::Values,
       [](const Clip& c) { features::heading_local_points(c.skeleton, c.motion); }},
      {"build_features", nullptr, MotionCheck::Values,
       [](const Clip& c) { features::build_features(std::span<const Clip>(&c, 1), {}); }},
      {"build_features(positions)", nullptr, MotionCheck::Values,
       [](const Clip& c) {
         features::FeatureOptions options;
         options.features = features::FeatureKind::Positions;
         options.distance = features::DistanceKind::Geodesic;
         features::build_features(std::span<const Clip>(&c, 1), options);
       }},
      {"select_samples", nullptr, MotionCheck::Values,
       [](const Clip& c) { features::select_samples(std::span<const Clip>(&c, 1), {}); }},
      {"find_rotation_flips", "find_rotation_flips", MotionCheck::Values,
       [](const Clip& c) { features::find_rotation_flips(c.skeleton, c.motion); }},
      {"clip_warnings", "clip_warnings", MotionCheck::Values,
       [](const Clip& c) { features::clip_warnings(c.skeleton, c.motion); }},
      {"from_motion", "from_motion", MotionCheck::Values,
       [](const Clip& c) { io::from_motion(c.skeleton, c.motion); }},
  };
  return entries;
}

class MotionCheckBadClip : public ::testing::TestWithParam<BadClip> {};

TEST_P(MotionCheckBadClip, EveryEntryPointRejectsItWithAClearError) {
  const BadClip& bad = GetParam();
  Clip clip = good_clip();
  bad.spoil(clip);
  for (const EntryPoint& entry : entry_points()) {
    SCOPED_TRACE(entry.name);
    const std::string who = entry.who ? entry.who : clip.path;
    std::string message = "no error";
    bool numerical = false;
    try {
      entry.call(clip);
    } catch (const NumericalError& e) {
      message = e.what();
      numerical = true;
    } catch (const ParameterError& e) {
      message = e.what();
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not a ParameterError or NumericalError: " << e.what();
      continue;
    }
    if (entry.depth == MotionCheck::Sizes && bad.found == Found::Values) {
      // Per-frame entry points check sizes only: values are not their O(#joints) business.
      EXPECT_EQ(message, "no error");
      continue;
    }
    EXPECT_EQ(numerical, bad.kind == Kind::Numerical) << message;
    EXPECT_EQ(message.rfind(who + ": ", 0), 0u) << message;
    for (const std::string& part : bad.says) {
      EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(MotionCheck, MotionCheckBadClip, ::testing::ValuesIn(bad_clips()),
                         [](const ::testing::TestParamInfo<BadClip>& info) {
                           return std::string(info.param.name);
                         });

// quaternion_features takes a motion without its skeleton: it sees the motion's own problems.
TEST(MotionCheck, QuaternionFeaturesRejectsEveryBadMotion) {
  const std::vector<int> joints{1, 2, 3};
  std::vector<int> frames;
  for (int f = 0; f < kFrames; ++f) frames.push_back(f);
  for (const BadClip& bad : bad_clips()) {
    if (bad.needs == Needs::Skeleton) continue;
    SCOPED_TRACE(bad.name);
    Clip clip = good_clip();
    bad.spoil(clip);
    std::string message = "no error";
    try {
      features::quaternion_features(clip.motion, joints, frames);
    } catch (const NumericalError& e) {
      EXPECT_EQ(bad.kind, Kind::Numerical) << e.what();
      message = e.what();
    } catch (const ParameterError& e) {
      EXPECT_EQ(bad.kind, Kind::Parameter) << e.what();
      message = e.what();
    }
    EXPECT_EQ(message.rfind("quaternion_features: ", 0), 0u) << message;
    for (const std::string& part : bad.says) {
      EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' not in: " << message;
    }
  }
}

TEST(MotionCheck, AGoodClipPassesEveryEntryPoint) {
  const Clip clip = good_clip();
  for (const EntryPoint& entry : entry_points()) {
    SCOPED_TRACE(entry.name);
    EXPECT_NO_THROW(entry.call(clip));
  }
  const std::vector<int> joints{1, 2, 3}, frames{0, 4, 9};
  EXPECT_NO_THROW(features::quaternion_features(clip.motion, joints, frames));
  // A skeleton without motion is a valid clip too.
  Clip still = clip;
  still.motion.resize(0, 4);
  EXPECT_NO_THROW(check_clip(still));
  EXPECT_EQ(world_points(still.skeleton, still.motion).rows(), 0);
}

TEST(MotionCheck, MessagesNameTheClipTheFrameAndTheJoint) {
  Clip clip = good_clip();
  clip.motion.rotation(7, 2).x() = kNaN;
  try {
    features::build_features(std::span<const Clip>(&clip, 1), {});
    ADD_FAILURE() << "no error";
  } catch (const NumericalError& e) {
    // The old check's text, then what was found and what was expected.
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("bad.bvh: frame 7, joint 'LeftThumb' holds a NaN or infinite value "
                            "(rotation w x y z = ",
                            0),
              0u)
        << message;
    EXPECT_NE(message.find(" nan 0 "), std::string::npos) << message;
    EXPECT_TRUE(message.ends_with("; expected finite numbers)")) << message;
  }
  // Without a skeleton, joints are named by index; without a path, the clip is "clip".
  try {
    features::quaternion_features(clip.motion, std::vector<int>{2}, std::vector<int>{7});
    ADD_FAILURE() << "no error";
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("quaternion_features: frame 7, joint 2 holds"),
              std::string::npos)
        << e.what();
  }
  clip.path.clear();
  try {
    check_clip(clip);
    ADD_FAILURE() << "no error";
  } catch (const NumericalError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("clip: frame 7, joint 'LeftThumb'", 0), 0u) << e.what();
  }
}

TEST(MotionCheck, StructureIsReportedBeforeValues) {
  // Sizes decide whether values can be read at all, so they come first whatever else is wrong.
  Clip clip = good_clip();
  clip.skeleton.joints[1].offset.x() = kNaN;
  clip.motion.rotation(0, 0).w() = kNaN;
  clip.motion.translations.pop_back();
  EXPECT_THROW(check_clip(clip), ParameterError);
  clip.motion.translations.emplace_back(0, 0, 0);
  try {
    check_clip(clip);
    ADD_FAILURE() << "no error";
  } catch (const NumericalError& e) {
    EXPECT_EQ(std::string(e.what()), "bad.bvh: joint 'Spine' has a non-finite offset (nan, 10, 0)");
  }
  clip.skeleton.joints[1].offset.x() = 0;
  try {
    check_clip(clip);
    ADD_FAILURE() << "no error";
  } catch (const NumericalError& e) {
    EXPECT_EQ(std::string(e.what()),
              "bad.bvh: frame 0, joint 'Hips' holds a NaN or infinite value (rotation w x y z = "
              "nan 0 0 0; expected finite numbers)");
  }
  // A rotation just shorter than kMinRotationNorm is zero, one just longer is not.
  clip.motion.rotation(0, 0) = Eigen::Quaterniond(0.9e-6, 0, 0, 0);
  EXPECT_THROW(check_clip(clip), NumericalError);
  clip.motion.rotation(0, 0) = Eigen::Quaterniond(1.1e-6, 0, 0, 0);
  EXPECT_NO_THROW(check_clip(clip));
}

TEST(MotionCheck, PerFrameForwardKinematicsChecksItsFrameAndPose) {
  const Clip clip = good_clip();
  for (const int frame : {-1, kFrames, 1 << 30}) {
    try {
      forward_kinematics(clip.skeleton, clip.motion, frame);
      ADD_FAILURE() << "no error for frame " << frame;
    } catch (const ParameterError& e) {
      EXPECT_EQ(std::string(e.what()), "forward_kinematics: frame " + std::to_string(frame) +
                                           " is out of range (the motion has 10 frames)");
    }
  }
  // A pose view shorter than the skeleton (here: 3 of its 4 joints).
  const PoseView whole = clip.motion.pose(2);
  const PoseView short_pose{whole.rotations.first(3), whole.translations};
  WorldPose world;
  try {
    forward_kinematics(clip.skeleton, short_pose, world);
    ADD_FAILURE() << "no error";
  } catch (const ParameterError& e) {
    EXPECT_EQ(std::string(e.what()),
              "forward_kinematics: the pose has 3 rotations and 4 translations; expected 4 of "
              "each (the skeleton's joint count)");
  }
  // A skeleton whose parents are out of order, with a pose that fits it.
  Skeleton unsorted = clip.skeleton;
  unsorted.joints[1].parent = 2;
  try {
    forward_kinematics(unsorted, whole, world);
    ADD_FAILURE() << "no error";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("forward_kinematics: joint 'Spine' (index 1) has parent "
                                         "index 2"),
              std::string::npos)
        << e.what();
  }
  forward_kinematics(clip.skeleton, whole, world);
  EXPECT_EQ(world.positions.size(), 4u);
}

TEST(MotionCheck, QuaternionFeaturesRejectsIndicesOutOfRange) {
  const Clip clip = good_clip();
  const std::vector<int> frames{0, 1};
  try {
    features::quaternion_features(clip.motion, std::vector<int>{1, 4}, frames);
    ADD_FAILURE() << "no error";
  } catch (const ParameterError& e) {
    EXPECT_EQ(std::string(e.what()),
              "quaternion_features: joint index 4 is out of range (the motion has 4 joints)");
  }
  try {
    features::quaternion_features(clip.motion, std::vector<int>{1}, std::vector<int>{3, -1});
    ADD_FAILURE() << "no error";
  } catch (const ParameterError& e) {
    EXPECT_EQ(std::string(e.what()),
              "quaternion_features: frame -1 is out of range (the motion has 10 frames)");
  }
}

TEST(MotionCheck, LoadClipChecksWhatTheFpsOverrideMakes) {
  const auto path = std::filesystem::temp_directory_path() / "motionmap_motion_check_test.bvh";
  {
    std::ofstream out(path, std::ios::binary);
    out << "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n  CHANNELS 3 Xposition Yposition Zposition\n"
           "  End Site\n  {\n    OFFSET 0 1 0\n  }\n}\nMOTION\nFrames: 2\nFrame Time: 0.1\n"
           "0 0 0\n1 0 0\n";
  }
  io::LoadOptions options;
  EXPECT_EQ(io::load_clip(path.string(), options).motion.frame_time, 0.1);
  options.fps = kInf;  // 1 / fps = 0
  try {
    io::load_clip(path.string(), options);
    ADD_FAILURE() << "no error";
  } catch (const ParameterError& e) {
    EXPECT_EQ(std::string(e.what()),
              path.string() + ": frame time 0.000000 is not a finite number > 0");
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace motionmap
