#include "motionmap/features/point_cloud.h"

#include <cmath>

#include "motionmap/features/detail/point_cloud.h"
#include "motionmap/skeleton/forward_kinematics.h"

namespace motionmap::features {

namespace {
// The floor axes (a, b) in cyclic order after `up`, so that a rotation about `up` by θ takes
// e_a to cos θ·e_a + sin θ·e_b.
std::pair<int, int> floor_axes(Axis up) {
  const int u = static_cast<int>(up);
  return {(u + 1) % 3, (u + 2) % 3};
}
}  // namespace

double heading_angle(const Eigen::Quaterniond& world_rotation, Axis up) {
  const auto [a, b] = floor_axes(up);
  const Eigen::Vector3d ea = Eigen::Vector3d::Unit(a);
  const Eigen::Vector3d eb = Eigen::Vector3d::Unit(b);
  const Eigen::Vector3d va = world_rotation * ea;
  const Eigen::Vector3d vb = world_rotation * eb;
  // For a pure yaw θ: va = (cos θ, sin θ) and vb = (−sin θ, cos θ) in (a, b). Turning vb by −90°
  // maps it onto va's estimate: (vb_b, −vb_a).
  const double ca = va[a] + vb[b];
  const double sa = va[b] - vb[a];
  return std::atan2(sa, ca);
}

namespace detail {

RowMatrix checked_heading_local_points(const Skeleton& skeleton, const Motion& motion, Axis up) {
  const int joints = skeleton.num_joints();
  const int points = joints + skeleton.num_end_sites();
  const int root = motion_root(skeleton, motion);
  const auto [a, b] = floor_axes(up);
  RowMatrix out(motion.num_frames, 3 * points);
  WorldPose world;
  for (int f = 0; f < motion.num_frames; ++f) {
    forward_kinematics(skeleton, motion.pose(f), world);
    const double theta = heading_angle(world.rotations[root], up);
    const Eigen::Matrix3d unturn =
        Eigen::AngleAxisd(-theta, Eigen::Vector3d::Unit(static_cast<int>(up))).toRotationMatrix();
    Eigen::Vector3d origin = Eigen::Vector3d::Zero();
    origin[a] = world.positions[root][a];
    origin[b] = world.positions[root][b];
    auto row = out.row(f);
    for (int j = 0; j < joints; ++j) row.segment<3>(3 * j) = unturn * (world.positions[j] - origin);
    for (std::size_t e = 0; e < world.end_sites.size(); ++e) {
      row.segment<3>(3 * (joints + static_cast<int>(e))) = unturn * (world.end_sites[e] - origin);
    }
  }
  return out;
}

}  // namespace detail

RowMatrix heading_local_points(const Skeleton& skeleton, const Motion& motion, Axis up) {
  check_motion(skeleton, motion, "heading_local_points");
  return detail::checked_heading_local_points(skeleton, motion, up);
}

}  // namespace motionmap::features
