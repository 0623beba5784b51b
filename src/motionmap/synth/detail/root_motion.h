#pragma once
// Root motion of a sample frame, split the way the blender blends it: the motion root's heading
// (yaw about the up axis) and floor position are not blended but integrated (synthesize()), from
// the heading-local floor velocity and the yaw rate; its height along the up axis and its tilt
// (the rotation with the heading removed) are blended like the other joints.
//
//   const RootSample r = root_sample(clip.motion, f, blender_root, Axis::Y);
//   // r.tilt: no heading; r.velocity: units/s in the heading frame (up component 0)
#include <span>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "motionmap/core/rotation.h"
#include "motionmap/skeleton/skeleton.h"

namespace motionmap::synth::detail {

/// One frame's root motion (see the top of the file).
struct RootSample {
  /// The root's rotation with its heading removed (heading_angle(tilt, up) = 0).
  Eigen::Quaterniond tilt = Eigen::Quaterniond::Identity();
  /// The root's translation along the up axis.
  double height = 0.0;
  /// Floor velocity in the frame's own heading frame, units per second (up component 0).
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  /// Heading change per second about the up axis, radians (the change wrapped to (−π, π]).
  double yaw_rate = 0.0;
};

/// `q` with its heading about `up` removed: yaw(−heading_angle(q, up))·q, normalised.
Eigen::Quaterniond remove_heading(const Eigen::Quaterniond& q, Axis up);

/// Root motion of frame f of `motion` at joint `root`, its `ancestors` folded in (root_transform
/// in blend_state.h). Velocity and yaw rate are forward differences to the next frame (the last
/// frame repeats its predecessor's; a one-frame motion stands still), so integrating a clip's own
/// samples retraces the clip exactly.
RootSample root_sample(const Motion& motion, int frame, int root, Axis up,
                       std::span<const int> ancestors = {});

}  // namespace motionmap::synth::detail
