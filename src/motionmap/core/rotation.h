#pragma once
// Rotation helpers shared by the readers, writers and the maths: axis rotations, Euler angles in an
// explicit order, quaternion hemisphere hygiene.
//
// Conventions: angles in radians unless a name says degrees; an Euler order lists the axes in the
// order they are written in a file, and the rotation is composed in that order:
// order {Z, Y, X} with angles (a, b, c) means R = Rz(a)·Ry(b)·Rx(c).
#include <array>
#include <span>

#include <Eigen/Geometry>

namespace motionmap {

enum class Axis { X = 0, Y = 1, Z = 2 };

constexpr double kPi = 3.14159265358979323846;
constexpr double deg_to_rad(double d) {
  return d * (kPi / 180.0);
}
constexpr double rad_to_deg(double r) {
  return r * (180.0 / kPi);
}

/// Rotation by `radians` about a coordinate axis.
Eigen::Quaterniond axis_rotation(Axis axis, double radians);

/// R = R(order[0], angles[0]) · R(order[1], angles[1]) · … for any number of axes (repeats
/// allowed).
Eigen::Quaterniond euler_to_quat(std::span<const Axis> order, std::span<const double> radians);

/// Inverse of euler_to_quat for three distinct axes (any of the six Tait–Bryan orders): the angles
/// (a, b, c) with q = R(order[0], a)·R(order[1], b)·R(order[2], c), middle angle in [-π/2, π/2].
/// With `near` given, picks of the two equivalent solutions (and their 2π shifts) the one closest
/// to `near`, so a frame-by-frame decomposition has no ±180° jumps.
Eigen::Vector3d quat_to_euler(const Eigen::Quaterniond& q, const std::array<Axis, 3>& order,
                              const Eigen::Vector3d* near = nullptr);

/// q or −q, whichever lies in the hemisphere of `reference` (non-negative dot product).
inline Eigen::Quaterniond align_hemisphere(const Eigen::Quaterniond& q,
                                           const Eigen::Quaterniond& reference) {
  return q.dot(reference) < 0.0 ? Eigen::Quaterniond(-q.w(), -q.x(), -q.y(), -q.z()) : q;
}

/// Angle in radians of the rotation taking a to b, in [0, π]: 2·acos|a·b| for unit quaternions,
/// computed in a form that stays accurate for tiny angles.
double rotation_angle(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b);

}  // namespace motionmap
