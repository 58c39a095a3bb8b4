#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/backend/scan_context.hpp"
#include "core/backend/scan_context_database.hpp"
#include "tools/simulate/simulator.hpp"

namespace dammloam::backend {
namespace {

sim::Simulator OutdoorSim() {
  sim::SensorSpec spec = sim::Os1_64();
  spec.columns = 512;
  spec.vertical_angles_deg = sim::UniformVerticalAngles(32, 22.5, -22.5);
  return sim::Simulator(sim::SceneKind::Outdoor, spec);
}

std::vector<Eigen::Vector3d> Rotated(const std::vector<Eigen::Vector3d>& points, double yaw) {
  // The same place seen by a sensor turned by +yaw: points appear turned by -yaw.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(-yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  std::vector<Eigen::Vector3d> out;
  for (const auto& p : points) out.push_back(R * p);
  return out;
}

double AngleDiff(double a, double b) { return std::abs(std::remainder(a - b, 2 * std::numbers::pi)); }

TEST(ScanContext, SamePlaceRotatedGivesZeroDistanceAndTheYaw) {
  const sim::Simulator simulator = OutdoorSim();
  const auto points = simulator.SimulateScan(40).points;
  const ScanContextConfig config;
  const ScanContext candidate = MakeScanContext(points, config);
  const double sector = 2 * std::numbers::pi / config.sectors;
  for (double yaw : {12 * sector, -25 * sector, 1.0}) {
    const ScanContext query = MakeScanContext(Rotated(points, yaw), config);
    EXPECT_TRUE(query.ring_key.isApprox(candidate.ring_key, 0.1f));
    const ScanContextMatch match = CompareScanContexts(query, candidate);
    // Exact multiples of a sector match exactly; other angles re-bin a little.
    EXPECT_LT(match.distance, std::fmod(yaw / sector, 1.0) == 0.0 ? 0.01 : 0.15) << yaw;
    EXPECT_LT(AngleDiff(match.yaw_rad, yaw), sector + 1e-9) << yaw;
  }
}

TEST(ScanContext, DifferentPlacesAreFarApart) {
  const sim::Simulator simulator = OutdoorSim();
  const ScanContextConfig config;
  const ScanContext a = MakeScanContext(simulator.SimulateScan(40).points, config);
  const ScanContext a_again = MakeScanContext(simulator.SimulateScan(41).points, config);
  const ScanContext b = MakeScanContext(simulator.SimulateScan(300).points, config);
  const double same = CompareScanContexts(a_again, a).distance;
  const double different = CompareScanContexts(b, a).distance;
  EXPECT_LT(same, 0.15);
  EXPECT_GT(different, 0.25);
  EXPECT_GT(different, 2.0 * same);
}

TEST(ScanContext, EmptyOrMismatchedDescriptorsNeverMatch) {
  const ScanContext empty;
  ScanContextConfig small;
  small.sectors = 30;
  const ScanContext other = MakeScanContext({{5, 0, 0}}, small);
  const ScanContext normal = MakeScanContext({{5, 0, 0}}, ScanContextConfig{});
  EXPECT_GE(CompareScanContexts(empty, normal).distance, 1.0);
  EXPECT_GE(CompareScanContexts(other, normal).distance, 1.0);
}

TEST(ScanContextDatabase, RetrievesTheRevisitedPlaceAndExcludesRecent) {
  const sim::Simulator simulator = OutdoorSim();
  const ScanContextConfig config;
  ScanContextDatabaseConfig db_config;
  db_config.exclude_recent = 5;
  db_config.rebuild_every = 4;  // exercise both the tree and the brute-force tail
  ScanContextDatabase database(db_config);
  for (int i = 0; i < 30; ++i) {
    database.Add(MakeScanContext(simulator.SimulateScan(i * 20).points, config));
  }
  // Scan 201 is next to stored entry 10 (scan 200), seen turned by 90 degrees.
  const ScanContext query =
      MakeScanContext(Rotated(simulator.SimulateScan(201).points, std::numbers::pi / 2), config);
  const auto candidates = database.Query(query);
  ASSERT_FALSE(candidates.empty());
  EXPECT_EQ(candidates.front().id, 10u);
  EXPECT_LT(AngleDiff(candidates.front().match.yaw_rad, std::numbers::pi / 2), 0.15);
  // Entry 29 is among the excluded newest entries, so querying with its own descriptor must
  // not return it.
  for (const auto& c : database.Query(database.at(29))) EXPECT_LT(c.id, 25u);
  EXPECT_TRUE(ScanContextDatabase(db_config).Query(query).empty());

  // A retired entry (its keyframe dropped its cloud) is never returned again, whether it was
  // already in the k-d tree or not, and the others still are.
  database.Retire(10);
  const auto after = database.Query(query);
  for (const auto& c : after) EXPECT_NE(c.id, 10u);
  EXPECT_TRUE(database.at(10).empty());
  const ScanContext entry_11 = MakeScanContext(simulator.SimulateScan(220).points, config);
  const auto still = database.Query(entry_11);
  ASSERT_FALSE(still.empty());
  EXPECT_EQ(still.front().id, 11u);
}

}  // namespace
}  // namespace dammloam::backend
