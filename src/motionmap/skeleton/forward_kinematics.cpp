#include "motionmap/skeleton/forward_kinematics.h"

namespace motionmap {

void forward_kinematics(const Skeleton& skeleton, const PoseView& pose, WorldPose& out) {
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

WorldPose forward_kinematics(const Skeleton& skeleton, const Motion& motion, int frame) {
  WorldPose out;
  forward_kinematics(skeleton, motion.pose(frame), out);
  return out;
}

Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> world_points(
    const Skeleton& skeleton, const Motion& motion) {
  const int joints = skeleton.num_joints();
  const int points = joints + skeleton.num_end_sites();
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> out(motion.num_frames,
                                                                             3 * points);
  WorldPose world;
  for (int f = 0; f < motion.num_frames; ++f) {
    forward_kinematics(skeleton, motion.pose(f), world);
    for (int j = 0; j < joints; ++j) out.row(f).segment<3>(3 * j) = world.positions[j];
    for (std::size_t e = 0; e < world.end_sites.size(); ++e) {
      out.row(f).segment<3>(3 * (joints + static_cast<int>(e))) = world.end_sites[e];
    }
  }
  return out;
}

}  // namespace motionmap
