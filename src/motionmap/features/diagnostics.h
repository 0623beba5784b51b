#pragma once
// Findings about a clip that users of real data need to know before mapping it: a leading bind
// pose (CMU's BVH conversions start with a T-pose frame) and joints whose rotation flips between
// consecutive frames (CMU's thumbs flip by ~180°).
#include <string>
#include <vector>

#include "motionmap/features/point_cloud.h"

namespace motionmap::features {

struct BindPoseCheck {
  bool detected = false;
  double distance = 0.0;     ///< point-cloud distance between frames 0 and 1
  double median_step = 0.0;  ///< median point-cloud distance between later consecutive frames
  double ratio = 0.0;        ///< distance / median_step (infinite if the rest of the clip is still)
  /// The largest of the next kBindPoseLocalSteps steps (frames 1–2, 2–3, 3–4).
  double local_step = 0.0;
  double local_ratio = 0.0;  ///< distance / local_step (infinite if those frames are still)
};

/// Steps right after frame 0 that a bind pose's jump must also exceed, kBindPoseLocalFactor ×
/// `factor` times (CMU's bind poses: 50–950× the next steps; synthesized clips that leave the
/// data at once, where the blend extrapolates: up to 12×).
inline constexpr int kBindPoseLocalSteps = 3;
inline constexpr double kBindPoseLocalFactor = 2.0;

/// Frame 0 is a leading bind pose when its point-cloud distance to frame 1 exceeds `factor` × the
/// median distance between the following consecutive frames (frames 1–2, 2–3, …) and
/// kBindPoseLocalFactor × `factor` × the largest of the next kBindPoseLocalSteps of them: a jump
/// out of frame 0 that the motion does not go on with. (A clip that moves at its start and then
/// stands nearly still — a synthesized path held at the data's edge, a capture that ends in a long
/// hold — has a large first step against its median, but its next steps are as large.) `points` is
/// #frames by 3·#points, e.g. heading_local_points(). Needs ≥ 3 frames, else never detected.
BindPoseCheck check_leading_bind_pose(const RowMatrix& points, double factor = 10.0);

struct RotationFlip {
  int joint = -1;
  std::vector<int>
      frames;  ///< f such that the joint's rotation changes by > threshold from f to f+1
  double max_degrees = 0.0;
};

/// Joints whose local rotation changes by more than `threshold_degrees` between consecutive
/// frames from `first_frame` on. Only meaningful at high frame rates (≥ 60 fps), where real
/// motion never does that.
/// @throws ParameterError or NumericalError if check_motion (MotionCheck::Values) fails.
std::vector<RotationFlip> find_rotation_flips(const Skeleton& skeleton, const Motion& motion,
                                              double threshold_degrees = 90.0, int first_frame = 0);

/// Human-readable warnings for a clip: the bind pose check and, at ≥ 60 fps, rotation flips,
/// each naming the frames (0-based, as in the file's motion rows). The jump out of a detected
/// bind pose is not reported as a flip.
/// @throws ParameterError or NumericalError if check_motion (MotionCheck::Values) fails.
std::vector<std::string> clip_warnings(const Skeleton& skeleton, const Motion& motion,
                                       Axis up = Axis::Y);

}  // namespace motionmap::features
