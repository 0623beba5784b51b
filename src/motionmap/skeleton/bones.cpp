#include "motionmap/skeleton/bones.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

namespace motionmap {

std::vector<bool> detached_joints(const Skeleton& skeleton, const Motion& motion) {
  const int n = skeleton.num_joints();
  std::vector<bool> out(std::size_t(n), false);
  if (motion.num_joints != n || motion.num_frames <= 0 ||
      motion.translations.size() != std::size_t(motion.num_frames) * std::size_t(n))
    return out;
  Motion rest;
  rest.resize(1, n);
  for (int j = 0; j < n; ++j) rest.translation(0, j) = skeleton.joints[std::size_t(j)].offset;
  const double extent = pose_extent(forward_kinematics(skeleton, rest, 0));
  for (int j = 0; j < n; ++j) {
    const Joint& joint = skeleton.joints[std::size_t(j)];
    if (joint.parent < 0) continue;
    // A joint without position channels always sits at its offset.
    const bool translated = std::any_of(joint.channels.begin(), joint.channels.end(),
                                        [](ChannelType c) { return !is_rotation(c); });
    if (!translated) continue;
    const double tolerance = 0.25 * joint.offset.norm() + 0.01 * extent;
    for (int f = 0; f < motion.num_frames && !out[std::size_t(j)]; ++f) {
      const Eigen::Vector3d d = motion.translation(f, j) - joint.offset;
      if (d.allFinite() && d.norm() > tolerance) out[std::size_t(j)] = true;
    }
  }
  return out;
}

std::vector<BoneSegment> bone_segments(const Skeleton& skeleton, const WorldPose& pose,
                                       const std::vector<bool>& detached) {
  std::vector<BoneSegment> out;
  std::size_t end_site = 0;
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    const Joint& joint = skeleton.joints[static_cast<std::size_t>(j)];
    if (std::size_t(j) >= pose.positions.size()) break;
    const Eigen::Vector3d& p = pose.positions[static_cast<std::size_t>(j)];
    const bool cut = std::size_t(j) < detached.size() && detached[std::size_t(j)];
    if (joint.parent >= 0 && !cut) {
      const Eigen::Vector3d& q = pose.positions[static_cast<std::size_t>(joint.parent)];
      if ((p - q).squaredNorm() > 0.0) out.push_back({q, p, j});
    }
    for (std::size_t e = 0; e < joint.end_sites.size(); ++e, ++end_site) {
      if (end_site >= pose.end_sites.size()) break;
      const Eigen::Vector3d& s = pose.end_sites[end_site];
      if ((s - p).squaredNorm() > 0.0) out.push_back({p, s, j});
    }
  }
  return out;
}

std::vector<bool> body_joints(const Skeleton& skeleton, const std::vector<bool>& detached) {
  const int n = skeleton.num_joints();
  std::vector<bool> out(std::size_t(n), n == 1);
  for (int j = 0; j < n; ++j) {
    const Joint& joint = skeleton.joints[std::size_t(j)];
    if (!joint.end_sites.empty()) out[std::size_t(j)] = true;
    const bool cut = std::size_t(j) < detached.size() && detached[std::size_t(j)];
    if (joint.parent >= 0 && !cut) out[std::size_t(j)] = out[std::size_t(joint.parent)] = true;
  }
  return out;
}

namespace {

bool is_upper(char c) {
  return c >= 'A' && c <= 'Z';
}
bool is_separator(char c) {
  return c == '_' || c == '.' || c == '-' || c == ' ' || c == ':';
}

/// Side marked in `name` by a word, a separated letter, or (when `a mirror` says the skeleton
/// has the mirrored name) a bare first letter.
JointSide marked_side(const std::string& name, const Skeleton& skeleton) {
  const std::size_t n = name.size();
  for (const auto& [word, side] :
       {std::pair{"Left", JointSide::Left}, std::pair{"left", JointSide::Left},
        std::pair{"LEFT", JointSide::Left}, std::pair{"Right", JointSide::Right},
        std::pair{"right", JointSide::Right}, std::pair{"RIGHT", JointSide::Right}}) {
    if (name.find(word) != std::string::npos) return side;
  }
  if (n < 2) return JointSide::Center;
  const auto letter_side = [](char c) {
    return c == 'L' || c == 'l'   ? JointSide::Left
           : c == 'R' || c == 'r' ? JointSide::Right
                                  : JointSide::Center;
  };
  // "L_Arm", "l.arm", "Arm_L", "arm.r".
  if (is_separator(name[1]) && letter_side(name[0]) != JointSide::Center)
    return letter_side(name[0]);
  if (is_separator(name[n - 2]) && letter_side(name[n - 1]) != JointSide::Center)
    return letter_side(name[n - 1]);
  // "LHipJoint", "lfemur": only beside a mirrored "RHipJoint", "rfemur" ("lowerback" has none).
  const JointSide first = letter_side(name[0]);
  if (first != JointSide::Center) {
    std::string mirror = name;
    const bool upper = is_upper(name[0]);
    mirror[0] = first == JointSide::Left ? (upper ? 'R' : 'r') : (upper ? 'L' : 'l');
    if (skeleton.find(mirror) >= 0) return first;
  }
  return JointSide::Center;
}

}  // namespace

std::vector<JointSide> joint_sides(const Skeleton& skeleton) {
  std::vector<JointSide> out(std::size_t(skeleton.num_joints()), JointSide::Center);
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    const Joint& joint = skeleton.joints[std::size_t(j)];
    JointSide side = marked_side(joint.name, skeleton);
    if (side == JointSide::Center && joint.parent >= 0) side = out[std::size_t(joint.parent)];
    out[std::size_t(j)] = side;
  }
  return out;
}

Eigen::Vector3f side_color(JointSide side, bool bone) {
  Eigen::Vector3f c;
  switch (side) {
    case JointSide::Left:
      c = {0.20f, 0.45f, 0.90f};
      break;
    case JointSide::Right:
      c = {0.88f, 0.27f, 0.22f};
      break;
    case JointSide::Center:
      c = {0.80f, 0.62f, 0.30f};
      break;
  }
  // Bones: the joint's hue, lighter, so joints stand out on them.
  return bone ? Eigen::Vector3f(c + 0.45f * (Eigen::Vector3f::Ones() - c)) : c;
}

double pose_extent(const WorldPose& pose) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const auto* points : {&pose.positions, &pose.end_sites}) {
    for (const auto& p : *points) {
      if (!p.allFinite()) continue;
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  }
  const double d = (hi - lo).norm();
  return std::isfinite(d) && d > 0.0 ? d : 1.0;
}

}  // namespace motionmap
