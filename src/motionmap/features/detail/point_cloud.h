#pragma once
// Inside the features stage only: heading_local_points() without its check_motion() pass, for
// build_features() and select_samples(), which check every clip once (with its path in the
// messages) before computing its point cloud — one pass over the data, not two.
#include "motionmap/features/point_cloud.h"

namespace motionmap::features::detail {

/// heading_local_points() of a skeleton and motion that passed check_motion()
/// (MotionCheck::Values).
RowMatrix checked_heading_local_points(const Skeleton& skeleton, const Motion& motion, Axis up);

}  // namespace motionmap::features::detail
