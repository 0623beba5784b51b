#pragma once
// Frames that repeat a pose. A looped cycle, a held pose, keyframed or game animation repeat
// poses exactly, or to the rounding of a file's decimals; in a k-NN graph every such frame's
// nearest neighbours are its own copies at distance ~0, so the graph falls apart into islands of
// copies and the automatic heat kernel width (a median of k-NN distances) becomes 0. The graph
// methods therefore map each distinct pose once and give every repeat its first occurrence's place
// (embed.cpp).
//
// The rule, the same on both paths: frame f repeats the earliest first occurrence r < f within
// τ = kRepeatTolerance·s of it, where s = sqrt(Σ_ij d_ij² / (2·#frames²)) is the data's scale
// (for Euclidean points, the RMS distance of the frames to their mean); a frame that repeats none
// is a first occurrence. τ is far below any two poses of a capture (the closest two frames of the
// shared CMU, Bandai, MocapBank and PyMO takes are ≥ 6·10⁻⁴·s apart; tests/embed/distinct_test.cpp)
// and above the rounding of a file's decimals (`motionmap sample --kind walk --seconds 600` written
// to BVH: its 72 000 frames are 120 poses to within τ).
#include <vector>

#include <Eigen/Core>

#include "motionmap/core/control.h"
#include "motionmap/core/metric.h"
#include "motionmap/embed/points.h"

namespace motionmap::embed {

/// The distinct poses among #frames frames.
struct DistinctPoses {
  std::vector<int> first;    ///< per distinct pose: the frame it first appears at (ascending)
  std::vector<int> pose_of;  ///< per frame: its pose, an index into `first`
  /// Frames that repeat an earlier frame's pose.
  int repeats() const { return static_cast<int>(pose_of.size() - first.size()); }
};

/// Frames within kRepeatTolerance times the data's scale are one pose.
constexpr double kRepeatTolerance = 1e-6;

/// The distinct poses of `points` (#frames rows, in their metric). @throws Cancelled.
DistinctPoses distinct_rows(const PointSet& points, const Control& control = {});

/// The distinct poses of the frames of a distance matrix D (#frames by #frames).
/// @throws Cancelled.
DistinctPoses distinct_in_distances(const Eigen::MatrixXd& D, const Control& control = {});

}  // namespace motionmap::embed
