#include "motionmap/features/diagnostics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include "motionmap/core/stats.h"

#include "motionmap/features/detail/point_cloud.h"

namespace motionmap::features {

BindPoseCheck check_leading_bind_pose(const RowMatrix& points, double factor) {
  BindPoseCheck check;
  const auto frames = points.rows();
  if (frames < 3) return check;
  check.distance = (points.row(0) - points.row(1)).norm();
  std::vector<double> steps;
  steps.reserve(static_cast<std::size_t>(frames - 2));
  for (Eigen::Index f = 1; f + 1 < frames; ++f)
    steps.push_back((points.row(f) - points.row(f + 1)).norm());
  // The upper median (for an even count the upper of the two middle steps, not numpy's mean):
  // the bind-pose decision has always used it, and a changed decision would change the maps.
  check.median_step = upper_median(std::move(steps));
  if (check.median_step > 0) {
    check.ratio = check.distance / check.median_step;
  } else {
    check.ratio = check.distance > 0 ? std::numeric_limits<double>::infinity() : 0.0;
  }
  for (Eigen::Index f = 1; f + 1 < frames && f <= kBindPoseLocalSteps; ++f)
    check.local_step = std::max(check.local_step, (points.row(f) - points.row(f + 1)).norm());
  if (check.local_step > 0) {
    check.local_ratio = check.distance / check.local_step;
  } else {
    check.local_ratio = check.distance > 0 ? std::numeric_limits<double>::infinity() : 0.0;
  }
  check.detected = check.ratio > factor && check.local_ratio > kBindPoseLocalFactor * factor;
  return check;
}

namespace {

// find_rotation_flips() of a skeleton and motion already checked.
std::vector<RotationFlip> rotation_flips(const Skeleton& skeleton, const Motion& motion,
                                         double threshold_degrees, int first_frame) {
  std::vector<RotationFlip> flips;
  const double threshold = deg_to_rad(threshold_degrees);
  for (int j = 0; j < skeleton.num_joints(); ++j) {
    RotationFlip flip;
    flip.joint = j;
    for (int f = std::max(first_frame, 0); f + 1 < motion.num_frames; ++f) {
      const double angle = rotation_angle(motion.rotation(f, j), motion.rotation(f + 1, j));
      if (angle > threshold) {
        flip.frames.push_back(f);
        flip.max_degrees = std::max(flip.max_degrees, rad_to_deg(angle));
      }
    }
    if (!flip.frames.empty()) flips.push_back(std::move(flip));
  }
  return flips;
}

}  // namespace

std::vector<RotationFlip> find_rotation_flips(const Skeleton& skeleton, const Motion& motion,
                                              double threshold_degrees, int first_frame) {
  check_motion(skeleton, motion, "find_rotation_flips");
  return rotation_flips(skeleton, motion, threshold_degrees, first_frame);
}

namespace {
std::string format_double(double v, int precision) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", precision, v);
  return buf;
}

std::string frame_pairs(const std::vector<int>& frames, std::size_t shown) {
  std::string out;
  for (std::size_t i = 0; i < frames.size() && i < shown; ++i) {
    if (i) out += ", ";
    out += std::to_string(frames[i]) + "→" + std::to_string(frames[i] + 1);
  }
  if (frames.size() > shown) out += ", … (" + std::to_string(frames.size()) + " in all)";
  return out;
}
}  // namespace

std::vector<std::string> clip_warnings(const Skeleton& skeleton, const Motion& motion, Axis up) {
  check_motion(skeleton, motion, "clip_warnings");
  std::vector<std::string> warnings;
  int first_flip_frame = 0;
  if (motion.num_frames >= 3) {
    const BindPoseCheck bind =
        check_leading_bind_pose(detail::checked_heading_local_points(skeleton, motion, up));
    if (bind.detected) {
      first_flip_frame = 1;
      warnings.push_back(
          "frame 0 looks like a bind pose (T-pose): it is " +
          (std::isfinite(bind.ratio) ? format_double(bind.ratio, 0) + "×"
                                     : std::string("infinitely")) +
          " farther from frame 1 than the median step between frames (CMU's BVH conversions start "
          "with one; `motionmap map` leaves it out unless --keep-first)");
    }
  }
  if (motion.fps() >= 60.0) {
    for (const RotationFlip& flip : rotation_flips(skeleton, motion, 90.0, first_flip_frame)) {
      warnings.push_back("joint '" + skeleton.joints[flip.joint].name + "' rotates by up to " +
                         format_double(flip.max_degrees, 0) + "° between consecutive frames (" +
                         frame_pairs(flip.frames, 5) + "), more than a body can at " +
                         format_double(motion.fps(), 0) +
                         " fps: likely a rotation flip in the data");
    }
  }
  return warnings;
}

}  // namespace motionmap::features
