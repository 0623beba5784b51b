#pragma once
// Forward kinematics: world transforms of every joint and end site, one loop over the
// parent-ordered joints (a parent's world transform is always ready before its children's).
#include <span>
#include <vector>

#include <Eigen/Geometry>

#include "motionmap/skeleton/skeleton.h"

namespace motionmap {

/// World transforms of one frame.
struct WorldPose {
  std::vector<Eigen::Vector3d> positions;     ///< #joints world positions
  std::vector<Eigen::Quaterniond> rotations;  ///< #joints world rotations
  std::vector<Eigen::Vector3d> end_sites;     ///< #end sites world positions, in joint order
};

/// World transforms of `pose` (a frame of a Motion for `skeleton`). `out` is resized as needed, so
/// a caller looping over frames reuses its buffers. Checks sizes and parents only (O(#joints)):
/// non-finite values give non-finite positions.
/// @throws ParameterError if the skeleton fails check_skeleton (MotionCheck::Sizes) or the pose
///         does not hold #joints rotations and translations.
void forward_kinematics(const Skeleton& skeleton, const PoseView& pose, WorldPose& out);

/// Convenience: world transforms of one frame of `motion`. Checks sizes only (O(#joints)).
/// @throws ParameterError if check_motion(…, MotionCheck::Sizes) fails or `frame` is not in
///         [0, #frames).
WorldPose forward_kinematics(const Skeleton& skeleton, const Motion& motion, int frame);

/// World positions of all joints then all end sites, for every frame:
/// #frames by 3·(#joints + #end sites), row f = [x0 y0 z0 x1 y1 z1 …] of frame f.
/// @throws ParameterError or NumericalError if check_motion (MotionCheck::Values) fails.
Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> world_points(
    const Skeleton& skeleton, const Motion& motion);

}  // namespace motionmap
