#pragma once
// The heading-local point cloud of a pose: world positions of every joint and end site after
// removing the root's floor translation and its heading (yaw about the up axis) — Kovar-style
// point clouds without the pairwise alignment search. Two frames' clouds are comparable however
// the performer travelled or turned.
#include <Eigen/Core>

#include "motionmap/core/metric.h"
#include "motionmap/core/rotation.h"
#include "motionmap/skeleton/skeleton.h"

namespace motionmap::features {

using motionmap::RowMatrix;

/// Heading (yaw about `up`, radians) of a world rotation: the angle that rotates the reference
/// frame's floor axes onto the rotation's, averaged over both floor axes so it stays defined when
/// the body bends far forward or sideways.
double heading_angle(const Eigen::Quaterniond& world_rotation, Axis up = Axis::Y);

/// #frames by 3·(#joints + #end sites): row f holds frame f's joint then end-site positions with
/// the motion root's (see motion_root()) floor position moved to the origin and its heading
/// turned to zero. Height along `up` is kept.
/// @throws ParameterError or NumericalError if check_motion (MotionCheck::Values) fails: the
///         motion does not fit the skeleton, or holds NaN, infinite or zero values.
RowMatrix heading_local_points(const Skeleton& skeleton, const Motion& motion, Axis up = Axis::Y);

}  // namespace motionmap::features
