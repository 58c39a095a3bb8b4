// Bad input never crashes or corrupts the map; pipelines do not share state.
#include <gtest/gtest.h>

#include <limits>
#include <thread>

#include "core/odometry/pipeline.hpp"
#include "tools/benchmark/sim_run.hpp"

namespace dammloam {
namespace {

bool SamePose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return a.matrix() == b.matrix();  // bit-identical
}

TEST(OdometryRobustness, BadScansGetAStatusAndLeaveTheMapAlone) {
  const auto seq = bench::GenerateSequence(sim::SceneKind::Zigzag, sim::Vlp16(), 4);
  OdometryPipeline pipeline(OdometryConfig{}, seq.model);
  ASSERT_EQ(pipeline.Process(seq.scans[0]).status, OdometryStatus::kFirstScan);
  ASSERT_EQ(pipeline.Process(seq.scans[1]).status, OdometryStatus::kOk);
  const std::size_t map_points = pipeline.odometry().local_map().NumPoints();
  const Eigen::Isometry3d pose = pipeline.odometry().last_pose();

  Scan empty;
  empty.t_start = seq.scans[1].t_start + 0.1;
  EXPECT_EQ(pipeline.Process(empty).status, OdometryStatus::kEmptyScan);

  Scan nan = seq.scans[2];
  for (auto& p : nan.points) p.setConstant(std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(pipeline.Process(nan).status, OdometryStatus::kEmptyScan);

  Scan few = seq.scans[2];
  few.points.resize(10);
  few.times.resize(10);
  few.rings.resize(10);
  few.intensities.resize(std::min<std::size_t>(few.intensities.size(), 10));
  EXPECT_EQ(pipeline.Process(few).status, OdometryStatus::kTooFewPoints);

  Scan duplicate = seq.scans[2];
  duplicate.t_start = seq.scans[1].t_start;
  EXPECT_EQ(pipeline.Process(duplicate).status, OdometryStatus::kNonIncreasingStamp);

  EXPECT_EQ(pipeline.odometry().local_map().NumPoints(), map_points);
  EXPECT_TRUE(SamePose(pipeline.odometry().last_pose(), pose));

  // The good scan after all that registers exactly as if the bad ones had never come.
  const OdometryResult good = pipeline.Process(seq.scans[2]);
  EXPECT_EQ(good.status, OdometryStatus::kOk);
  OdometryPipeline clean(OdometryConfig{}, seq.model);
  for (int i = 0; i < 2; ++i) clean.Process(seq.scans[i]);
  EXPECT_TRUE(SamePose(good.T_world_sensor, clean.Process(seq.scans[2]).T_world_sensor));

  // A 10 s gap: registered with a reset velocity model, flagged.
  Scan late = seq.scans[3];
  late.t_start += 10.0;
  const OdometryResult gap = pipeline.Process(late);
  EXPECT_EQ(gap.status, OdometryStatus::kTimeGap);
  EXPECT_TRUE(gap.T_world_sensor.matrix().allFinite());
}

// Every status reports a pose in the same frame, the scan start: a rejected scan the last
// reported pose, an unregistered one its predicted start pose (not the mid-scan pose, which
// is half a scan of motion ahead).
TEST(OdometryRobustness, RejectedAndUnregisteredScansReportScanStartPoses) {
  constexpr int kRegistered = 24;  // past the simulator's speed ramp
  const auto seq = bench::GenerateSequence(sim::SceneKind::Zigzag, sim::Vlp16(), kRegistered + 1);
  OdometryPipeline pipeline(OdometryConfig{}, seq.model);
  OdometryResult last;
  for (int i = 0; i < kRegistered; ++i) {
    last = pipeline.Process(seq.scans[static_cast<std::size_t>(i)]);
    ASSERT_TRUE(Registered(last.status));
  }
  const Vector6d velocity = pipeline.odometry().velocity();
  ASSERT_GT(velocity.head<3>().norm(), 0.3);  // moving: start and mid-scan poses differ
  const Eigen::Isometry3d last_mid = pipeline.odometry().last_pose();

  Scan empty;
  empty.t_start = seq.scans[kRegistered - 1].t_start + 0.05;
  const OdometryResult rejected = pipeline.Process(empty);
  EXPECT_EQ(rejected.status, OdometryStatus::kEmptyScan);
  EXPECT_TRUE(SamePose(rejected.T_world_sensor, last.T_world_sensor));

  // Lifted 50 m above the map: valid points, but none near a map point.
  Scan lifted = seq.scans[kRegistered];
  for (auto& p : lifted.points) p.z() += 50.0;
  const OdometryResult lost = pipeline.Process(lifted);
  ASSERT_EQ(lost.status, OdometryStatus::kTooFewCorrespondences);
  const double dt = seq.scans[kRegistered].t_start - seq.scans[kRegistered - 1].t_start;
  // Predicted mid-scan pose, then back half a deskewed scan period to the scan start.
  const Eigen::Isometry3d predicted_start =
      last_mid * ExpSE3(velocity * dt) * ExpSE3(-0.5 * seq.model.scan_period * velocity);
  EXPECT_LT((lost.T_world_sensor.translation() - predicted_start.translation()).norm(), 1e-9);
  EXPECT_LT((lost.T_world_sensor.linear() - predicted_start.linear()).norm(), 1e-9);
  // The predicted mid-scan pose, what was reported before, is half a scan of motion away.
  const Eigen::Isometry3d predicted_mid = last_mid * ExpSE3(velocity * dt);
  EXPECT_GT((predicted_mid.translation() - lost.T_world_sensor.translation()).norm(), 0.01);
}

// No hidden shared state: two pipelines interleaved give the same poses as each alone.
TEST(OdometryRobustness, InterleavedPipelinesDoNotInterfere) {
  const auto a = bench::GenerateSequence(sim::SceneKind::Zigzag, sim::Vlp16(), 6);
  const auto b = bench::GenerateSequence(sim::SceneKind::Outdoor, sim::Vlp16(), 6);
  std::vector<Eigen::Isometry3d> alone_a, alone_b;
  {
    OdometryPipeline pa(OdometryConfig{}, a.model);
    for (const auto& s : a.scans) alone_a.push_back(pa.Process(s).T_world_sensor);
    OdometryPipeline pb(OdometryConfig{}, b.model);
    for (const auto& s : b.scans) alone_b.push_back(pb.Process(s).T_world_sensor);
  }
  OdometryPipeline pa(OdometryConfig{}, a.model);
  OdometryPipeline pb(OdometryConfig{}, b.model);
  for (std::size_t i = 0; i < a.scans.size(); ++i) {
    EXPECT_TRUE(SamePose(pa.Process(a.scans[i]).T_world_sensor, alone_a[i])) << i;
    EXPECT_TRUE(SamePose(pb.Process(b.scans[i]).T_world_sensor, alone_b[i])) << i;
  }
}

// The daemon's split: Extract on one thread, Register on another, in lock-step, gives the
// same poses as Process. Two pipelines on two threads at once do not interfere either.
TEST(OdometryRobustness, ThreadedUseMatchesProcess) {
  const auto seq = bench::GenerateSequence(sim::SceneKind::Zigzag, sim::Vlp16(), 5);
  std::vector<Eigen::Isometry3d> reference;
  {
    OdometryPipeline p(OdometryConfig{}, seq.model);
    for (const auto& s : seq.scans) reference.push_back(p.Process(s).T_world_sensor);
  }
  OdometryPipeline split(OdometryConfig{}, seq.model);
  for (std::size_t i = 0; i < seq.scans.size(); ++i) {
    ClassifiedScan features;
    std::thread extract([&] { features = split.Extract(seq.scans[i]); });
    extract.join();
    OdometryResult result;
    std::thread reg([&] { result = split.odometry().Register(std::move(features)); });
    reg.join();
    EXPECT_TRUE(SamePose(result.T_world_sensor, reference[i])) << i;
  }
  std::vector<Eigen::Isometry3d> t1, t2;
  auto run = [&](std::vector<Eigen::Isometry3d>& out) {
    OdometryPipeline p(OdometryConfig{}, seq.model);
    for (const auto& s : seq.scans) out.push_back(p.Process(s).T_world_sensor);
  };
  std::thread th1(run, std::ref(t1)), th2(run, std::ref(t2));
  th1.join();
  th2.join();
  for (std::size_t i = 0; i < reference.size(); ++i) {
    EXPECT_TRUE(SamePose(t1[i], reference[i])) << i;
    EXPECT_TRUE(SamePose(t2[i], reference[i])) << i;
  }
}

}  // namespace
}  // namespace dammloam
