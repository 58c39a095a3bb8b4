#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <atomic>
#include <cstdio>
#include <thread>

#include "core/backend/loop_closing_backend.hpp"
#include "tests/backend/sim_run.hpp"
#include "tools/simulate/presets.hpp"

namespace dammloam::backend {
namespace {

using test::DriftModel;
using test::MakeSimRun;
using test::PositionRmse;
using test::SimRun;

struct Outcome {
  std::vector<LoopEvent> events;
  std::vector<Eigen::Isometry3d> corrected;
};

// Feeds the run from this thread while a second thread calls Process(), as the daemon does.
Outcome RunBackendThreaded(LoopClosingBackend& backend, const SimRun& run) {
  Outcome outcome;
  std::atomic<bool> done{false};
  std::thread worker([&] {
    while (true) {
      const bool finished = done.load();
      for (auto& e : backend.Process()) outcome.events.push_back(std::move(e));
      if (finished) break;
      std::this_thread::yield();
    }
  });
  for (const OdometryResult& r : run.odometry) backend.AddScan(r);
  done = true;
  worker.join();
  for (const OdometryResult& r : run.odometry) {
    const auto pose = backend.CorrectedPoseOf(r.scan_index, r.T_world_sensor);
    EXPECT_TRUE(pose.has_value());
    outcome.corrected.push_back(pose.value_or(Eigen::Isometry3d::Identity()));
  }
  return outcome;
}

// The back-end keeping up with every scan: Process() right after each AddScan, on this thread.
// Deterministic (the threaded run checks a varying number of loops between two solves), for
// tests whose counts depend on the order of checks and solves.
Outcome RunBackendStepByStep(LoopClosingBackend& backend, const SimRun& run) {
  Outcome outcome;
  for (const OdometryResult& r : run.odometry) {
    backend.AddScan(r);
    for (auto& e : backend.Process()) outcome.events.push_back(std::move(e));
  }
  for (const OdometryResult& r : run.odometry) {
    const auto pose = backend.CorrectedPoseOf(r.scan_index, r.T_world_sensor);
    EXPECT_TRUE(pose.has_value());
    outcome.corrected.push_back(pose.value_or(Eigen::Isometry3d::Identity()));
  }
  return outcome;
}

// An accepted loop's error along the translation directions it constrains (standard deviation
// under 1 m in its covariance) and its rotation error. A corridor loop leaves the corridor's
// axis free: what it says along it carries no weight and is not judged.
struct LoopError {
  double translation = 0.0;  // metres, constrained directions only
  double rotation = 0.0;     // radians
  int constrained = 0;       // translation directions constrained
};

LoopError ConstrainedError(const LoopEvent& e, const Eigen::Isometry3d& T_true) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(e.covariance.topLeftCorner<3, 3>());
  Eigen::Matrix3d P = Eigen::Matrix3d::Zero();
  LoopError error;
  for (int i = 0; i < 3; ++i) {
    if (solver.eigenvalues()(i) < 1.0) {
      P += solver.eigenvectors().col(i) * solver.eigenvectors().col(i).transpose();
      ++error.constrained;
    }
  }
  error.translation = (P * (e.T_candidate_query.translation() - T_true.translation())).norm();
  error.rotation =
      Eigen::AngleAxisd(T_true.rotation().transpose() * e.T_candidate_query.rotation()).angle();
  return error;
}

std::size_t CountAccepted(const std::vector<LoopEvent>& events) {
  std::size_t n = 0;
  for (const auto& e : events) n += e.accepted ? 1 : 0;
  return n;
}

TEST(LoopClosure, OutdoorLoopHalvesApeAndAcceptsOnlyTrueLoops) {
  const sim::Simulator simulator(sim::SceneKind::Outdoor, test::TestSensor());
  // ~1.05 m between scans, 1.2 laps of the ~130 m loop.
  const int stride = 7;
  const SimRun run = MakeSimRun(simulator, 150, stride, DriftModel{0.0015, 0.02});
  LoopClosingBackend backend;
  const Outcome outcome = RunBackendThreaded(backend, run);

  std::vector<Eigen::Isometry3d> odometry;
  for (const auto& r : run.odometry) odometry.push_back(r.T_world_sensor);
  const double before = PositionRmse(odometry, run.truth);
  const double after = PositionRmse(outcome.corrected, run.truth);
  const std::size_t accepted = CountAccepted(outcome.events);
  std::printf("outdoor loop: %zu keyframes, %zu candidates, %zu accepted; APE RMSE odometry %.3f m,"
              " with loop closure %.3f m\n",
              backend.NumKeyframes(), outcome.events.size(), accepted, before, after);
  ASSERT_GE(accepted, 1u);
  double min_observability = 1.0;
  for (const LoopEvent& e : outcome.events) {
    if (!e.accepted) continue;
    min_observability = std::min(min_observability, e.translation_observability);
    const auto truth_of = [&](std::uint64_t scan_index) {
      return run.truth[static_cast<std::size_t>(scan_index / stride)];
    };
    const Eigen::Isometry3d T_true =
        truth_of(e.candidate_scan_index).inverse() * truth_of(e.query_scan_index);
    EXPECT_LT((T_true.translation() - e.T_candidate_query.translation()).norm(), 0.3)
        << e.query_keyframe << " -> " << e.candidate_keyframe;
  }
  std::printf("outdoor loop: smallest translation observability of accepted loops %.3f\n",
              min_observability);
  EXPECT_LT(after * 2.0, before);
  const MapData map = backend.ExportMap();
  EXPECT_EQ(map.keyframes.size(), backend.NumStoredKeyframes());
  EXPECT_GT(map.global_points.size(), 1000u);
}

// Laps over mapped ground: keyframes keep being taken (loops keep being closed, every scan keeps
// a corrected pose), but a keyframe verified within revisit_drop_distance of an older one drops
// its cloud, and loops that agree with the map start no optimisation. The saved map must still
// cover every place driven through, and the laps after the first may add only a few clouds
// (where a loop was rejected or lay farther away).
TEST(LoopClosure, LapsOverMappedGroundKeepPosesButNotClouds) {
  const sim::Simulator simulator(sim::SceneKind::Outdoor, test::TestSensor());
  const int stride = 7;  // ~1.05 m between scans; 270 scans are ~2.2 laps of the ~130 m loop
  const SimRun run = MakeSimRun(simulator, 270, stride, DriftModel{0.0015, 0.02});
  LoopClosingBackend backend;
  const Outcome outcome = RunBackendThreaded(backend, run);

  // Path length at each scan, and the length of one lap (first return to the start).
  std::vector<double> path(run.truth.size(), 0.0);
  double lap = 0.0;
  for (std::size_t i = 1; i < run.truth.size(); ++i) {
    path[i] = path[i - 1] + (run.truth[i].translation() - run.truth[i - 1].translation()).norm();
    if (lap == 0.0 && path[i] > 20.0 &&
        (run.truth[i].translation() - run.truth[0].translation()).norm() < 2.0) {
      lap = path[i];
    }
  }
  ASSERT_GT(lap, 0.0) << "the simulated path never returned to its start";

  const MapData map = backend.ExportMap();
  std::vector<Eigen::Vector3d> stored;  // true positions of the keyframes that kept a cloud
  std::size_t stored_after_first_lap = 0;
  for (const Keyframe& kf : map.keyframes) {
    const std::size_t i = static_cast<std::size_t>(kf.scan_index / stride);
    ASSERT_LT(i, run.truth.size());
    stored.push_back(run.truth[i].translation());
    if (path[i] > lap + 10.0) ++stored_after_first_lap;
  }
  std::size_t taken_after_first_lap = 0;
  for (const OdometryResult& r : run.odometry) {
    // Keyframes are at least 1 m apart and the scans ~1.05 m apart: nearly every scan is one.
    if (path[static_cast<std::size_t>(r.scan_index / stride)] > lap + 10.0) ++taken_after_first_lap;
  }
  double worst_gap = 0.0;
  for (const Eigen::Isometry3d& T : run.truth) {
    double nearest = 1e9;
    for (const Eigen::Vector3d& p : stored) nearest = std::min(nearest, (p - T.translation()).norm());
    worst_gap = std::max(worst_gap, nearest);
  }
  std::vector<Eigen::Isometry3d> odometry;
  for (const auto& r : run.odometry) odometry.push_back(r.T_world_sensor);
  const double before = PositionRmse(odometry, run.truth);
  const double after = PositionRmse(outcome.corrected, run.truth);
  std::printf("laps: lap %.0f m, %zu keyframes, %zu with a cloud (%zu of ~%zu after the first "
              "lap), %zu accepted loops, farthest scan from a stored keyframe %.2f m, APE %.3f -> "
              "%.3f m, %zu optimisations\n",
              lap, backend.NumKeyframes(), backend.NumStoredKeyframes(), stored_after_first_lap,
              taken_after_first_lap, CountAccepted(outcome.events), worst_gap, before, after,
              backend.NumOptimizations());
  EXPECT_GT(backend.NumKeyframes(), run.odometry.size() * 9 / 10);  // poses are all still taken
  // Loops that agree with the corrected map start no optimisation (loop_optimize_residual): the
  // first closure of the lap does; going round mapped ground after it costs no more solves.
  EXPECT_GE(backend.NumOptimizations(), 1u);
  EXPECT_LT(backend.NumOptimizations() * 10, CountAccepted(outcome.events));
  EXPECT_EQ(map.keyframes.size(), backend.NumStoredKeyframes());
  EXPECT_LT(worst_gap, 3.0);
  EXPECT_LT(stored_after_first_lap * 3, taken_after_first_lap);
  EXPECT_LT(after * 2.0, before);
  for (std::size_t i = 0; i < map.keyframes.size(); ++i) EXPECT_EQ(map.keyframes[i].id, i);
  for (const LoopConstraint& loop : map.loops) {
    EXPECT_LT(loop.from, map.keyframes.size());
    EXPECT_LT(loop.to, map.keyframes.size());
  }
}

// Identical corridor segments: a look-alike segment metres away registers perfectly. It may
// only be accepted as what it truly is, a constraint across the corridor (lateral, vertical,
// rotation), never as a fix along the axis, where it would be wrong by the segment length.
TEST(LoopClosure, RepetitiveCorridorGivesNoAcceptedFalseLoop) {
  const sim::Simulator simulator(sim::SceneKind::Repetitive, test::TestSensor());
  const int stride = 10;
  const SimRun run = MakeSimRun(simulator, 60, stride, DriftModel{0.001, 0.01});
  BackendConfig config;
  config.scan_context.max_range = 30.0;  // indoor
  config.scan_context.sensor_height = 1.2;
  config.database.max_distance = 0.4;   // let look-alikes through to verification
  LoopClosingBackend backend(config);
  const Outcome outcome = RunBackendThreaded(backend, run);
  std::size_t look_alikes = 0, partial = 0;
  for (const LoopEvent& e : outcome.events) {
    EXPECT_FALSE(e.reason.empty());
    const Eigen::Isometry3d T_true = run.truth[e.candidate_scan_index / stride].inverse() *
                                     run.truth[e.query_scan_index / stride];
    const double separation = (T_true.translation() - e.T_candidate_query.translation()).norm();
    look_alikes += separation > 2.0 ? 1 : 0;
    if (!e.accepted) continue;
    const LoopError error = ConstrainedError(e, T_true);
    partial += error.constrained < 3 ? 1 : 0;
    EXPECT_LT(error.translation, 0.3) << e.query_keyframe << " -> " << e.candidate_keyframe;
    EXPECT_LT(error.rotation, 0.05) << e.query_keyframe << " -> " << e.candidate_keyframe;
  }
  std::printf("repetitive corridor: %zu keyframes, %zu candidates (%zu registered at a look-alike"
              " place), %zu accepted, %zu of them across the corridor only\n",
              backend.NumKeyframes(), outcome.events.size(), look_alikes,
              CountAccepted(outcome.events), partial);
  EXPECT_GT(look_alikes, 0u) << "the scene no longer tests aliasing";
}

// Descriptors sized for the corridor (indoor range, hand height); loops only after 10 keyframes.
BackendConfig CorridorReturnConfig() {
  BackendConfig config;
  config.scan_context.max_range = 30.0;
  config.scan_context.sensor_height = 1.2;
  config.database.exclude_recent = 10;
  return config;
}

// A corridor driven to a U-turn and back along the other side: loops are seen facing the
// other way (yaw ~180 deg), and the corridor leaves the along-axis translation weakly observed.
// The injected drift (2 % scale, 0.002 rad/m yaw) is what corridor odometry suffers.
TEST(LoopClosure, CorridorReturnHalvesApeAndAcceptsOnlyTrueLoops) {
  const sim::Simulator simulator(sim::SceneKind::CorridorReturn, test::TestSensor());
  const int stride = 10;
  const SimRun run = MakeSimRun(simulator, 60, stride, DriftModel{0.002, 0.02});
  BackendConfig config = CorridorReturnConfig();
  LoopClosingBackend backend(config);
  const Outcome outcome = RunBackendThreaded(backend, run);
  std::vector<Eigen::Isometry3d> odometry;
  for (const auto& r : run.odometry) odometry.push_back(r.T_world_sensor);
  const double before = PositionRmse(odometry, run.truth);
  const double after = PositionRmse(outcome.corrected, run.truth);
  std::size_t full = 0;
  for (const LoopEvent& e : outcome.events) {
    if (!e.accepted) continue;
    const Eigen::Isometry3d T_true = run.truth[e.candidate_scan_index / stride].inverse() *
                                     run.truth[e.query_scan_index / stride];
    const LoopError error = ConstrainedError(e, T_true);
    full += error.constrained == 3 ? 1 : 0;
    EXPECT_LT(error.translation, 0.3) << e.query_keyframe << " -> " << e.candidate_keyframe;
    EXPECT_LT(error.rotation, 0.05) << e.query_keyframe << " -> " << e.candidate_keyframe;
  }
  std::printf("corridor-return: %zu keyframes, %zu candidates, %zu accepted (%zu fully "
              "constrained); APE RMSE odometry %.3f m, with loop closure %.3f m\n",
              backend.NumKeyframes(), outcome.events.size(), CountAccepted(outcome.events), full,
              before, after);
  // Loops facing back along the corridor, and the end walls, fix the axis as well.
  EXPECT_GE(full, 5u);
  EXPECT_LT(after * 2.0, before);
  // map -> odom for the newest scan (what /tf carries): its corrected pose over its odometry,
  // and far from identity after this much drift was removed.
  const OdometryResult& last = run.odometry.back();
  const Eigen::Isometry3d T_map_odom = backend.MapFromOdom();
  const Eigen::Isometry3d expected = outcome.corrected.back() * last.T_world_sensor.inverse();
  EXPECT_LT((T_map_odom.translation() - expected.translation()).norm(), 1e-9);
  EXPECT_LT(Eigen::AngleAxisd(T_map_odom.rotation().transpose() * expected.rotation()).angle(), 1e-9);
  EXPECT_GT((outcome.corrected.back().translation() - last.T_world_sensor.translation()).norm(), 0.05);
}

// The same walk with odometry that does not drift: loops that agree with the map within their
// noise stay out of the graph and start no solve. (The one or two whose registration noise
// passes the bound still start one: this test's loops move exact odometry by ~5 cm either way.)
double LargestMove(const Outcome& outcome, const SimRun& run) {
  double moved = 0.0;
  for (std::size_t i = 0; i < run.odometry.size(); ++i) {
    moved = std::max(moved, (outcome.corrected[i].translation() -
                             run.odometry[i].T_world_sensor.translation()).norm());
  }
  return moved;
}

TEST(LoopClosure, LoopsThatAgreeWithTheMapLeaveTheTrajectoryAlone) {
  const sim::Simulator simulator(sim::SceneKind::CorridorReturn, test::TestSensor());
  const int stride = 10;
  const SimRun run = MakeSimRun(simulator, 60, stride, DriftModel{0.0, 0.0});
  BackendConfig config = CorridorReturnConfig();
  LoopClosingBackend backend(config);
  const Outcome outcome = RunBackendStepByStep(backend, run);
  std::size_t accepted = 0, agreeing = 0;
  for (const LoopEvent& e : outcome.events) {
    if (!e.accepted) continue;
    ++accepted;
    EXPECT_DOUBLE_EQ(e.map_chi2_bound, 1.0);
    EXPECT_EQ(e.started_optimization, e.map_chi2 > e.map_chi2_bound) << e.reason;
    if (e.started_optimization) {
      // The solve it started is reported with the graph it solved (one node per keyframe).
      EXPECT_GT(e.solve_ms, 0.0);
      EXPECT_GT(e.graph_nodes, e.query_keyframe);
      EXPECT_LE(e.graph_nodes, backend.NumKeyframes());
      continue;
    }
    EXPECT_EQ(e.solve_ms, 0.0);
    EXPECT_EQ(e.graph_nodes, 0u);
    ++agreeing;
    EXPECT_NE(e.reason.find("agrees with the map"), std::string::npos) << e.reason;
  }
  // Solving after every loop instead: every loop's noise is carried into the trajectory.
  config.loop_optimize_residual = 0.0;
  LoopClosingBackend eager(config);
  const Outcome eager_outcome = RunBackendStepByStep(eager, run);
  const double moved = LargestMove(outcome, run), eager_moved = LargestMove(eager_outcome, run);
  std::printf("exact odometry: %zu loops accepted, %zu agree with the map; %zu solves move the "
              "trajectory by up to %.4f m; solving after every loop (%zu solves) by %.4f m\n",
              accepted, agreeing, backend.NumOptimizations(), moved, eager.NumOptimizations(),
              eager_moved);
  EXPECT_GE(accepted, 5u);
  EXPECT_GT(agreeing * 4, accepted * 3);  // most loops agree and stay out of the graph
  EXPECT_LT(backend.NumOptimizations() * 5, accepted);
}

// Two identical floors 3 m apart: Scan Context and registration find a floor-2 place on the
// floor below (the walls match at any height; only the stairwell doors differ). Odometry, which
// climbed the stairs (here keeping 70 % of the climb, as the VLP-16 front end did), puts the
// query a storey up, far outside the odometry chain's and the loop's uncertainty: refused.
// Without that test the same walk accepts loops between the floors.
TEST(LoopClosure, TwoFloorsAreNeverJoined) {
  const auto preset = sim::FindPreset("two-floor");
  ASSERT_TRUE(preset.has_value());
  sim::SensorSpec sensor = test::TestSensor();  // 16 of its rings: a VLP-16's field of view
  sensor.vertical_angles_deg = sim::UniformVerticalAngles(16, 15.0, -15.0);
  const sim::Simulator simulator(*preset, sensor, 1);
  const int stride = 10;  // 1 s between keyframes, ~1.3 m of walk
  DriftModel drift{0.0005, 0.01};
  drift.climb_loss = 0.3;
  drift.translation_sigma = 0.01;
  drift.rotation_sigma = 0.001;
  const SimRun run = MakeSimRun(simulator, 245, stride, drift);
  BackendConfig config;
  config.scan_context.max_range = 30.0;  // indoor
  config.scan_context.sensor_height = 1.4;
  const auto count = [&](const Outcome& outcome, std::size_t& same_floor, std::size_t& between) {
    same_floor = between = 0;
    for (const LoopEvent& e : outcome.events) {
      const Eigen::Isometry3d T_true = run.truth[e.candidate_scan_index / stride].inverse() *
                                       run.truth[e.query_scan_index / stride];
      const bool false_loop =
          (T_true.translation() - e.T_candidate_query.translation()).norm() > 1.0;
      if (e.accepted) (false_loop ? between : same_floor) += 1;
      if (false_loop && !e.accepted && e.odometry_chi2 > e.odometry_chi2_bound) {
        EXPECT_NE(e.reason.find("inconsistent with odometry"), std::string::npos) << e.reason;
      }
    }
  };
  LoopClosingBackend backend(config);
  std::size_t same_floor = 0, between = 0;
  count(RunBackendStepByStep(backend, run), same_floor, between);
  config.odometry_consistency_chi2 = 0.0;
  LoopClosingBackend untested(config);
  std::size_t same_floor_untested = 0, between_untested = 0;
  count(RunBackendStepByStep(untested, run), same_floor_untested, between_untested);
  std::printf("two floors: %zu keyframes; loops accepted on one floor %zu, between floors %zu; "
              "without the consistency test %zu and %zu\n",
              backend.NumKeyframes(), same_floor, between, same_floor_untested, between_untested);
  EXPECT_EQ(between, 0u);
  EXPECT_GE(same_floor, 3u);
  EXPECT_GT(between_untested, 0u) << "the walk no longer tests loops between floors";
}

TEST(LoopClosure, UnknownScanHasNoCorrectedPose) {
  LoopClosingBackend backend;
  const Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  EXPECT_FALSE(backend.CorrectedPoseOf(7, T).has_value());
  EXPECT_TRUE(backend.Process().empty());
  OdometryResult empty_cloud;
  empty_cloud.scan_index = 3;
  backend.AddScan(empty_cloud);  // a keyframe with no points must not break anything
  EXPECT_TRUE(backend.Process().empty());
  EXPECT_TRUE(backend.CorrectedPoseOf(3, T).has_value());
  EXPECT_FALSE(backend.CorrectedPoseOf(2, T).has_value());  // before the first scan
  EXPECT_FALSE(backend.CorrectedPoseOf(4, T).has_value());  // not added yet
}

}  // namespace
}  // namespace dammloam::backend
