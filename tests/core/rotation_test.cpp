#include "motionmap/core/rotation.h"

#include <array>
#include <random>

#include <gtest/gtest.h>

namespace motionmap {
namespace {

constexpr std::array<std::array<Axis, 3>, 6> kOrders = {{{Axis::X, Axis::Y, Axis::Z},
                                                         {Axis::X, Axis::Z, Axis::Y},
                                                         {Axis::Y, Axis::X, Axis::Z},
                                                         {Axis::Y, Axis::Z, Axis::X},
                                                         {Axis::Z, Axis::X, Axis::Y},
                                                         {Axis::Z, Axis::Y, Axis::X}}};

Eigen::Matrix3d axis_matrix(Axis a, double r) {
  return Eigen::AngleAxisd(r, Eigen::Vector3d::Unit(static_cast<int>(a))).toRotationMatrix();
}

TEST(Rotation, EulerComposesInWrittenOrder) {
  // "Zrotation Yrotation Xrotation" with (a, b, c) means R = Rz(a)·Ry(b)·Rx(c).
  const std::array<Axis, 3> zyx{Axis::Z, Axis::Y, Axis::X};
  const std::array<double, 3> angles{0.3, -0.7, 1.1};
  const Eigen::Matrix3d expected =
      axis_matrix(Axis::Z, 0.3) * axis_matrix(Axis::Y, -0.7) * axis_matrix(Axis::X, 1.1);
  EXPECT_TRUE(euler_to_quat(zyx, angles).toRotationMatrix().isApprox(expected, 1e-14));
}

TEST(Rotation, EulerOfNinetyDegreesAboutZTurnsXIntoY) {
  const std::array<Axis, 1> z{Axis::Z};
  const std::array<double, 1> a{deg_to_rad(90)};
  const Eigen::Vector3d v = euler_to_quat(z, a) * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(v.x(), 0.0, 1e-15);
  EXPECT_NEAR(v.y(), 1.0, 1e-15);
}

TEST(Rotation, QuatToEulerInvertsEveryOrder) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> any(-3.1, 3.1), mid(-1.5, 1.5);
  for (const auto& order : kOrders) {
    for (int trial = 0; trial < 200; ++trial) {
      const std::array<double, 3> angles{any(rng), mid(rng), any(rng)};
      const Eigen::Quaterniond q = euler_to_quat(order, angles);
      const Eigen::Vector3d back = quat_to_euler(q, order);
      const std::array<double, 3> back_arr{back[0], back[1], back[2]};
      EXPECT_LT(rotation_angle(q, euler_to_quat(order, back_arr)), 1e-9);
      EXPECT_NEAR(back[0], angles[0], 1e-9);
      EXPECT_NEAR(back[1], angles[1], 1e-9);
      EXPECT_NEAR(back[2], angles[2], 1e-9);
    }
  }
}

TEST(Rotation, QuatToEulerHandlesGimbalLock) {
  for (const auto& order : kOrders) {
    const std::array<double, 3> angles{0.4, kPi / 2, 0.0};
    const Eigen::Quaterniond q = euler_to_quat(order, angles);
    const Eigen::Vector3d back = quat_to_euler(q, order);
    const std::array<double, 3> back_arr{back[0], back[1], back[2]};
    EXPECT_LT(rotation_angle(q, euler_to_quat(order, back_arr)), 1e-7);
  }
}

TEST(Rotation, QuatToEulerNearKeepsAnglesContinuous) {
  // A joint turning steadily about Z past ±180°: with `near` the angles keep growing instead of
  // wrapping to −180°, so an exported clip has no jumps.
  const std::array<Axis, 3> zyx{Axis::Z, Axis::Y, Axis::X};
  Eigen::Vector3d previous(0, 0, 0);
  for (int i = 0; i <= 400; ++i) {
    const double a = deg_to_rad(i * 1.0);
    const std::array<double, 3> angles{a, 0.2, 0.1};
    const Eigen::Vector3d e = quat_to_euler(euler_to_quat(zyx, angles), zyx, &previous);
    EXPECT_NEAR(e[0], a, 1e-9);
    EXPECT_NEAR(e[1], 0.2, 1e-9);
    previous = e;
  }
}

TEST(Rotation, AngleAndHemisphere) {
  const Eigen::Quaterniond a = axis_rotation(Axis::Y, 0.5);
  const Eigen::Quaterniond minus_a(-a.w(), -a.x(), -a.y(), -a.z());
  EXPECT_NEAR(rotation_angle(a, minus_a), 0.0, 1e-7);  // q and −q are one rotation
  EXPECT_NEAR(rotation_angle(Eigen::Quaterniond::Identity(), a), 0.5, 1e-12);
  EXPECT_GE(align_hemisphere(minus_a, a).dot(a), 0.0);
}

}  // namespace
}  // namespace motionmap
