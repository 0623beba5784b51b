#include "motionmap/synth/detail/root_motion.h"

#include <algorithm>
#include <cmath>

#include "motionmap/core/error.h"
#include "motionmap/features/point_cloud.h"
#include "motionmap/synth/blend_state.h"

namespace motionmap::synth::detail {

Eigen::Quaterniond remove_heading(const Eigen::Quaterniond& q, Axis up) {
  return (axis_rotation(up, -features::heading_angle(q, up)) * q).normalized();
}

namespace {

double heading_at(const Motion& motion, int frame, int root, Axis up,
                  std::span<const int> ancestors) {
  return features::heading_angle(
      root_transform(motion, frame, root, ancestors).rotation.normalized(), up);
}

// The sway of frame f, whose heading is `at`: minus the mean of the headings (relative to `at`)
// of the frames f + round(j·w/kTurnSamples), j = −kTurnSamples … kTurnSamples, in the motion,
// with w = kTurnSeconds in frames. Each is unwrapped from its neighbour nearer f, so a spin faster
// than half a turn over the window still averages what it turned.
double sway(const Motion& motion, int f, double at, int root, Axis up,
            std::span<const int> ancestors) {
  const double wide = kTurnSeconds / motion.frame_time;  // frames
  const double w = std::isfinite(wide) && wide > 0.0
                       ? std::min(wide, static_cast<double>(motion.num_frames))
                       : 0.0;
  double sum = 0.0;
  int count = 1;  // frame f itself, at 0
  for (const int side : {-1, 1}) {
    long last = f;
    double heading = at, relative = 0.0;
    for (int j = 1; j <= kTurnSamples; ++j) {
      const long g = f + side * std::lround(j * w / kTurnSamples);
      if (g < 0 || g >= motion.num_frames) break;
      if (g == last) {
        sum += relative;
      } else {
        const double h = heading_at(motion, static_cast<int>(g), root, up, ancestors);
        relative += wrap_angle(h - heading);
        heading = h;
        last = g;
        sum += relative;
      }
      ++count;
    }
  }
  return -sum / count;
}

}  // namespace

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
  // The turning's change from a to b: the heading's less the sway's.
  const double sway_a = sway(motion, a, ha, root, up, ancestors);
  const double sway_b = b == a ? sway_a : sway(motion, b, hb, root, up, ancestors);
  s.yaw_rate = (wrap_angle(hb - ha) - (sway_b - sway_a)) / dt;
  s.heading_offset = f == a ? sway_a : sway_b;
  return s;
}

double planted_weight(double share) {
  return std::clamp((share - kFollowShare) / (1.0 - kFollowShare), 0.0, 1.0);
}

std::vector<FeetFrame> feet_frames(const Skeleton& skeleton, const Motion& motion, int root,
                                   const Feet& feet,
                                   std::span<const std::array<double, 2>> shares) {
  if (shares.size() != static_cast<std::size_t>(motion.num_frames)) {
    throw ParameterError("feet_frames: " + std::to_string(shares.size()) + " contact shares for " +
                         std::to_string(motion.num_frames) + " frames");
  }
  const std::vector<Eigen::Vector3d> at = joint_trajectory(skeleton, motion, root);
  std::vector<FeetFrame> out(shares.size());
  for (int side = 0; side < 2; ++side) {
    const Leg& leg = feet.legs[static_cast<std::size_t>(side)];
    const double slack = (skeleton.joints[static_cast<std::size_t>(leg.knee)].offset.norm() +
                          skeleton.joints[static_cast<std::size_t>(leg.ankle)].offset.norm()) *
                         motion.frame_time;
    const std::vector<Eigen::Vector3d> ankle = joint_trajectory(skeleton, motion, leg.ankle);
    for (std::size_t k = 0; k < out.size(); ++k) {
      out[k].ankle[side] = ankle[k] - at[k];
      out[k].planted[side] = planted_weight(shares[k][side]);
      out[k].slack[side] = slack;
    }
  }
  return out;
}

Eigen::Vector3d root_step(const Eigen::Vector3d& blended, const Eigen::Quaterniond& yaw,
                          const Eigen::Quaterniond& next_yaw, const FeetFrame& now,
                          const FeetFrame& next, Axis up) {
  const int u = static_cast<int>(up);
  double total = 0.0;
  Eigen::Vector3d by_feet = Eigen::Vector3d::Zero();
  for (int side = 0; side < 2; ++side) {
    const double w = std::min(now.planted[side], next.planted[side]);
    if (w <= 0.0) continue;
    Eigen::Vector3d step = yaw * now.ankle[side] - next_yaw * next.ankle[side];
    step[u] = 0.0;
    if ((step - blended).norm() > blended.norm() + now.slack[side]) continue;
    by_feet += w * step;
    total += w;
  }
  if (total <= 0.0) return blended;
  const double share = std::min(1.0, total);
  return (1.0 - share) * blended + share * by_feet / total;
}

RootState integrate_root(RootState start, std::span<const Eigen::Vector3d> velocity,
                         std::span<const double> yaw_rate, std::span<const double> heading_offset,
                         double dt, std::span<const FeetFrame> standing, Axis up,
                         std::span<Eigen::Vector3d> positions, std::span<double> headings) {
  RootState at = start;
  for (std::size_t i = 0; i < velocity.size(); ++i) {
    positions[i] = at.position;
    headings[i] = at.heading + heading_offset[i];
    const Eigen::Quaterniond yaw = axis_rotation(up, headings[i]);
    const double next_heading = at.heading + yaw_rate[i] * dt;
    const Eigen::Vector3d blended = yaw * velocity[i] * dt;
    at.position +=
        i + 1 >= standing.size()
            ? blended
            : root_step(blended, yaw, axis_rotation(up, next_heading + heading_offset[i + 1]),
                        standing[i], standing[i + 1], up);
    at.heading = next_heading;
  }
  return at;
}

}  // namespace motionmap::synth::detail
