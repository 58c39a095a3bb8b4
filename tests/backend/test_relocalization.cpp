#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <random>

#include "core/backend/localizer.hpp"
#include "core/backend/loop_closing_backend.hpp"
#include "tests/backend/sim_run.hpp"
#include "io/mapstore/map_store.hpp"
#include "tests/support/temp_dir.hpp"

namespace dammloam::backend {
namespace {

namespace fs = std::filesystem;

std::vector<Eigen::Vector3d> Rotated(const std::vector<Eigen::Vector3d>& points, double yaw) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(-yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::vector<Eigen::Vector3d> out;
  for (const auto& p : points) out.push_back(R * p);
  return out;
}

// Maps one lap of the outdoor scene (true odometry), saves and reloads it, then relocalizes
// scans taken between keyframes, each seen with a random heading.
TEST(Relocalization, TwentyRandomPosesInASavedMap) {
  const sim::Simulator simulator(sim::SceneKind::Outdoor, test::TestSensor());
  const int stride = 7;
  const test::SimRun run = test::MakeSimRun(simulator, 125, stride, test::DriftModel{0.0, 0.0});
  LoopClosingBackend backend;
  for (const auto& r : run.odometry) backend.AddScan(r);
  backend.Process();

  const test::TempDir tmp;
  mapstore::SaveMap(tmp / "map", backend.ExportMap());
  const MapData map = mapstore::LoadMap(tmp / "map");

  Localizer localizer(map);
  std::mt19937 rng(42);
  std::uniform_int_distribution<int> scan(0, 124 * stride);
  std::uniform_real_distribution<double> heading(-std::numbers::pi, std::numbers::pi);
  int successes = 0;
  int wrong = 0;  // a confident wrong pose is worse than none
  double worst = 0.0;
  for (int trial = 0; trial < 20; ++trial) {
    const int index = scan(rng);
    const double yaw = heading(rng);
    Eigen::Isometry3d truth = simulator.PoseAt(simulator.ScanStartTime(index));
    truth.linear() = truth.linear() *
                     Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const auto result = localizer.Relocalize(Rotated(test::DeskewedScan(simulator, index), yaw));
    if (!result) {
      std::printf("  trial %2d scan %4d: not found\n", trial, index);
      continue;
    }
    const double error = (result->T_map_sensor.translation() - truth.translation()).norm();
    std::printf("  trial %2d scan %4d: error %.3f m, inliers %.2f, rmse %.3f, sc %.3f, kf %u\n",
                trial, index, error, result->inlier_ratio, result->rmse,
                result->scan_context_distance, result->keyframe);
    worst = std::max(worst, error);
    if (error < 0.3) ++successes;
    if (error > 1.0) ++wrong;
  }
  std::printf("relocalization: %d/20 within 0.3 m (worst error of the found poses %.3f m)\n",
              successes, worst);
  EXPECT_GE(successes, 19);
  EXPECT_EQ(wrong, 0);

  // Localization mode: track a short stretch without growing the map.
  const std::size_t map_points = localizer.NumMapPoints();
  for (int index = 300; index < 320; ++index) {
    const auto result = localizer.Localize(test::DeskewedScan(simulator, index));
    ASSERT_TRUE(result.has_value()) << index;
    const Eigen::Isometry3d truth = simulator.PoseAt(simulator.ScanStartTime(index));
    EXPECT_LT((result->T_map_sensor.translation() - truth.translation()).norm(), 0.2) << index;
  }
  EXPECT_EQ(localizer.NumMapPoints(), map_points);
}

}  // namespace
}  // namespace dammloam::backend
