#include "motionmap/core/metric.h"

#include <cmath>

#include <Eigen/Geometry>

#include "motionmap/core/names.h"
#include "motionmap/core/rotation.h"

namespace motionmap {

std::string_view metric_name(Metric metric) {
  return enum_name(kMetricNames, metric);
}

std::optional<Metric> parse_metric(std::string_view name) {
  return parse_enum(kMetricNames, name);
}

double quaternion_angle_distance(PoseRow a, PoseRow b) {
  double sum = 0.0;
  for (Eigen::Index k = 0; k < a.cols() / 4; ++k) {
    const auto qa = a.segment<4>(4 * k);
    const auto qb = b.segment<4>(4 * k);
    const double theta = rotation_angle(Eigen::Quaterniond(qa[0], qa[1], qa[2], qa[3]),
                                        Eigen::Quaterniond(qb[0], qb[1], qb[2], qb[3]));
    sum += theta * theta;
  }
  return std::sqrt(sum);
}

}  // namespace motionmap
