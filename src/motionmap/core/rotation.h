#pragma once
// Rotation helpers shared by the readers, writers and the maths: axis rotations, Euler angles in an
// explicit order, angle wrapping, quaternion hemisphere hygiene and weighted averages.
//
// Conventions: angles in radians unless a name says degrees; an Euler order lists the axes in the
// order they are written in a file, and the rotation is composed in that order:
// order {Z, Y, X} with angles (a, b, c) means R = Rz(a)·Ry(b)·Rx(c).
#include <array>
#include <optional>
#include <span>
#include <string_view>

#include <Eigen/Geometry>

#include "motionmap/core/names.h"

namespace motionmap {

enum class Axis { X = 0, Y = 1, Z = 2 };

/// The axes' names, as options and map files write them.
inline constexpr EnumName<Axis> kAxisNames[] = {{Axis::X, "x"}, {Axis::Y, "y"}, {Axis::Z, "z"}};
/// "x", "y", "z".
std::string_view axis_name(Axis axis);
/// The axis named `name` ("x", "y" or "z", either case); nullopt for anything else.
std::optional<Axis> parse_axis(std::string_view name);

constexpr double kPi = 3.14159265358979323846;
constexpr double deg_to_rad(double d) {
  return d * (kPi / 180.0);
}
constexpr double rad_to_deg(double r) {
  return r * (180.0 / kPi);
}

/// The angle `radians` wrapped by a multiple of 2π into (−π, π] (e.g. the change between two
/// headings). Exact: std::remainder, then −π moved to π.
double wrap_angle(double radians);

/// The angle `radians` shifted by a multiple of 2π to lie closest to `target` (for angles that
/// follow a previous frame's without ±2π jumps): a + 2π·round((target − a) / 2π).
double wrap_near(double radians, double target);

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

/// Weighted average of k rotations: every q_i is first put in the hemisphere of `reference`
/// (align_hemisphere), then Σ w_i·q_i is normalised. Weights need not be positive nor sum to 1
/// (negative weights of kriging are fine: the sum is only rescaled). When the sum nearly
/// cancels (|Σ w_i·q_i| ≤ 1e-12·|Σ w_i|, e.g. opposite rotations with opposite weights, or k = 0),
/// returns `reference`. Pick as reference one of the rotations (say the one of largest weight),
/// so rotations near it blend the short way round. This is a normalised linear blend (nlerp for
/// k = 2): continuous in the weights and close to the geodesic (Karcher) mean for rotations
/// within a few tens of degrees of each other, but neither that nor Markley's eigenvector mean.
/// The result does not depend on the signs of the q_i.
/// @throws ParameterError if the spans differ in size.
///
///   const std::array<Eigen::Quaterniond, 2> q{a, b};
///   const std::array<double, 2> w{0.25, 0.75};
///   Eigen::Quaterniond mid = weighted_average(q, w, b);  // near slerp(a, b, 0.75)
Eigen::Quaterniond weighted_average(std::span<const Eigen::Quaterniond> rotations,
                                    std::span<const double> weights,
                                    const Eigen::Quaterniond& reference);

/// Angle in radians of the rotation taking a to b, in [0, π]: 2·acos|a·b| for unit quaternions,
/// computed in a form that stays accurate for tiny angles.
double rotation_angle(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b);

}  // namespace motionmap
