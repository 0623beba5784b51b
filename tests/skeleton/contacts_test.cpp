#include "motionmap/skeleton/contacts.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/io/load.h"
#include "motionmap/sample/sample_clip.h"
#include "support/error_message.h"
#include "support/test_data.h"

namespace motionmap {
namespace {

std::string joint_name(const Skeleton& s, int j) {
  return j < 0 ? "(none)" : s.joints[j].name;
}

// "hip knee ankle toe" of a leg, by name.
std::string leg_names(const Skeleton& s, const Leg& leg) {
  return joint_name(s, leg.hip) + " " + joint_name(s, leg.knee) + " " + joint_name(s, leg.ankle) +
         " " + joint_name(s, leg.toe);
}

// A chain skeleton from (name, parent, offset) triples; rotations only.
Skeleton make_skeleton(const std::vector<std::tuple<std::string, int, Eigen::Vector3d>>& joints) {
  Skeleton s;
  for (const auto& [name, parent, offset] : joints) {
    Joint j;
    j.name = name;
    j.parent = parent;
    j.offset = offset;
    j.channels = {ChannelType::Zrotation, ChannelType::Xrotation, ChannelType::Yrotation};
    s.joints.push_back(j);
  }
  return s;
}

// A body of the given joint names: hips at 100, thighs and shins of 45, a 70 up head (with an
// End Site) and feet with toes, in cm; the left leg on +X.
Skeleton legged(const std::array<std::string, 10>& n) {
  using V = Eigen::Vector3d;
  Skeleton s = make_skeleton({{n[0], -1, V(0, 100, 0)},
                              {n[1], 0, V(10, -5, 0)},
                              {n[2], 1, V(0, -45, 0)},
                              {n[3], 2, V(0, -45, 0)},
                              {n[4], 3, V(0, -5, 10)},
                              {n[5], 0, V(-10, -5, 0)},
                              {n[6], 5, V(0, -45, 0)},
                              {n[7], 6, V(0, -45, 0)},
                              {n[8], 7, V(0, -5, 10)},
                              {n[9], 0, V(0, 60, 0)}});
  s.joints[9].end_sites.push_back(V(0, 10, 0));
  s.joints[0].channels.insert(
      s.joints[0].channels.begin(),
      {ChannelType::Xposition, ChannelType::Yposition, ChannelType::Zposition});
  return s;
}

TEST(SkeletonContacts, FindsFeetByNameInTheCommonConventions) {
  struct Case {
    std::array<std::string, 10> names;
    std::string left, right;
  };
  const std::vector<Case> cases = {
      {{"Hips", "LeftUpLeg", "LeftLeg", "LeftFoot", "LeftToeBase", "RightUpLeg", "RightLeg",
        "RightFoot", "RightToeBase", "Head"},
       "LeftUpLeg LeftLeg LeftFoot LeftToeBase",
       "RightUpLeg RightLeg RightFoot RightToeBase"},
      {{"Hips", "UpperLeg_L", "LowerLeg_L", "Foot_L", "Toes_L", "UpperLeg_R", "LowerLeg_R",
        "Foot_R", "Toes_R", "Head"},
       "UpperLeg_L LowerLeg_L Foot_L Toes_L",
       "UpperLeg_R LowerLeg_R Foot_R Toes_R"},
      {{"root", "lfemur", "ltibia", "lfoot", "ltoes", "rfemur", "rtibia", "rfoot", "rtoes", "head"},
       "lfemur ltibia lfoot ltoes",
       "rfemur rtibia rfoot rtoes"},
      {{"mixamorig:Hips", "mixamorig:LeftUpLeg", "mixamorig:LeftLeg", "mixamorig:LeftFoot",
        "mixamorig:LeftToeBase", "mixamorig:RightUpLeg", "mixamorig:RightLeg",
        "mixamorig:RightFoot", "mixamorig:RightToeBase", "mixamorig:Head"},
       "mixamorig:LeftUpLeg mixamorig:LeftLeg mixamorig:LeftFoot mixamorig:LeftToeBase",
       "mixamorig:RightUpLeg mixamorig:RightLeg mixamorig:RightFoot mixamorig:RightToeBase"},
      // Blender's ".L" and a toe named "Ball": found by name, sides from the names even though
      // the "left" leg is declared second.
      {{"pelvis", "thigh.R", "shin.R", "foot.R", "ball.R", "thigh.L", "shin.L", "foot.L", "ball.L",
        "head"},
       "thigh.L shin.L foot.L ball.L",
       "thigh.R shin.R foot.R ball.R"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.names[3]);
    const Skeleton s = legged(c.names);
    const Feet feet = find_feet(s);
    EXPECT_TRUE(feet.by_name);
    EXPECT_EQ(feet.legs[0].side, FootSide::Left);
    EXPECT_EQ(leg_names(s, feet.legs[0]), c.left);
    EXPECT_EQ(leg_names(s, feet.legs[1]), c.right);
  }
}

TEST(SkeletonContacts, FallsBackToTheLegChainsOfTheHierarchy) {
  // No name says foot: the two lowest leaf chains of ≥ 3 joints, the +X one left; chains of 4
  // end in a toe.
  const Skeleton s = legged({"a", "b", "c", "d", "e", "f", "g", "h", "i", "j"});
  const Feet feet = find_feet(s);
  EXPECT_FALSE(feet.by_name);
  EXPECT_EQ(leg_names(s, feet.legs[0]), "b c d e");
  EXPECT_EQ(leg_names(s, feet.legs[1]), "f g h i");
  // Without toes the leaf is the ankle; a zero-offset joint (CMU's LHipJoint) is skipped.
  using V = Eigen::Vector3d;
  const Skeleton t = make_skeleton({{"p", -1, V(0, 90, 0)},
                                    {"q", 0, V(0, 0, 0)},
                                    {"r", 1, V(-8, -5, 0)},
                                    {"s", 2, V(0, -40, 0)},
                                    {"u", 3, V(0, -40, 0)},
                                    {"v", 0, V(8, -5, 0)},
                                    {"w", 5, V(0, -40, 0)},
                                    {"x", 6, V(0, -40, 0)},
                                    {"y", 0, V(0, 50, 0)}});
  const Feet f2 = find_feet(t);
  EXPECT_EQ(leg_names(t, f2.legs[0]), "v w x (none)");
  EXPECT_EQ(leg_names(t, f2.legs[1]), "r s u (none)");
}

TEST(SkeletonContacts, SaysClearlyWhenThereAreNoFeet) {
  using V = Eigen::Vector3d;
  const Skeleton s = make_skeleton({{"Hips", -1, V(0, 90, 0)},
                                    {"Spine", 0, V(0, 10, 0)},
                                    {"Head", 1, V(0, 8, 0)},
                                    {"LeftArm", 1, V(5, 6, 0)},
                                    {"RightArm", 1, V(-5, 6, 0)}});
  std::string why;
  EXPECT_FALSE(try_find_feet(s, Axis::Y, &why).has_value());
  EXPECT_NE(why.find("no feet found"), std::string::npos) << why;
  const std::string message = test::error_message<ParameterError>([&] { find_feet(s); });
  EXPECT_EQ(message, why);
  EXPECT_NE(message.find("LeftFoot, Foot_L"), std::string::npos) << message;
}

TEST(SkeletonContacts, FindsTheFeetOfTheSampleAndOfRealSkeletons) {
  const Skeleton sample = sample::cmu_like_skeleton();
  EXPECT_EQ(leg_names(sample, find_feet(sample).legs[0]), "LeftUpLeg LeftLeg LeftFoot LeftToeBase");
  struct Real {
    const char* file;
    const char* left;
    const char* right;
  };
  const Real reals[] = {
      {"bandai/dataset-1_walk_angry_001.bvh", "UpperLeg_L LowerLeg_L Foot_L Toes_L",
       "UpperLeg_R LowerLeg_R Foot_R Toes_R"},
      {"cmu/64_08.bvh", "LeftUpLeg LeftLeg LeftFoot LeftToeBase",
       "RightUpLeg RightLeg RightFoot RightToeBase"},
      {"asfamc/02_02.amc", "lfemur ltibia lfoot ltoes", "rfemur rtibia rfoot rtoes"},
      {"other/20tab_test_mocapbank.bvh", "LeftHip LeftKnee LeftAnkle (none)",
       "RightHip RightKnee RightAnkle (none)"},
      {"other/20tab_test_freebvh.bvh",
       "mixamorig:LeftUpLeg mixamorig:LeftLeg mixamorig:LeftFoot mixamorig:LeftToeBase",
       "mixamorig:RightUpLeg mixamorig:RightLeg mixamorig:RightFoot mixamorig:RightToeBase"},
  };
  for (const Real& r : reals) {
    if (!std::filesystem::exists(test::shared_file(r.file))) {
      std::printf("[ skipped  ] %s absent\n", r.file);
      continue;
    }
    const Clip clip = io::load_clip(test::shared_file(r.file));
    const Feet feet = find_feet(clip.skeleton);
    EXPECT_TRUE(feet.by_name) << r.file;
    EXPECT_EQ(leg_names(clip.skeleton, feet.legs[0]), r.left) << r.file;
    EXPECT_EQ(leg_names(clip.skeleton, feet.legs[1]), r.right) << r.file;
  }
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
}

TEST(SkeletonContacts, DetectsTheLengthUnitFromTheBodysSize) {
  // The sample is in cm (1.72 m); scaled copies in m and mm.
  Clip walk = sample::make_sample_clip(sample::SampleKind::Walk, {.fps = 30.0, .seconds = 2.0});
  LengthUnits u = detect_length_units(walk.skeleton, walk.motion);
  EXPECT_EQ(u.unit, LengthUnit::Centimetre);
  EXPECT_TRUE(u.plausible);
  EXPECT_NEAR(u.size * u.metres_per_unit, 1.7, 0.2);
  for (const auto& [scale, unit] :
       {std::pair{0.01, LengthUnit::Metre}, std::pair{10.0, LengthUnit::Millimetre},
        std::pair{1.0 / 2.54, LengthUnit::Inch}}) {
    Clip scaled = walk;
    for (Joint& j : scaled.skeleton.joints) {
      j.offset *= scale;
      for (auto& e : j.end_sites) e *= scale;
    }
    for (auto& t : scaled.motion.translations) t *= scale;
    const LengthUnits s = detect_length_units(scaled.skeleton, scaled.motion);
    EXPECT_EQ(s.unit, unit) << scale;
    EXPECT_TRUE(s.plausible) << scale;
  }
  // No frame: the rest pose (a T-pose, 1.72 m).
  Motion empty;
  empty.resize(0, walk.skeleton.num_joints());
  EXPECT_EQ(detect_length_units(walk.skeleton, empty).unit, LengthUnit::Centimetre);
  EXPECT_EQ(length_unit_name(LengthUnit::CmuUnit), "CMU units (1/0.45 in)");

  const std::pair<const char*, LengthUnit> reals[] = {
      {"bandai/dataset-1_walk_angry_001.bvh", LengthUnit::Centimetre},
      {"cmu/64_08.bvh", LengthUnit::CmuUnit},
      {"asfamc/02_02.amc", LengthUnit::CmuUnit},
      {"other/omimo_AV_8Walk_Meredith_HVHA_Rep1.bvh", LengthUnit::Inch},
      {"other/20tab_test_freebvh.bvh", LengthUnit::Centimetre},
      {"other/facebookresearch_pfnn_hierarchy.bvh", LengthUnit::Metre},
  };
  for (const auto& [file, unit] : reals) {
    if (!std::filesystem::exists(test::shared_file(file))) continue;
    const Clip clip = io::load_clip(test::shared_file(file));
    const LengthUnits got = detect_length_units(clip.skeleton, clip.motion);
    std::printf("[ figures  ] %s: size %.4g → %s, %.3g m\n", file, got.size,
                std::string(length_unit_name(got.unit)).c_str(), got.size * got.metres_per_unit);
    EXPECT_EQ(got.unit, unit) << file;
    EXPECT_TRUE(got.plausible) << file;
  }
  MOTIONMAP_REQUIRE_SHARED("cmu/64_08.bvh");
}

// A two-legged clip at 10 fps whose ankles follow scripted paths (cm): the ankles' local
// translations are animated, everything else is at rest.
struct Scripted {
  Skeleton skeleton;
  Motion motion;
  Feet feet;
};

Scripted scripted(const std::vector<Eigen::Vector3d>& left,
                  const std::vector<Eigen::Vector3d>& right, double scale = 1.0) {
  Scripted out;
  out.skeleton = legged({"Hips", "LeftUpLeg", "LeftLeg", "LeftFoot", "LeftToeBase", "RightUpLeg",
                         "RightLeg", "RightFoot", "RightToeBase", "Head"});
  for (Joint& j : out.skeleton.joints) {
    j.offset *= scale;
    for (auto& e : j.end_sites) e *= scale;
  }
  out.feet = find_feet(out.skeleton);
  const int F = static_cast<int>(left.size());
  out.motion.frame_time = 0.1;
  out.motion.resize(F, out.skeleton.num_joints());
  for (int f = 0; f < F; ++f) {
    for (int j = 0; j < out.skeleton.num_joints(); ++j) {
      out.motion.translation(f, j) = out.skeleton.joints[j].offset;
    }
    // At rest the left ankle is at (10, 5, 0) and the right at (−10, 5, 0): move them by the
    // script, relative to a floor at 5.
    out.motion.translation(f, 3) += left[f] * scale;
    out.motion.translation(f, 7) += right[f] * scale;
  }
  return out;
}

TEST(SkeletonContacts, SkatingMeasureOfAScriptedClip) {
  using V = Eigen::Vector3d;
  // Left: heights 0 2 4 6 1 0 (cm), forward 0 3 10 20 21 21. Right: heights 10 10 0 0 0 0,
  // moving 6 sideways and 8 forward between frames 2 and 3.
  const std::vector<V> left{V(0, 0, 0),  V(0, 2, 3),  V(0, 4, 10),
                            V(0, 6, 20), V(0, 1, 21), V(0, 0, 21)};
  const std::vector<V> right{V(0, 10, 0), V(0, 10, 0), V(0, 0, 0),
                             V(6, 0, 8),  V(6, 0, 8),  V(6, 0, 8)};
  // By hand, 5 transitions of 0.1 s, contact = both frames < 5 cm above the lowest:
  //  left in contact over 0→1 (3 cm: 30 cm/s), 1→2 (7 cm: 70 cm/s, skates), 4→5 (0);
  //  right over 2→3 (10 cm: 100 cm/s, skates), 3→4 (0), 4→5 (0).
  //  Skating transitions: 1→2 and 2→3 → 2/5 = 0.4; mean in-contact speed 200/6 cm/s.
  const Scripted cm = scripted(left, right);
  LengthUnits units;
  units.unit = LengthUnit::Centimetre;
  units.metres_per_unit = 0.01;
  const Skating s = measure_skating(cm.skeleton, cm.motion, cm.feet, units);
  EXPECT_EQ(s.transitions, 5);
  EXPECT_EQ(s.skating_transitions, 2);
  EXPECT_EQ(s.contact_transitions, 6);
  EXPECT_DOUBLE_EQ(s.ratio, 0.4);
  EXPECT_NEAR(s.contact_speed_cm_s, 200.0 / 6.0, 1e-9);
  // A foot up (5 cm or more over its lowest): the left in frame 3 (6 cm), the right in frames 0
  // and 1 (10 cm): 2 frames, 0.2 s.
  EXPECT_NEAR(s.longest_raised_s, 0.2, 1e-12);
  // The same clip in metres, its unit detected (the body is 1.7 m tall): the same answer.
  const Scripted m = scripted(left, right, 0.01);
  const Skating sm = measure_skating(m.skeleton, m.motion, m.feet);
  EXPECT_EQ(sm.units.unit, LengthUnit::Metre);
  EXPECT_DOUBLE_EQ(sm.ratio, 0.4);
  EXPECT_NEAR(sm.contact_speed_cm_s, 200.0 / 6.0, 1e-9);
  EXPECT_NEAR(sm.longest_raised_s, 0.2, 1e-12);
  // One frame: no transition, no contact.
  Motion one = cm.motion;
  one.resize(1, cm.skeleton.num_joints());
  for (int j = 0; j < cm.skeleton.num_joints(); ++j)
    one.translation(0, j) = cm.skeleton.joints[j].offset;
  const Skating s1 = measure_skating(cm.skeleton, one, cm.feet, units);
  EXPECT_EQ(s1.transitions, 0);
  EXPECT_EQ(s1.ratio, 0.0);
  EXPECT_TRUE(std::isnan(s1.contact_speed_cm_s));
  EXPECT_EQ(s1.longest_raised_s, 0.0);
}

TEST(SkeletonContacts, ContactOptionsNameTheirField) {
  auto message = [](ContactOptions o) {
    return test::error_message<ParameterError>([&] { o.validate(); });
  };
  EXPECT_EQ(message({.height = 0.0}),
            "height: 0 is out of range (fraction of the leg length, must be in (0, 1])");
  EXPECT_EQ(message({.speed = NAN}).substr(0, 10), "speed: nan");
  EXPECT_EQ(message({.gap_seconds = -1}).substr(0, 12), "gap_seconds:");
  EXPECT_EQ(message({.min_seconds = 11}).substr(0, 12), "min_seconds:");
  EXPECT_EQ(message({}), "no error");
}

TEST(SkeletonContacts, TheSampleWalkPlantsEachFootOncePerStride) {
  // The built-in walk: a 1 s gait cycle, feet planted in stance; 4 s at 60 fps.
  const Clip walk = sample::make_sample_clip(sample::SampleKind::Walk, {.fps = 60.0});
  const Feet feet = find_feet(walk.skeleton);
  const auto contacts = detect_contacts(walk.skeleton, walk.motion, feet);
  for (const FootContacts& fc : contacts) {
    SCOPED_TRACE(std::string(foot_side_name(fc.leg.side)));
    // One stance of ≥ 0.2 s per stride (a 1 s cycle: 4 s hold 3 to 5); the sample's ankle
    // also pauses briefly as it rolls over the ball of the foot (short contacts, ≥ 0.05 s).
    int stances = 0;
    for (const ContactInterval& c : fc.intervals) {
      stances += c.frames() >= 12;
      EXPECT_GE(c.frames(), 3);
      EXPECT_TRUE(fc.in_contact(c.first) && fc.in_contact(c.last));
      EXPECT_FALSE(fc.in_contact(c.first - 1) || fc.in_contact(c.last + 1));
    }
    EXPECT_GE(stances, 3);
    EXPECT_LE(stances, 5);
    EXPECT_NEAR(fc.leg_length, 90.0, 15.0);
  }
  const Skating s = measure_skating(walk.skeleton, walk.motion, feet);
  std::printf("[ figures  ] sample walk: skating ratio %.3f, in contact %.1f cm/s\n", s.ratio,
              s.contact_speed_cm_s);
}

// Hand-labelled contacts (tests/data/bandai_walk_contacts.csv): clip → foot → intervals.
std::map<std::string, std::map<std::string, std::vector<ContactInterval>>> read_labels() {
  std::ifstream in(std::string(MOTIONMAP_SOURCE_DIR) + "/tests/data/bandai_walk_contacts.csv");
  EXPECT_TRUE(in.good());
  std::map<std::string, std::map<std::string, std::vector<ContactInterval>>> out;
  std::string line;
  bool header = true;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (header) {
      header = false;
      continue;
    }
    std::stringstream ss(line);
    std::string clip, foot, first, last;
    std::getline(ss, clip, ',');
    std::getline(ss, foot, ',');
    std::getline(ss, first, ',');
    std::getline(ss, last, ',');
    out[clip][foot].push_back({std::stoi(first), std::stoi(last)});
  }
  return out;
}

TEST(SkeletonContacts, AgreeWithHandLabelledContactsOnBandaiWalks) {
  MOTIONMAP_REQUIRE_SHARED("bandai/dataset-1_walk_angry_001.bvh");
  const auto labels = read_labels();
  ASSERT_EQ(labels.size(), 2u);
  for (const auto& [clip_name, feet_labels] : labels) {
    const Clip clip = io::load_clip(test::shared_file("bandai/" + clip_name));
    const Feet feet = find_feet(clip.skeleton);
    const auto found = detect_contacts(clip.skeleton, clip.motion, feet);
    for (const FootContacts& fc : found) {
      const std::string side(foot_side_name(fc.leg.side));
      const auto& truth = feet_labels.at(side);
      FootContacts labelled;
      labelled.intervals = truth;
      int tp = 0, fp = 0, fn = 0;
      for (int f = 0; f < clip.motion.num_frames; ++f) {
        const bool a = fc.in_contact(f), b = labelled.in_contact(f);
        tp += a && b;
        fp += a && !b;
        fn += !a && b;
      }
      const double precision = tp / static_cast<double>(tp + fp);
      const double recall = tp / static_cast<double>(tp + fn);
      std::printf(
          "[ figures  ] %s %s: %zu contacts found, %zu labelled; per frame precision %.3f, "
          "recall %.3f (%d true, %d false positive, %d missed frames)\n",
          clip_name.c_str(), side.c_str(), fc.intervals.size(), truth.size(), precision, recall, tp,
          fp, fn);
      EXPECT_EQ(fc.intervals.size(), truth.size()) << clip_name << " " << side;
      EXPECT_GE(precision, 0.85) << clip_name << " " << side;
      EXPECT_GE(recall, 0.9) << clip_name << " " << side;
    }
  }
}

TEST(SkeletonContacts, SkatingOfCapturedBandaiWalks) {
  MOTIONMAP_REQUIRE_SHARED("bandai/dataset-1_walk_angry_001.bvh");
  for (const char* name : {"angry", "feminine", "old", "proud", "tired"}) {
    const std::string file = std::string("bandai/dataset-1_walk_") + name + "_001.bvh";
    const Clip clip = io::load_clip(test::shared_file(file));
    const Skating s = measure_skating(clip.skeleton, clip.motion, find_feet(clip.skeleton));
    std::printf("[ figures  ] %s: skating ratio %.3f, in contact %.1f cm/s\n", file.c_str(),
                s.ratio, s.contact_speed_cm_s);
    EXPECT_EQ(s.units.unit, LengthUnit::Centimetre);
    // Captured walks: the ankle still rolls forward at heel strike and heel-off within 5 cm of
    // the floor, so the measure is far from 0 even for clean capture.
    EXPECT_GT(s.ratio, 0.2) << file;
    EXPECT_LT(s.ratio, 0.6) << file;
    EXPECT_GT(s.contact_speed_cm_s, 20.0) << file;
    EXPECT_LT(s.contact_speed_cm_s, 120.0) << file;
  }
}

}  // namespace
}  // namespace motionmap

