#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "core/backend/loop_verifier.hpp"
#include "tests/backend/sim_run.hpp"

namespace dammloam::backend {
namespace {

// A keyframe of simulator scan `index`: its true pose, its cloud kept within `radius` metres (a
// stretch of a corridor far longer than that, whose end walls it cannot see).
Keyframe CorridorKeyframe(const sim::Simulator& simulator, int index, std::uint32_t id,
                          double radius) {
  Keyframe kf;
  kf.id = id;
  kf.scan_index = static_cast<std::uint64_t>(index);
  kf.T_world_sensor_odom = simulator.PoseAt(simulator.ScanStartTime(index));
  kf.T_world_sensor = kf.T_world_sensor_odom;
  for (const Eigen::Vector3d& p : test::DeskewedScan(simulator, index)) {
    if (p.norm() < radius) kf.points.push_back(p);
  }
  kf.points = VoxelDownsample(kf.points, 0.2);
  kf.descriptor = MakeScanContext(kf.points, ScanContextConfig{20, 60, 30.0, 1.2});
  return kf;
}

struct Verified {
  LoopEvent event;
  Eigen::Isometry3d T_true;
  Eigen::Isometry3d T_odom;
};

// Verifies keyframe `query` against `candidate` with odometry's relative pose off the truth by
// 0.3 m along the corridor, 5 cm across it and 0.01 rad of yaw.
Verified VerifyWithDrift(const Keyframe& candidate, Keyframe query) {
  Verified v;
  v.T_true = candidate.T_world_sensor_odom.inverse() * query.T_world_sensor_odom;
  Eigen::Isometry3d drift = Eigen::Isometry3d::Identity();
  drift.translation() = Eigen::Vector3d(0.3, 0.05, 0.0);
  drift.linear() = Eigen::AngleAxisd(0.01, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  query.T_world_sensor_odom = candidate.T_world_sensor_odom * drift * v.T_true;
  v.T_odom = candidate.T_world_sensor_odom.inverse() * query.T_world_sensor_odom;
  const ScanContextMatch match = CompareScanContexts(query.descriptor, candidate.descriptor);
  v.event = LoopVerifier().Verify(query, candidate, match, 20.0);
  return v;
}

double AngleBetween(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.rotation().transpose() * b.rotation()).angle();
}

// In the middle of a long corridor a loop fixes the lateral and vertical offset and the
// rotation, but not the position along the axis: it must say so in its covariance and keep
// odometry's value there instead of sliding towards "same place".
TEST(LoopVerifier, MidCorridorLoopConstrainsOnlyAcrossTheAxis) {
  const sim::Simulator simulator(sim::SceneKind::Corridor, test::TestSensor());
  const Keyframe candidate = CorridorKeyframe(simulator, 200, 0, 12.0);
  const Keyframe query = CorridorKeyframe(simulator, 230, 1, 12.0);
  const Verified v = VerifyWithDrift(candidate, query);
  ASSERT_TRUE(v.event.accepted) << v.event.reason;
  EXPECT_EQ(v.event.observed_translation_directions, 2);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(
      v.event.covariance.topLeftCorner<3, 3>());
  const Eigen::Vector3d free_axis = solver.eigenvectors().col(2);
  EXPECT_GT(std::abs(free_axis.x()), 0.99);                 // the corridor's axis...
  EXPECT_GT(std::sqrt(solver.eigenvalues()(2)), 10.0);      // ...carries no information
  EXPECT_LT(std::sqrt(solver.eigenvalues()(1)), 0.05);      // across it: centimetres
  const Eigen::Vector3d t = v.event.T_candidate_query.translation();
  EXPECT_NEAR(t.y(), v.T_true.translation().y(), 0.03);
  EXPECT_NEAR(t.z(), v.T_true.translation().z(), 0.03);
  EXPECT_NEAR(t.x(), v.T_odom.translation().x(), 0.05);     // no slide along the free axis
  EXPECT_LT(AngleBetween(v.event.T_candidate_query, v.T_true), 0.005);
}

// Near the corridor's end wall the same drift is corrected in every direction.
TEST(LoopVerifier, LoopSeeingTheEndWallConstrainsAllDirections) {
  const sim::Simulator simulator(sim::SceneKind::Corridor, test::TestSensor());
  const Keyframe candidate = CorridorKeyframe(simulator, 0, 0, 20.0);  // end wall 10 m behind
  const Keyframe query = CorridorKeyframe(simulator, 30, 1, 20.0);
  const Verified v = VerifyWithDrift(candidate, query);
  ASSERT_TRUE(v.event.accepted) << v.event.reason;
  EXPECT_EQ(v.event.observed_translation_directions, 3);
  EXPECT_LT((v.event.T_candidate_query.translation() - v.T_true.translation()).norm(), 0.05);
  EXPECT_LT(AngleBetween(v.event.T_candidate_query, v.T_true), 0.005);
}

// A stairwell's walls run through both floors, and a floor plan repeated on the next floor
// fits as well as the same floor's: nothing in such a pair tells the heights apart, and
// odometry, having climbed the stairs, agrees with the registration. A revisit on another
// floor must not be accepted; the same pair on one floor is.
Keyframe WallsKeyframe(std::uint32_t id, double sensor_height) {
  Keyframe kf;
  kf.id = id;
  kf.T_world_sensor_odom.translation() = Eigen::Vector3d(0.0, 0.0, sensor_height);
  kf.T_world_sensor = kf.T_world_sensor_odom;
  // Two side walls 3 m apart and an end wall 8 m ahead, from 2 m below the ground floor to
  // 2 m above the first floor (world z -2..5); what this keyframe sees of them, its frame.
  for (double z = -2.0; z <= 5.0; z += 0.1) {
    for (double x = -8.0; x <= 8.0; x += 0.1) {
      for (const double y : {-1.5, 1.5}) kf.points.emplace_back(x, y, z - sensor_height);
    }
    for (double y = -1.5; y <= 1.5; y += 0.1) kf.points.emplace_back(8.0, y, z - sensor_height);
  }
  kf.descriptor = MakeScanContext(kf.points, ScanContextConfig{20, 60, 30.0, 1.2});
  return kf;
}

TEST(LoopVerifier, AFloorPlanOneStoreyUpIsNotALoop) {
  const Keyframe candidate = WallsKeyframe(0, 1.0);
  const Keyframe same_floor = WallsKeyframe(1, 1.0);
  const Keyframe upstairs = WallsKeyframe(1, 4.0);
  const LoopVerifier verifier;
  const auto verify = [&](const LoopVerifier& v, const Keyframe& query) {
    return v.Verify(query, candidate, CompareScanContexts(query.descriptor, candidate.descriptor),
                    60.0);
  };
  const LoopEvent same = verify(verifier, same_floor);
  ASSERT_TRUE(same.accepted) << same.reason;
  EXPECT_EQ(same.observed_translation_directions, 2);  // the height is free: walls only
  const LoopEvent up = verify(verifier, upstairs);
  EXPECT_FALSE(up.accepted);
  EXPECT_NE(up.reason.find("another level: +3.00 m"), std::string::npos) << up.reason;

  LoopVerifierConfig unchecked;
  unchecked.max_level_difference = 0.0;
  const LoopEvent without_check = verify(LoopVerifier(unchecked), upstairs);
  EXPECT_TRUE(without_check.accepted) << without_check.reason;  // what the check is for
}

}  // namespace
}  // namespace dammloam::backend
