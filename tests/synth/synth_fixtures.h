#pragma once
// Small synthetic clips and maps for the synth tests: a five-joint body that walks a curve,
// turns, bobs and moves its limbs smoothly, and a hand-made 2-D map of its frames.
#include <algorithm>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "motionmap/core/rotation.h"
#include "motionmap/features/features.h"
#include "motionmap/skeleton/forward_kinematics.h"
#include "motionmap/skeleton/skeleton.h"

namespace motionmap::synth::test {

inline Skeleton five_joint_skeleton() {
  using C = ChannelType;
  Skeleton s;
  const std::vector<C> root{C::Xposition, C::Yposition, C::Zposition,
                            C::Zrotation, C::Yrotation, C::Xrotation};
  const std::vector<C> rot{C::Zrotation, C::Yrotation, C::Xrotation};
  s.joints.push_back({"Hips", -1, {0, 0, 0}, root, {}});
  s.joints.push_back({"Spine", 0, {0, 10, 0}, rot, {}});
  s.joints.push_back({"Head", 1, {0, 8, 0}, rot, {{0, 3, 0}}});
  s.joints.push_back({"LeftArm", 1, {5, 6, 0}, rot, {{6, 0, 0}}});
  s.joints.push_back({"RightArm", 1, {-5, 6, 0}, rot, {{-6, 0, 0}}});
  return s;
}

/// `frames` frames at `fps`: the root walks forward along its heading at 30 units/s while the
/// heading turns at 0.4 rad/s, bobs ±2 around 90 and leans a little; the limbs swing.
inline Clip walking_clip(int frames = 80, double fps = 30.0) {
  Clip clip;
  clip.path = "walking.bvh";
  clip.skeleton = five_joint_skeleton();
  clip.motion.frame_time = 1.0 / fps;
  clip.motion.resize(frames, 5);
  Eigen::Vector3d pos(10, 0, -5);
  for (int f = 0; f < frames; ++f) {
    const double t = f / fps;
    const double heading = 0.3 + 0.4 * t;
    for (int j = 0; j < 5; ++j) clip.motion.translation(f, j) = clip.skeleton.joints[j].offset;
    clip.motion.translation(f, 0) = Eigen::Vector3d(pos.x(), 90 + 2 * std::sin(6 * t), pos.z());
    clip.motion.rotation(f, 0) =
        axis_rotation(Axis::Y, heading) * axis_rotation(Axis::X, 0.1 * std::sin(3 * t));
    clip.motion.rotation(f, 1) = axis_rotation(Axis::X, 0.3 * std::sin(2 * t));
    clip.motion.rotation(f, 2) =
        axis_rotation(Axis::Y, 0.5 * std::cos(1.5 * t)) * axis_rotation(Axis::Z, 0.1 * t);
    clip.motion.rotation(f, 3) = axis_rotation(Axis::Z, 1.0 + 0.6 * std::sin(3 * t));
    clip.motion.rotation(f, 4) = axis_rotation(Axis::X, -0.8 * std::sin(3 * t + 0.5));
    // Forward is +Z turned by the heading.
    pos += axis_rotation(Axis::Y, heading) * Eigen::Vector3d(0, 0, 30.0 / fps);
  }
  return clip;
}

/// Feature-set bookkeeping for a map of every frame of clip 0 (X and D are not needed).
inline features::FeatureSet all_frames(int frames) {
  features::FeatureSet set;
  set.segment_starts = {0};
  for (int f = 0; f < frames; ++f) {
    set.clip_of.push_back(0);
    set.frame_of.push_back(f);
  }
  return set;
}

/// A map of `frames` samples along a gently winding, non-crossing curve, step ≈ 0.1.
inline Eigen::MatrixXd curve_map(int frames) {
  Eigen::MatrixXd c(frames, 2);
  for (int f = 0; f < frames; ++f) c.row(f) << 0.1 * f, 0.8 * std::sin(0.15 * f);
  return c;
}

/// Largest rotation angle (radians) between the joints of two poses.
inline double max_joint_angle(const Motion& a, int fa, const Motion& b, int fb) {
  double worst = 0.0;
  for (int j = 0; j < a.num_joints; ++j)
    worst = std::max(worst, rotation_angle(a.rotation(fa, j), b.rotation(fb, j)));
  return worst;
}

/// The largest distance any joint moves between two consecutive frames of `m`.
inline double max_jump(const Skeleton& s, const Motion& m) {
  double worst = 0.0;
  WorldPose a, b;
  for (int f = 0; f < m.num_frames; ++f) {
    forward_kinematics(s, m.pose(f), b);
    for (std::size_t j = 0; f > 0 && j < b.positions.size(); ++j)
      worst = std::max(worst, (b.positions[j] - a.positions[j]).norm());
    std::swap(a, b);
  }
  return worst;
}

}  // namespace motionmap::synth::test
