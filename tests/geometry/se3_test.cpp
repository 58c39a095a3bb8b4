#include "core/geometry/se3.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace dammloam {
namespace {

TEST(Se3, ExpLogRoundTrip) {
  Vector6d xi;
  xi << 0.3, -1.2, 2.0, 0.1, -0.4, 0.9;
  const Eigen::Isometry3d T = ExpSE3(xi);
  EXPECT_TRUE(LogSE3(T).isApprox(xi, 1e-10));
  EXPECT_NEAR(T.linear().determinant(), 1.0, 1e-12);
}

TEST(Se3, PureTranslationAndPureRotation) {
  Vector6d xi = Vector6d::Zero();
  xi.head<3>() << 1.0, 2.0, 3.0;
  EXPECT_TRUE(ExpSE3(xi).translation().isApprox(Eigen::Vector3d(1.0, 2.0, 3.0)));

  xi.setZero();
  xi(5) = M_PI / 2.0;  // yaw: tangent order is [t; r], so index 5 is rotation about z
  const Eigen::Vector3d x_rotated = ExpSE3(xi).linear() * Eigen::Vector3d::UnitX();
  EXPECT_TRUE(x_rotated.isApprox(Eigen::Vector3d::UnitY(), 1e-12));
}

TEST(Se3, ScaleMotionInterpolatesAConstantTwist) {
  Vector6d xi;
  xi << 1.0, 0.0, 0.0, 0.0, 0.0, 0.2;
  const Eigen::Isometry3d full = ExpSE3(xi);
  const Eigen::Isometry3d half = ScaleMotion(full, 0.5);
  EXPECT_TRUE((half * half).isApprox(full, 1e-10));
  EXPECT_TRUE(ScaleMotion(full, 0.0).isApprox(Eigen::Isometry3d::Identity(), 1e-12));
}

TEST(Se3, HatIsTheCrossProduct) {
  const Eigen::Vector3d a(0.2, -0.7, 1.1), b(-3.0, 0.5, 2.0);
  EXPECT_TRUE((Hat(a) * b).isApprox(a.cross(b)));
}

}  // namespace
}  // namespace dammloam