namespace motionmap {
namespace {

// The ankle paths given (what synth::clean_feet computes once for the contacts and the clean-up):
// the same contacts as detect_contacts() computing them itself; paths of another length refused.
TEST(SkeletonContacts, AnklePathsGivenGiveTheSameContacts) {
  MOTIONMAP_REQUIRE_SHARED("bandai/dataset-1_walk_proud_001.bvh");
  const Clip clip = io::load_clip(test::shared_file("bandai/dataset-1_walk_proud_001.bvh"));
  const Feet feet = find_feet(clip.skeleton);
  const AnklePaths ankles = ankle_paths(clip.skeleton, clip.motion, feet);
  ASSERT_EQ(ankles[0].size(), static_cast<std::size_t>(clip.motion.num_frames));
  EXPECT_EQ(ankles[1], joint_trajectory(clip.skeleton, clip.motion, feet.legs[1].ankle));
  const auto own = detect_contacts(clip.skeleton, clip.motion, feet);
  const auto given = detect_contacts(clip.skeleton, clip.motion, feet, ankles);
  for (int s = 0; s < 2; ++s) {
    const FootContacts& a = own[static_cast<std::size_t>(s)];
    const FootContacts& b = given[static_cast<std::size_t>(s)];
    EXPECT_EQ(a.floor, b.floor);
    EXPECT_EQ(a.leg_length, b.leg_length);
    ASSERT_EQ(a.intervals.size(), b.intervals.size());
    EXPECT_GT(a.intervals.size(), 5u);
    for (std::size_t i = 0; i < a.intervals.size(); ++i) {
      EXPECT_EQ(a.intervals[i].first, b.intervals[i].first);
      EXPECT_EQ(a.intervals[i].last, b.intervals[i].last);
    }
  }
  AnklePaths short_paths = ankles;
  short_paths[1].pop_back();
  const std::string message = test::error_message<ParameterError>(
      [&] { detect_contacts(clip.skeleton, clip.motion, feet, short_paths); });
  EXPECT_EQ(message, "detect_contacts: an ankle path of 330 points for 331 frames");
}

// Frame times written to a few digits are their frame rate: CMU's BVH of the 02_03 jog says
// 0.0083333 s (120.0005 fps), its ASF/AMC original 1/120 s. Read as 120.0005 fps, the velocity's
// window was ±3 frames, not ±2, and its contacts 7 frames at least, not 6: the BVH lost a
// contact of the left foot that the AMC keeps.
TEST(SkeletonContacts, FrameTimesWrittenToAFewDigitsAreTheirFrameRate) {
  EXPECT_EQ(frames_at_least(0.05, 1.0 / 0.0083333), 6);
  EXPECT_EQ(frames_at_most(0.05, 1.0 / 0.0083337), 6);
  EXPECT_EQ(frames_at_least(1.0 / 60.0, 120.005), 2);
  EXPECT_EQ(frames_at_least(0.05, 30.0), 2);  // 1.5 frames: rounded up
  EXPECT_EQ(frames_at_most(0.05, 30.0), 1);
  EXPECT_EQ(frames_at_least(0.0, 120.0), 0);
  EXPECT_EQ(frames_at_most(1e30, 120.0), std::numeric_limits<int>::max());
  MOTIONMAP_REQUIRE_SHARED("cmu/02_03.bvh");
  MOTIONMAP_REQUIRE_SHARED("asfamc/02_03.amc");
  const Clip bvh = io::load_clip(test::shared_file("cmu/02_03.bvh"));
  const Clip amc = io::load_clip(test::shared_file("asfamc/02_03.amc"));
  // The BVH without its leading T-pose: the AMC's frames.
  const Motion jog = bvh.motion.frames(1, bvh.motion.num_frames);
  ASSERT_EQ(jog.num_frames, amc.motion.num_frames);
  const auto from_bvh = detect_contacts(bvh.skeleton, jog, find_feet(bvh.skeleton));
  const auto from_amc = detect_contacts(amc.skeleton, amc.motion, find_feet(amc.skeleton));
  for (int s = 0; s < 2; ++s) {
    SCOPED_TRACE(s);
    EXPECT_EQ(from_bvh[s].intervals, from_amc[s].intervals);
    EXPECT_EQ(from_bvh[s].intervals.size(), 2u);
  }
}

}  // namespace
}  // namespace motionmap
