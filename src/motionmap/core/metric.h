#pragma once
// The distance between two poses given as rows of a point matrix, as every stage computes it:
// the entries of the dense distance matrix D, the neighbour searches and landmark distances of
// the scalable maps, and the placement of new frames all call these, so they agree to the bit.
//
//   double d = pose_distance(points.row(i), points.row(j), Metric::Euclidean);
#include <optional>
#include <string_view>

#include <Eigen/Core>

#include "motionmap/core/names.h"

namespace motionmap {

/// Rows are frames: #frames by #values, row-major so a frame is contiguous.
using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
/// One frame's values.
using PoseRow = Eigen::Ref<const Eigen::RowVectorXd>;

enum class Metric {
  /// ‖a − b‖: point clouds, or any feature vector.
  Euclidean,
  /// sqrt(Σ_j θ_j²) over 4-value blocks read as unit quaternions (w, x, y, z), θ_j the angle of
  /// the rotation between the two: the geodesic distance of joint rotations.
  QuaternionAngles,
};

/// The metrics' names, as map files write them.
inline constexpr EnumName<Metric> kMetricNames[] = {
    {Metric::Euclidean, "euclidean"}, {Metric::QuaternionAngles, "quaternion-angles"}};
/// "euclidean", "quaternion-angles".
std::string_view metric_name(Metric metric);
/// The metric named `name` (metric_name's names); nullopt for anything else.
std::optional<Metric> parse_metric(std::string_view name);

/// ‖a − b‖.
inline double euclidean_distance(PoseRow a, PoseRow b) {
  return (a - b).norm();
}

/// sqrt(Σ_j θ_j²), see Metric::QuaternionAngles. a and b hold 4·#joints values.
double quaternion_angle_distance(PoseRow a, PoseRow b);

inline double pose_distance(PoseRow a, PoseRow b, Metric metric) {
  return metric == Metric::Euclidean ? euclidean_distance(a, b) : quaternion_angle_distance(a, b);
}

}  // namespace motionmap
