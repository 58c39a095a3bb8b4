// Which per-point times can drive a deskew: real firing times of a spinning sensor can; the
// constant times of an already compensated cloud and times unrelated to the firing cannot.
#include "core/preprocess/point_times.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "tests/core/lidar_raycast.hpp"

namespace dammloam {
namespace {

constexpr double kPeriod = 0.1;

// A 64-beam scan from inside a 20 x 10 x 3 m room, with the time at which each column fired
// (the sensor turns once per kPeriod, from azimuth -pi).
Scan RoomScanWithFiringTimes() {
  test::Scene scene;
  scene.has_room = true;
  scene.room = {Eigen::Vector3d(-8, -4, -1.5), Eigen::Vector3d(12, 6, 1.5)};
  Scan scan = test::CastScan(test::SyntheticLidar{}, scene, Eigen::Isometry3d::Identity(), nullptr);
  for (const Eigen::Vector3d& p : scan.points) {
    const double turn = (std::atan2(p.y(), p.x()) + std::numbers::pi) / (2 * std::numbers::pi);
    scan.times.push_back(static_cast<float>(turn * kPeriod));
  }
  return scan;
}

TEST(PointTimes, FiringTimesOfASpinningSensorAreUsable) {
  const Scan scan = RoomScanWithFiringTimes();
  ASSERT_GT(scan.size(), 30000u);
  EXPECT_EQ(CheckPointTimes(scan, kPeriod), PointTimeCheck::kUsable);
}

TEST(PointTimes, TimesOfOnlyPartOfARevolutionAreUsable) {
  // A driver that publishes a quarter turn per message: its times still follow the firing.
  Scan scan = RoomScanWithFiringTimes();
  Scan quarter;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (scan.times[i] < 0.25 * kPeriod) {
      quarter.points.push_back(scan.points[i]);
      quarter.times.push_back(scan.times[i]);
    }
  }
  EXPECT_EQ(CheckPointTimes(quarter, kPeriod), PointTimeCheck::kUsable);
}

TEST(PointTimes, AllZeroTimesAreConstant) {
  Scan scan = RoomScanWithFiringTimes();
  std::fill(scan.times.begin(), scan.times.end(), 0.0f);
  EXPECT_EQ(CheckPointTimes(scan, kPeriod), PointTimeCheck::kConstant);
  // One time for all, not zero (a recorder stamping every point with the scan's end).
  std::fill(scan.times.begin(), scan.times.end(), 0.1f);
  EXPECT_EQ(CheckPointTimes(scan, kPeriod), PointTimeCheck::kConstant);
}

TEST(PointTimes, ShuffledTimesAreNotFiringOrder) {
  Scan scan = RoomScanWithFiringTimes();
  std::mt19937 rng(7);
  std::shuffle(scan.times.begin(), scan.times.end(), rng);
  EXPECT_EQ(CheckPointTimes(scan, kPeriod), PointTimeCheck::kNotFiringOrder);
}

TEST(PointTimes, TimesByRingInsteadOfColumnAreNotFiringOrder) {
  // A layout mix-up: the time field holds the beam's share of the rings, not the column's turn.
  Scan scan = RoomScanWithFiringTimes();
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double elevation = std::atan2(scan.points[i].z(), scan.points[i].head<2>().norm());
    scan.times[i] = static_cast<float>((elevation + 0.4) / 0.8 * kPeriod);
  }
  EXPECT_EQ(CheckPointTimes(scan, kPeriod), PointTimeCheck::kNotFiringOrder);
}

TEST(PointTimes, MissingOrNonFiniteTimesAreNamed) {
  Scan scan = RoomScanWithFiringTimes();
  scan.times[100] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(CheckPointTimes(scan, kPeriod), PointTimeCheck::kNotFinite);
  scan.times.clear();
  EXPECT_EQ(CheckPointTimes(scan, kPeriod), PointTimeCheck::kAbsent);
  EXPECT_EQ(Name(PointTimeCheck::kConstant), "constant");
}

}  // namespace
}  // namespace dammloam
