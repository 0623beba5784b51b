#include "motionmap/synth/detail/root_motion.h"

#include "motionmap/features/point_cloud.h"
#include "motionmap/synth/blend_state.h"

namespace motionmap::synth::detail {

Eigen::Quaterniond remove_heading(const Eigen::Quaterniond& q, Axis up) {
  return (axis_rotation(up, -features::heading_angle(q, up)) * q).normalized();
}

RootSample root_sample(const Motion& motion, int frame, int root, Axis up,
                       std::span<const int> ancestors) {
  RootSample s;
  const RootTransform at = root_transform(motion, frame, root, ancestors);
  s.tilt = remove_heading(at.rotation.normalized(), up);
  s.height = at.translation.dot(Eigen::Vector3d::Unit(static_cast<int>(up)));
  // Forward difference from frame a to b = a + 1.
  const int f = frame, frames = motion.num_frames;
  const int a = frames == 1 ? f : (f + 1 < frames ? f : f - 1);
  const int b = frames == 1 ? f : a + 1;
  const RootTransform ta = root_transform(motion, a, root, ancestors);
  const RootTransform tb = root_transform(motion, b, root, ancestors);
  const double ha = features::heading_angle(ta.rotation.normalized(), up);
  const double hb = features::heading_angle(tb.rotation.normalized(), up);
  const double dt = motion.frame_time;
  Eigen::Vector3d floor = tb.translation - ta.translation;
  floor[static_cast<int>(up)] = 0.0;
  s.velocity = axis_rotation(up, -ha) * floor / dt;
  s.yaw_rate = wrap_angle(hb - ha) / dt;
  return s;
}

}  // namespace motionmap::synth::detail
