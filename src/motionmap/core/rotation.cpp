#include "motionmap/core/rotation.h"

#include <cmath>
#include <string>

#include "motionmap/core/error.h"
#include "motionmap/core/names.h"

namespace motionmap {

std::string_view axis_name(Axis axis) {
  return enum_name(kAxisNames, axis);
}

std::optional<Axis> parse_axis(std::string_view name) {
  if (name.size() == 1 && name[0] >= 'X' && name[0] <= 'Z') {
    const char lower[1] = {static_cast<char>(name[0] - 'X' + 'x')};
    return parse_enum(kAxisNames, std::string_view(lower, 1));
  }
  return parse_enum(kAxisNames, name);
}

Eigen::Quaterniond axis_rotation(Axis axis, double radians) {
  const double h = 0.5 * radians;
  const double s = std::sin(h);
  switch (axis) {
    case Axis::X:
      return {std::cos(h), s, 0.0, 0.0};
    case Axis::Y:
      return {std::cos(h), 0.0, s, 0.0};
    case Axis::Z:
      return {std::cos(h), 0.0, 0.0, s};
  }
  return Eigen::Quaterniond::Identity();
}

Eigen::Quaterniond euler_to_quat(std::span<const Axis> order, std::span<const double> radians) {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  for (std::size_t i = 0; i < order.size() && i < radians.size(); ++i) {
    q = q * axis_rotation(order[i], radians[i]);
  }
  return q.normalized();
}

double wrap_angle(double radians) {
  const double a = std::remainder(radians, 2.0 * kPi);
  return a <= -kPi ? a + 2.0 * kPi : a;
}

double wrap_near(double radians, double target) {
  return radians + 2.0 * kPi * std::round((target - radians) / (2.0 * kPi));
}

Eigen::Vector3d quat_to_euler(const Eigen::Quaterniond& q, const std::array<Axis, 3>& order,
                              const Eigen::Vector3d* near) {
  const int i = static_cast<int>(order[0]);
  const int j = static_cast<int>(order[1]);
  const int k = static_cast<int>(order[2]);
  // s = +1 for the cyclic orders (XYZ, YZX, ZXY), −1 for the others. For R = Ri(a)Rj(b)Rk(c):
  //   R(i,k) = s·sin b,  tan a = −s·R(j,k) / R(k,k),  tan c = −s·R(i,j) / R(i,i).
  const double s = ((j - i + 3) % 3 == 1) ? 1.0 : -1.0;
  const Eigen::Matrix3d R = q.normalized().toRotationMatrix();
  // cos b from the other two entries of row i, and b by atan2: asin(s·R(i,k)) alone loses
  // precision near ±90°.
  const double cb = std::sqrt(R(i, i) * R(i, i) + R(i, j) * R(i, j));
  double a, b = std::atan2(s * R(i, k), cb), c;
  if (cb > 1e-9) {
    a = std::atan2(-s * R(j, k), R(k, k));
    c = std::atan2(-s * R(i, j), R(i, i));
  } else {
    // Gimbal lock: only a ± c is defined; put it all in a (c = 0). Column j of R is Ri(a)·e_j.
    c = 0.0;
    a = std::atan2(s * R(k, j), R(j, j));
  }
  Eigen::Vector3d first(a, b, c);
  if (!near) return first;
  // The other solution of the same rotation: (a + π, π − b, c + π).
  Eigen::Vector3d second(a + kPi, kPi - b, c + kPi);
  for (Eigen::Vector3d* v : {&first, &second}) {
    for (int n = 0; n < 3; ++n) (*v)[n] = wrap_near((*v)[n], (*near)[n]);
  }
  return (first - *near).squaredNorm() <= (second - *near).squaredNorm() ? first : second;
}

Eigen::Quaterniond weighted_average(std::span<const Eigen::Quaterniond> rotations,
                                    std::span<const double> weights,
                                    const Eigen::Quaterniond& reference) {
  if (rotations.size() != weights.size()) {
    throw ParameterError("weighted_average: " + std::to_string(rotations.size()) +
                         " rotations but " + std::to_string(weights.size()) + " weights");
  }
  const Eigen::Vector4d& r = reference.coeffs();
  Eigen::Vector4d sum = Eigen::Vector4d::Zero();
  double total = 0.0;
  for (std::size_t i = 0; i < rotations.size(); ++i) {
    const Eigen::Vector4d& c = rotations[i].coeffs();
    sum += (c.dot(r) < 0.0 ? -weights[i] : weights[i]) * c;
    total += weights[i];
  }
  const double norm = sum.norm();
  return norm > 1e-12 * std::abs(total) ? Eigen::Quaterniond(sum / norm) : reference;
}

double rotation_angle(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  // 2·acos|a·b| loses half the digits near 0 (acos(1 − ε) ≈ √(2ε)); the atan2 form of the
  // relative rotation a⁻¹·b is accurate at every angle.
  const Eigen::Quaterniond d = a.conjugate() * b;
  return 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
}

}  // namespace motionmap
