#include "motionmap/core/rotation.h"

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "motionmap/core/error.h"

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

TEST(Rotation, WrapAngleIntoMinusPiPi) {
  EXPECT_EQ(wrap_angle(0.0), 0.0);
  EXPECT_EQ(wrap_angle(kPi), kPi);
  EXPECT_EQ(wrap_angle(-kPi), kPi);  // the interval is (−π, π]
  EXPECT_NEAR(wrap_angle(3 * kPi), kPi, 1e-15);
  EXPECT_NEAR(wrap_angle(1.5 * kPi), -0.5 * kPi, 1e-15);
  EXPECT_NEAR(wrap_angle(-1.5 * kPi), 0.5 * kPi, 1e-15);
  EXPECT_NEAR(wrap_angle(0.3 - 40 * kPi), 0.3, 1e-13);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> any(-100.0, 100.0);
  for (int i = 0; i < 1000; ++i) {
    const double a = any(rng), w = wrap_angle(a);
    EXPECT_GT(w, -kPi);
    EXPECT_LE(w, kPi);
    const double turns = (a - w) / (2 * kPi);
    EXPECT_NEAR(turns, std::round(turns), 1e-12);
  }
}

TEST(Rotation, WrapNearPicksTheClosestTurn) {
  EXPECT_NEAR(wrap_near(deg_to_rad(-170), deg_to_rad(175)), deg_to_rad(190), 1e-12);
  EXPECT_NEAR(wrap_near(0.1, 4 * kPi), 4 * kPi + 0.1, 1e-12);
  EXPECT_EQ(wrap_near(0.1, 0.2), 0.1);
}

TEST(Rotation, WeightedAverageOfOneOrEqualRotations) {
  const Eigen::Quaterniond a = axis_rotation(Axis::Y, 0.7) * axis_rotation(Axis::X, -0.2);
  const std::array<Eigen::Quaterniond, 1> one{a};
  const std::array<double, 1> w1{1.0};
  EXPECT_LE(rotation_angle(weighted_average(one, w1, a), a), 1e-14);
  // Any sign of the inputs, any scale of the weights.
  const Eigen::Quaterniond minus_a(-a.w(), -a.x(), -a.y(), -a.z());
  const std::array<Eigen::Quaterniond, 3> same{a, minus_a, a};
  const std::array<double, 3> w3{0.5, 2.0, 1.0};
  const Eigen::Quaterniond avg = weighted_average(same, w3, a);
  EXPECT_LE(rotation_angle(avg, a), 1e-14);
  EXPECT_NEAR(avg.norm(), 1.0, 1e-15);
  EXPECT_GE(avg.dot(a), 0.0);  // in the reference's hemisphere
}

TEST(Rotation, WeightedAverageOfTwoFollowsSlerp) {
  // Two rotations about one axis: the normalised sum lies on the arc between them, at the angle
  // whose tangent splits the weights (exact for two rotations, close to slerp for small arcs).
  const Eigen::Quaterniond a = axis_rotation(Axis::Z, 0.1), b = axis_rotation(Axis::Z, 0.5);
  for (double t : {0.0, 0.25, 0.5, 0.9, 1.0}) {
    const std::array<Eigen::Quaterniond, 2> q{a, b};
    const std::array<double, 2> w{1.0 - t, t};
    const Eigen::Quaterniond avg = weighted_average(q, w, b);
    const Eigen::Quaterniond expected = a.slerp(t, b);
    EXPECT_LE(rotation_angle(avg, expected), 2e-3) << "t = " << t;
    // About the same axis, between the two.
    const Eigen::AngleAxisd aa(avg);
    EXPECT_NEAR(std::abs(aa.axis().z()), 1.0, 1e-12);
    EXPECT_GE(aa.angle(), 0.1 - 1e-12);
    EXPECT_LE(aa.angle(), 0.5 + 1e-12);
  }
  // Exact for equal weights: the midpoint.
  const std::array<Eigen::Quaterniond, 2> q{a, b};
  const std::array<double, 2> half{0.5, 0.5};
  EXPECT_LE(rotation_angle(weighted_average(q, half, a), axis_rotation(Axis::Z, 0.3)), 1e-14);
}

TEST(Rotation, WeightedAverageAlignsToTheReferenceHemisphere) {
  // Flipping the sign of some inputs changes nothing: each is aligned to the reference first.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> angle(-0.4, 0.4), weight(-0.3, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<Eigen::Quaterniond> q, flipped;
    std::vector<double> w;
    for (int i = 0; i < 6; ++i) {
      const std::array<double, 3> e{angle(rng), angle(rng), angle(rng)};
      q.push_back(euler_to_quat(std::array<Axis, 3>{Axis::Z, Axis::Y, Axis::X}, e));
      flipped.push_back(i % 2 ? Eigen::Quaterniond(-q.back().coeffs()) : q.back());
      w.push_back(weight(rng));
    }
    const Eigen::Quaterniond a = weighted_average(q, w, q[0]);
    const Eigen::Quaterniond b = weighted_average(flipped, w, q[0]);
    EXPECT_EQ(a.coeffs(), b.coeffs());
    EXPECT_NEAR(a.norm(), 1.0, 1e-14);
  }
}

TEST(Rotation, WeightedAverageThatCancelsReturnsTheReference) {
  // Opposite weights on one rotation sum to 0: the reference is returned, not a NaN.
  const Eigen::Quaterniond a = axis_rotation(Axis::X, 0.3), ref = axis_rotation(Axis::Y, 1.0);
  const std::array<Eigen::Quaterniond, 2> q{a, a};
  const std::array<double, 2> w{1.0, -1.0};
  EXPECT_EQ(weighted_average(q, w, ref).coeffs(), ref.coeffs());
  EXPECT_EQ(weighted_average({}, {}, ref).coeffs(), ref.coeffs());
  const std::array<double, 1> one{1.0};
  EXPECT_THROW(weighted_average(q, one, ref), ParameterError);
}

}  // namespace
}  // namespace motionmap
