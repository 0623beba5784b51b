#include "motionmap/synth/detail/root_motion.h"

#include <algorithm>
#include <limits>

#include "motionmap/features/point_cloud.h"

namespace motionmap::synth::detail {

int shared_motion_root(std::span<const Clip> clips) {
  int root = std::numeric_limits<int>::max();
  for (const Clip& clip : clips) root = std::min(root, motion_root(clip.skeleton, clip.motion));
  return root;
}

Eigen::Quaterniond remove_heading(const Eigen::Quaterniond& q, Axis up) {
  return (axis_rotation(up, -features::heading_angle(q, up)) * q).normalized();
}

RootSample root_sample(const Motion& motion, int frame, int root, Axis up) {
  RootSample s;
  const Eigen::Quaterniond q = motion.rotation(frame, root).normalized();
  s.tilt = remove_heading(q, up);
  s.height = motion.translation(frame, root).dot(Eigen::Vector3d::Unit(static_cast<int>(up)));
  // Forward difference from frame a to b = a + 1.
  const int f = frame, frames = motion.num_frames;
  const int a = frames == 1 ? f : (f + 1 < frames ? f : f - 1);
  const int b = frames == 1 ? f : a + 1;
  const double ha = features::heading_angle(motion.rotation(a, root).normalized(), up);
  const double hb = features::heading_angle(motion.rotation(b, root).normalized(), up);
  const double dt = motion.frame_time;
  Eigen::Vector3d floor = motion.translation(b, root) - motion.translation(a, root);
  floor[static_cast<int>(up)] = 0.0;
  s.velocity = axis_rotation(up, -ha) * floor / dt;
  s.yaw_rate = wrap_angle(hb - ha) / dt;
  return s;
}

}  // namespace motionmap::synth::detail
