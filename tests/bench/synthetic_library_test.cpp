// The synthetic library generator's operations (bench/library/synthetic_library.h): mirroring is
// an exact involution and reflects forward kinematics, time warps are monotone and smooth, clips
// are deterministic. The generator program itself is run by tests/bench/make_library_test.py.
#include "synthetic_library.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"
#include "motionmap/features/point_cloud.h"
#include "motionmap/io/bvh.h"
#include "motionmap/sample/sample_clip.h"
#include "motionmap/skeleton/forward_kinematics.h"
#include "support/test_data.h"

namespace motionmap::bench {
namespace {

using Eigen::Vector3d;

// Largest rotation angle (radians) and translation difference between two motions.
struct MotionDifference {
  double angle = 0.0, translation = 0.0;
};
MotionDifference difference(const Motion& a, const Motion& b) {
  EXPECT_EQ(a.num_frames, b.num_frames);
  EXPECT_EQ(a.num_joints, b.num_joints);
  MotionDifference d;
  for (std::size_t i = 0; i < a.rotations.size() && i < b.rotations.size(); ++i) {
    d.angle = std::max(d.angle, rotation_angle(a.rotations[i], b.rotations[i]));
    d.translation =
        std::max(d.translation, (a.translations[i] - b.translations[i]).cwiseAbs().maxCoeff());
  }
  return d;
}

// Max distance between joint `a`'s world positions in `ma` and M times joint `b`'s in `mb`.
double mirrored_trace_error(const Skeleton& sa, const Motion& ma, int a, const Skeleton& sb,
                            const Motion& mb, int b, Axis lateral) {
  const auto pa = world_points(sa, ma);
  const auto pb = world_points(sb, mb);
  double worst = 0.0;
  for (int f = 0; f < ma.num_frames; ++f) {
    Vector3d q = pb.row(f).segment<3>(3 * b).transpose();
    q[static_cast<int>(lateral)] = -q[static_cast<int>(lateral)];
    worst = std::max(worst, (pa.row(f).segment<3>(3 * a).transpose() - q).norm());
  }
  return worst;
}

TEST(SyntheticLibrary, PartnersAndLateralAxisOfTheCmuSkeleton) {
  const Skeleton skeleton = sample::cmu_like_skeleton();
  const std::vector<int> partners = mirror_partners(skeleton);
  auto partner = [&](const char* name) {
    return skeleton.joints[partners[skeleton.find(name)]].name;
  };
  EXPECT_EQ(partner("LeftFoot"), "RightFoot");
  EXPECT_EQ(partner("RightHandIndex1"), "LeftHandIndex1");
  EXPECT_EQ(partner("LHipJoint"), "RHipJoint");
  EXPECT_EQ(partner("RThumb"), "LThumb");
  EXPECT_EQ(partner("LowerBack"), "LowerBack");
  EXPECT_EQ(partner("Hips"), "Hips");
  // CMU: Y up, facing +Z, the subject's left on +X.
  EXPECT_EQ(lateral_axis(skeleton, partners), Axis::X);
}

// Mirroring twice gives the original back, in memory (exactly: sign flips and swaps) and through
// BVH documents (Euler angles and back, within 1e-9).
TEST(SyntheticLibrary, MirroringTwiceIsTheIdentity) {
  const Clip walk = sample::make_sample_clip(sample::SampleKind::Walk, {120.0, 2.0});
  const std::vector<int> partners = mirror_partners(walk.skeleton);
  const Axis lateral = lateral_axis(walk.skeleton, partners);
  const Motion once = mirror_motion(walk.motion, partners, lateral);
  const Motion twice = mirror_motion(once, partners, lateral);
  EXPECT_EQ(twice.rotations, walk.motion.rotations);
  EXPECT_EQ(twice.translations, walk.motion.translations);

  const Motion once_bvh = io::to_motion(io::from_motion(walk.skeleton, once));
  const Motion twice_bvh =
      io::to_motion(io::from_motion(walk.skeleton, mirror_motion(once_bvh, partners, lateral)));
  const MotionDifference d = difference(twice_bvh, walk.motion);
  EXPECT_LT(d.angle, 1e-9);
  EXPECT_LT(d.translation, 1e-9);
  EXPECT_GT(difference(once, walk.motion).angle, 0.1);  // it did change something
}

// The mirrored walk's left foot traces what the right foot traced, reflected across the sagittal
// plane: exactly on the mirrored skeleton, and on the original one as far as the two legs differ.
TEST(SyntheticLibrary, MirroredWalkFeetTraceEachOther) {
  const Clip walk = sample::make_sample_clip(sample::SampleKind::Walk, {120.0, 2.0});
  const Skeleton& skeleton = walk.skeleton;
  const std::vector<int> partners = mirror_partners(skeleton);
  const Axis lateral = lateral_axis(skeleton, partners);
  const Motion mirrored = mirror_motion(walk.motion, partners, lateral);
  const Skeleton mirrored_skeleton = mirror_skeleton(skeleton, partners, lateral);
  using Pair = std::array<const char*, 2>;
  for (const Pair& pair : {Pair{"LeftFoot", "RightFoot"}, Pair{"RightToeBase", "LeftToeBase"},
                           Pair{"LeftHand", "RightHand"}}) {
    SCOPED_TRACE(pair[0]);
    const int a = skeleton.find(pair[0]), b = skeleton.find(pair[1]);
    EXPECT_LT(
        mirrored_trace_error(mirrored_skeleton, mirrored, a, skeleton, walk.motion, b, lateral),
        1e-9);
  }
  // The sample skeleton is symmetric, so on it the traces match too.
  EXPECT_LT(mirrored_trace_error(skeleton, mirrored, skeleton.find("LeftFoot"), skeleton,
                                 walk.motion, skeleton.find("RightFoot"), lateral),
            1e-9);
}

// The same on a real CMU run (subject 02): exact on the mirrored skeleton; on the subject's own
// (asymmetric) skeleton within 2 % of the leg's length, which a wrong axis (a front/back or up/down
// reflection) would break by far.
TEST(SyntheticLibrary, MirroredCmuRunFeetTraceEachOther) {
  MOTIONMAP_REQUIRE_SHARED("cmu/02_03.bvh");
  const Clip run = io::load_bvh(test::shared_file("cmu/02_03.bvh"));
  const Skeleton& skeleton = run.skeleton;
  const std::vector<int> partners = mirror_partners(skeleton);
  const Axis lateral = lateral_axis(skeleton, partners);
  ASSERT_EQ(lateral, Axis::X);
  const Motion mirrored = mirror_motion(run.motion, partners, lateral);
  const int left = skeleton.find("LeftFoot"), right = skeleton.find("RightFoot");
  EXPECT_LT(mirrored_trace_error(mirror_skeleton(skeleton, partners, lateral), mirrored, left,
                                 skeleton, run.motion, right, lateral),
            1e-9);
  const double leg = skeleton.joints[skeleton.find("RightLeg")].offset.norm() +
                     skeleton.joints[right].offset.norm();  // thigh + shin
  const double own =
      mirrored_trace_error(skeleton, mirrored, left, skeleton, run.motion, right, lateral);
  EXPECT_LT(own, 0.02 * leg) << "leg " << leg;
  for (Axis wrong : {Axis::Y, Axis::Z}) {
    const Motion bad = mirror_motion(run.motion, partners, wrong);
    EXPECT_GT(mirrored_trace_error(skeleton, bad, left, skeleton, run.motion, right, lateral),
              0.5 * leg);
  }
}

TEST(SyntheticLibrary, TimeWarpIsMonotoneWithinTheRates) {
  Random random(7);
  const std::vector<double> u = time_warp(random, 3.0, 400.0, 10000, 1.25, 1.0, 1.0 / 120.0);
  ASSERT_GT(u.size(), 300u);
  EXPECT_EQ(u.front(), 3.0);
  EXPECT_LE(u.back(), 400.0);
  double lo = 10.0, hi = 0.0, biggest_change = 0.0;
  for (std::size_t i = 1; i < u.size(); ++i) {
    const double rate = u[i] - u[i - 1];
    lo = std::min(lo, rate);
    hi = std::max(hi, rate);
    if (i >= 2) biggest_change = std::max(biggest_change, std::abs(rate - (u[i - 1] - u[i - 2])));
  }
  EXPECT_GE(lo, 1.0 / 1.25 - 1e-12);
  EXPECT_LE(hi, 1.25 + 1e-12);
  EXPECT_GT(hi - lo, 0.05);  // it does warp
  // Smoothly: |dr/dt| ≤ r·ln(max_rate)·2π/(shortest period, 1 s), per frame of 1/120 s.
  EXPECT_LT(biggest_change, 1.25 * std::log(1.25) * 2.0 * kPi / 120.0);
}

TEST(SyntheticLibrary, ResampleInterpolatesBetweenFrames) {
  const Clip walk = sample::make_sample_clip(sample::SampleKind::Walk, {120.0, 0.5});
  const std::vector<double> at{0.0, 2.0, 2.5, 59.0};
  const Motion m = resample(walk.motion, at);
  ASSERT_EQ(m.num_frames, 4);
  for (int j = 0; j < m.num_joints; ++j) {
    EXPECT_LT(rotation_angle(m.rotation(1, j), walk.motion.rotation(2, j)), 1e-12);
    EXPECT_LT(rotation_angle(m.rotation(3, j), walk.motion.rotation(59, j)), 1e-12);
    const double half = rotation_angle(walk.motion.rotation(2, j), walk.motion.rotation(3, j)) / 2;
    EXPECT_NEAR(rotation_angle(m.rotation(2, j), walk.motion.rotation(2, j)), half, 1e-9);
    EXPECT_LT((m.translation(2, j) -
               0.5 * (walk.motion.translation(2, j) + walk.motion.translation(3, j)))
                  .norm(),
              1e-12);
  }
  EXPECT_THROW(resample(walk.motion, std::vector<double>{60.0}), ParameterError);
}

// A clip is a function of (sources, options, seed, index): the same call gives the same numbers,
// another index another clip; segments tile the clip.
TEST(SyntheticLibrary, ClipsAreDeterministicAndTiled) {
  Source source;
  source.clip = sample::make_sample_clip(sample::SampleKind::Walk, {120.0, 3.0});
  source.clip.path = "walk.bvh";
  source.partners = mirror_partners(source.clip.skeleton);
  source.lateral = lateral_axis(source.clip.skeleton, source.partners);
  source.can_mirror = true;
  source.hip_height = 95.0;
  const std::vector<Source> sources{source};
  LibraryOptions options;
  options.segment_min = 40;
  options.segment_max = 120;
  const SyntheticClip a = make_clip(sources, options, 3, 700);
  const SyntheticClip b = make_clip(sources, options, 3, 700);
  const SyntheticClip c = make_clip(sources, options, 4, 700);
  EXPECT_EQ(a.clip.motion.rotations, b.clip.motion.rotations);
  EXPECT_EQ(a.clip.motion.translations, b.clip.motion.translations);
  EXPECT_NE(a.clip.motion.rotations, c.clip.motion.rotations);
  ASSERT_GE(a.segments.size(), 6u);
  int next = 0;
  bool some_mirrored = false;
  for (const Segment& s : a.segments) {
    EXPECT_EQ(s.first_frame, next);
    EXPECT_LE(s.frames, 120);
    next += s.frames;
    some_mirrored = some_mirrored || s.mirrored;
  }
  EXPECT_EQ(next, 700);
  EXPECT_TRUE(some_mirrored);
  check_clip(a.clip);
  // Segments join without jumps: no root step at a junction is far beyond the clip's usual step.
  const int root = 0;
  std::vector<double> steps;
  for (int f = 1; f < 700; ++f) {
    steps.push_back(
        (a.clip.motion.translation(f, root) - a.clip.motion.translation(f - 1, root)).norm());
  }
  std::vector<double> sorted = steps;
  std::sort(sorted.begin(), sorted.end());
  EXPECT_LT(*std::max_element(steps.begin(), steps.end()), 4.0 * sorted[sorted.size() / 2]);
  // Nor turns: each segment is turned to go on in the previous one's heading.
  double turn = 0.0;
  for (int f = 1; f < 700; ++f) {
    turn = std::max(
        turn, std::abs(wrap_angle(features::heading_angle(a.clip.motion.rotation(f, root)) -
                                  features::heading_angle(a.clip.motion.rotation(f - 1, root)))));
  }
  EXPECT_LT(rad_to_deg(turn), 2.0);
}

TEST(SyntheticLibrary, RoundValuesKeepsDecimalsAndDropsNegativeZero) {
  std::vector<double> v{1.23456789, -0.00001, -2.5e-5, 12.0};
  round_values(v, 4);
  EXPECT_EQ(v[0], 1.2346);
  EXPECT_FALSE(std::signbit(v[1]));
  EXPECT_EQ(v[1], 0.0);
  EXPECT_EQ(v[2], -0.0);  // std::round(-0.25) is -0, made +0
  EXPECT_FALSE(std::signbit(v[2]));
  EXPECT_EQ(v[3], 12.0);
}

}  // namespace
}  // namespace motionmap::bench
