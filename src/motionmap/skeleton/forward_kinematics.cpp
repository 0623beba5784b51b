#include "motionmap/skeleton/forward_kinematics.h"

#include <string>

#include "motionmap/core/error.h"

namespace motionmap {

namespace {

// The FK loop, for a skeleton and pose already checked to fit each other.
void world_pose(const Skeleton& skeleton, const PoseView& pose, WorldPose& out) {
  const int n = skeleton.num_joints();
  out.positions.resize(n);
  out.rotations.resize(n);
  out.end_sites.resize(skeleton.num_end_sites());
  std::size_t e = 0;
  for (int j = 0; j < n; ++j) {
    const Joint& joint = skeleton.joints[j];
    if (joint.parent < 0) {
      out.positions[j] = pose.translations[j];
      out.rotations[j] = pose.rotations[j];
    } else {
      const auto& parent_rot = out.rotations[joint.parent];
      out.positions[j] = out.positions[joint.parent] + parent_rot * pose.translations[j];
      out.rotations[j] = parent_rot * pose.rotations[j];
    }
    for (const auto& site : joint.end_sites) {
      out.end_sites[e++] = out.positions[j] + out.rotations[j] * site;
    }
  }
}

}  // namespace

void forward_kinematics(const Skeleton& skeleton, const PoseView& pose, WorldPose& out) {
  check_skeleton(skeleton, "forward_kinematics", MotionCheck::Sizes);
  const auto n = static_cast<std::size_t>(skeleton.num_joints());
  if (pose.rotations.size() != n || pose.translations.size() != n) {
    throw ParameterError("forward_kinematics: the pose has " +
                         std::to_string(pose.rotations.size()) + " rotations and " +
                         std::to_string(pose.translations.size()) + " translations; expected " +
                         std::to_string(n) + " of each (the skeleton's joint count)");
  }
  world_pose(skeleton, pose, out);
}

WorldPose forward_kinematics(const Skeleton& skeleton, const Motion& motion, int frame) {
  check_motion(skeleton, motion, "forward_kinematics", MotionCheck::Sizes);
  if (frame < 0 || frame >= motion.num_frames) {
    throw ParameterError("forward_kinematics: frame " + std::to_string(frame) +
                         " is out of range (the motion has " + std::to_string(motion.num_frames) +
                         " frames)");
  }
  WorldPose out;
  world_pose(skeleton, motion.pose(frame), out);
  return out;
}

Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> world_points(
    const Skeleton& skeleton, const Motion& motion) {
  check_motion(skeleton, motion, "world_points");
  const int joints = skeleton.num_joints();
  const int points = joints + skeleton.num_end_sites();
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> out(motion.num_frames,
                                                                             3 * points);
  WorldPose world;
  for (int f = 0; f < motion.num_frames; ++f) {
    world_pose(skeleton, motion.pose(f), world);
    for (int j = 0; j < joints; ++j) out.row(f).segment<3>(3 * j) = world.positions[j];
    for (std::size_t e = 0; e < world.end_sites.size(); ++e) {
      out.row(f).segment<3>(3 * (joints + static_cast<int>(e))) = world.end_sites[e];
    }
  }
  return out;
}

}  // namespace motionmap
