#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "core/backend/keyframe_selector.hpp"
#include "core/backend/loop_closing_backend.hpp"

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

// A person labelled Moving in a keyframe's scan must not enter the keyframe's cloud, nor the
// global map saved from it: the map would keep a trail of everyone who walked past.
TEST(LoopClosingBackend, KeyframesAndTheGlobalMapLeaveMovingPointsOut) {
  OdometryResult r;
  r.scan_index = 0;
  r.stamp = 1.0;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  for (int i = 0; i < 4000; ++i) {  // a floor
    r.deskewed_points.emplace_back(u(rng), u(rng), -1.5);
    r.labels.push_back(PointClass::Ground);
  }
  std::uniform_real_distribution<double> body(-0.2, 0.2), height(-1.5, 0.3);
  for (int i = 0; i < 500; ++i) {  // a person 3 m ahead
    r.deskewed_points.emplace_back(3.0 + body(rng), body(rng), height(rng));
    r.labels.push_back(i % 2 ? PointClass::Moving : PointClass::Wall);
  }
  LoopClosingBackend backend;
  backend.AddScan(r);
  backend.Process();
  const MapData map = backend.ExportMap();
  ASSERT_EQ(map.keyframes.size(), 1u);
  const Keyframe& kf = map.keyframes.front();
  ASSERT_EQ(kf.labels.size(), kf.points.size());
  EXPECT_EQ(std::count(kf.labels.begin(), kf.labels.end(), PointClass::Moving), 0);
  EXPECT_GT(std::count(kf.labels.begin(), kf.labels.end(), PointClass::Wall), 0);
  ASSERT_FALSE(map.global_labels.empty());
  EXPECT_EQ(std::count(map.global_labels.begin(), map.global_labels.end(), PointClass::Moving), 0);
}

}  // namespace
}  // namespace dammloam::backend
