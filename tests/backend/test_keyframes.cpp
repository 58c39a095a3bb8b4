#include <gtest/gtest.h>

#include "core/backend/keyframe_selector.hpp"

namespace dammloam::backend {
namespace {

Eigen::Isometry3d Pose(double x, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation().x() = x;
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

TEST(KeyframeSelector, ByDistanceAndRotation) {
  KeyframeSelector selector({1.0, 0.2});
  EXPECT_TRUE(selector.Consider(Pose(0, 0)));     // first scan
  EXPECT_FALSE(selector.Consider(Pose(0.5, 0)));  // too close
  EXPECT_TRUE(selector.Consider(Pose(1.1, 0)));   // moved enough
  EXPECT_FALSE(selector.Consider(Pose(1.1, 0.1)));
  EXPECT_TRUE(selector.Consider(Pose(1.1, 0.35)));  // turned enough in place
  EXPECT_FALSE(selector.Consider(Pose(1.1, 0.35)));  // standing still adds nothing
}

}  // namespace
}  // namespace dammloam::backend
