// Tracking on short simulated sequences with stated bounds that fail if tracking breaks.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "core/odometry/pipeline.hpp"
#include "tools/benchmark/sim_run.hpp"
#include "tools/simulate/presets.hpp"
#include "tools/simulate/simulator.hpp"

namespace dammloam {
namespace {

using bench::GenerateSequence;
using bench::RunPipeline;

OdometryConfig WithMode(RegistrationMode mode) {
  OdometryConfig config;
  config.registration.mode = mode;
  return config;
}

// The first `scans` scans of the hand-held corridor preset seen by a VLP-16.
bench::SimSequence HandheldCorridorVlp16(std::uint64_t seed, int scans) {
  return bench::RecordSequence(
      sim::Simulator(*sim::FindPreset("handheld-corridor"), sim::Vlp16(), seed), scans);
}

TEST(OdometryIntegration, ZigzagCorridorIsTracked) {
  // OS1-64: on VLP-16 the zigzag drifts more (see the benchmark), bounded in the next test.
  const auto seq = GenerateSequence(sim::SceneKind::Zigzag, sim::Os1_64(), 40);
  const auto run = RunPipeline(seq, WithMode(RegistrationMode::kFull));
  EXPECT_EQ(run.registered, seq.scans.size());
  EXPECT_LT(run.ape_rmse, 0.25) << "zigzag APE RMSE";
}

TEST(OdometryIntegration, OutdoorLoopIsTracked) {
  const auto seq = GenerateSequence(sim::SceneKind::Outdoor, sim::Vlp16(), 40);
  const auto run = RunPipeline(seq, WithMode(RegistrationMode::kFull));
  EXPECT_EQ(run.registered, seq.scans.size());
  EXPECT_LT(run.ape_rmse, 0.2) << "outdoor APE RMSE";
  EXPECT_LT(run.rpe_rmse, 0.1) << "outdoor RPE RMSE";
}

// In the featureless corridor the weakest translational direction is the corridor axis (+-x in
// the simulator's world frame), and lateral/vertical motion stays
// tracked.
TEST(OdometryIntegration, CorridorDegenerateAxisIsX) {
  const auto seq = GenerateSequence(sim::SceneKind::Corridor, sim::Os1_64(), 20);
  const auto run = RunPipeline(seq, WithMode(RegistrationMode::kFull));
  for (std::size_t i = 2; i < run.results.size(); ++i) {
    const DegeneracyReport& d = run.results[i].degeneracy;
    const Eigen::Vector3d weakest = d.eigenvectors.col(0);
    EXPECT_GT(std::abs(weakest.x()), std::cos(5.0 * M_PI / 180.0)) << "scan " << i;
    EXPECT_FALSE(d.degenerate[2]) << "scan " << i;
    // The end walls 10 m+ away keep x weakly observable: an order of magnitude below the
    // strongest direction (the infinite-corridor case, flagged degenerate, is pinned in
    // registration_test).
    EXPECT_LT(d.eigenvalues(0), 0.15 * d.eigenvalues(2)) << "scan " << i;
    // The covariance is largest along x.
    EXPECT_GT(run.results[i].covariance(0, 0), run.results[i].covariance(1, 1)) << "scan " << i;
  }
  for (std::size_t i = 0; i < seq.scans.size(); ++i) {
    const Eigen::Vector3d gt = seq.ground_truth[0].T.inverse() * seq.ground_truth[i].T.translation();
    const Eigen::Vector3d est = run.estimate[i].T.translation();
    EXPECT_NEAR(est.y(), gt.y(), 0.1) << "scan " << i;
    EXPECT_NEAR(est.z(), gt.z(), 0.1) << "scan " << i;
  }
}

// A VLP-16 down 30 m of featureless corridor: once the end walls are 20-40 m away nothing but
// the constant-velocity model knows the axis, and point pairs on the ring pattern pull towards
// standstill. The full method keeps the model's prediction there (with hysteresis, so a scan at
// the threshold cannot kick the held velocity), and its error is set by the velocity it held
// when the walls faded: measured over simulator seeds 1-4, full 0.74 / 0.43 / 0.12 / 0.27 m,
// point-to-point 8.6 m every time. Without remapping the full method drifted like
// point-to-point (7.8 m); without hysteresis 0.06 to 2.5 m.
TEST(OdometryIntegration, LongSparseCorridorDoesNotCollapseToStandstill) {
  const auto seq = GenerateSequence(sim::SceneKind::Corridor, sim::Vlp16(), 300);
  const auto full = RunPipeline(seq, WithMode(RegistrationMode::kFull));
  const auto p2p = RunPipeline(seq, WithMode(RegistrationMode::kPointToPoint));
  EXPECT_EQ(full.registered, seq.scans.size());
  EXPECT_LT(full.ape_rmse, 1.5) << "full APE RMSE";
  EXPECT_GT(p2p.ape_rmse, 5.0 * full.ape_rmse) << "point-to-point APE RMSE";
}

// Honest uncertainty: in the featureless corridor the pose's covariance along the corridor axis
// (world x) grows scan by scan while the axis stays weak, and stays small across it, where the
// walls hold the pose.
TEST(OdometryIntegration, PoseCovarianceGrowsAlongTheWeakAxisWhileItIsWeak) {
  const auto seq = GenerateSequence(sim::SceneKind::Corridor, sim::Vlp16(), 160);
  const auto run = RunPipeline(seq, WithMode(RegistrationMode::kFull));
  ASSERT_EQ(run.registered, seq.scans.size());
  // The longest stretch of consecutive scans whose weak direction is the axis.
  std::size_t best_begin = 0, best_length = 0, begin = 0;
  auto weak_along_axis = [&](const OdometryResult& r) {
    const DegeneracyReport& d = r.degeneracy;
    for (int i = 0; i < 3; ++i) {
      if (d.degenerate[static_cast<std::size_t>(i)] && std::abs(d.eigenvectors(0, i)) > 0.9) {
        return true;
      }
    }
    return false;
  };
  for (std::size_t i = 1; i < run.results.size(); ++i) {
    if (!weak_along_axis(run.results[i])) {
      begin = i + 1;
    } else if (i + 1 - begin > best_length) {
      best_begin = begin;
      best_length = i + 1 - begin;
    }
  }
  ASSERT_GE(best_length, 40u) << "the corridor axis should stay weak for a while";
  const Matrix6d& early = run.results[best_begin + 5].pose_covariance;
  const Matrix6d& late = run.results[best_begin + best_length - 1].pose_covariance;
  EXPECT_GT(late(0, 0), 4.0 * early(0, 0)) << "axis variance did not grow while weak";
  EXPECT_GT(late(0, 0), 100.0 * late(1, 1)) << "axis not the uncertain direction";
  EXPECT_LT(std::sqrt(late(1, 1)), 0.01) << "the walls should hold the pose across";
}

// Memory stays flat on a long drive: the map is cropped to max_distance around the sensor, so
// once the sensor has left its start that far behind, the map's size stops growing. Without
// the crop the same drive holds far more: the whole corridor the sensor has seen.
TEST(OdometryIntegration, MapSizeIsBoundedOnALongDrive) {
  const auto seq = GenerateSequence(sim::SceneKind::Corridor, sim::Vlp16(), 400);  // 38 m
  auto map_points = [&](double max_distance) {
    OdometryConfig config;
    config.map.max_distance = max_distance;
    const auto run = RunPipeline(seq, config);
    EXPECT_EQ(run.registered, seq.scans.size());
    std::size_t peak_first_half = 0, peak_second_half = 0;
    for (std::size_t i = 0; i < run.results.size(); ++i) {
      std::size_t& peak = i < run.results.size() / 2 ? peak_first_half : peak_second_half;
      peak = std::max(peak, run.results[i].map_points);
    }
    return std::pair{peak_first_half, peak_second_half};
  };
  const auto [cropped_first, cropped_second] = map_points(8.0);
  EXPECT_GT(cropped_first, 1000u);
  // How many points the 8 m ball holds depends on where the rings fell: 1.06-1.11 over
  // trajectories that differ by a millimetre per scan (stretch factors 1.0-2.0); uncropped 1.39.
  EXPECT_LT(double(cropped_second), 1.15 * double(cropped_first)) << "cropped map kept growing";
  const auto [kept_first, kept_second] = map_points(1000.0);
  EXPECT_GT(double(kept_second), 1.5 * double(cropped_second)) << "the drive does not test the crop";
}

// Odometry started while the sensor is already moving (a daemon restarted on a driving robot):
// the first scans are deskewed under a zero-velocity guess. The first registration measures the
// motion; the first scan and itself are then deskewed again, so the very first steps come out
// at the true speed instead of one of them being centimetres off.
TEST(OdometryIntegration, StartWhileMovingRecoversTheSpeedAtOnce) {
  const auto seq = GenerateSequence(sim::SceneKind::Outdoor, sim::Vlp16(), 46);
  auto first_step_errors = [&](double max_deviation) {
    OdometryConfig config;
    config.motion_model_max_deviation = max_deviation;
    OdometryPipeline pipeline(config, seq.model);
    std::vector<double> errors;
    Eigen::Isometry3d last = Eigen::Isometry3d::Identity();
    for (std::size_t i = 40; i < seq.scans.size(); ++i) {  // at speed after the 2 s ramp-up
      const OdometryResult r = pipeline.Process(seq.scans[i]);
      EXPECT_TRUE(Registered(r.status)) << "scan " << i;
      if (i > 40) {
        const Eigen::Vector3d step = (last.inverse() * r.T_world_sensor).translation();
        const Eigen::Vector3d truth =
            (seq.ground_truth[i - 1].T.inverse() * seq.ground_truth[i].T).translation();
        errors.push_back((step - truth).norm());
      }
      last = r.T_world_sensor;
    }
    return errors;
  };
  const std::vector<double> redeskewed = first_step_errors(0.1);
  const std::vector<double> guessed = first_step_errors(1e9);  // never deskewed again
  std::printf("first steps, error m: redeskewed %.4f %.4f, guessed %.4f %.4f\n", redeskewed[0],
              redeskewed[1], guessed[0], guessed[1]);
  // Measured: first two steps 7.2 / 1.4 mm deskewed again, 7.9 / 49.7 mm on the guess.
  for (double e : redeskewed) EXPECT_LT(e, 0.02);
  const double worst_redeskewed = *std::max_element(redeskewed.begin(), redeskewed.end());
  const double worst_guessed = *std::max_element(guessed.begin(), guessed.end());
  EXPECT_GT(worst_guessed, 3.0 * worst_redeskewed);
}

// The adaptive threshold measures rotation errors at the scene's scale: in a 2.4 m corridor the
// points that matter lie within metres, and measuring at map.max_distance (100 m, KISS-ICP's
// sensor range) turned the 0.5 deg shake of a hand-held walk into a 4.7 m correspondence gate
// along which single scans slid 0.2 m. The gate must shrink with the scene and tracking must hold.
TEST(OdometryIntegration, TheCorrespondenceGateFollowsTheSceneSize) {
  const bench::SimSequence seq = HandheldCorridorVlp16(/*seed=*/1, /*scans=*/80);
  auto run_with = [&](double factor) {
    OdometryConfig config;
    config.threshold_range_factor = factor;
    return RunPipeline(seq, config);
  };
  const auto scene_scale = run_with(OdometryConfig{}.threshold_range_factor);
  const auto sensor_range = run_with(0.0);
  ASSERT_EQ(scene_scale.registered, seq.scans.size());
  const double gate_scene = scene_scale.results.back().correspondence_gate;
  const double gate_range = sensor_range.results.back().correspondence_gate;
  std::printf("gate %.3f m at scene scale, %.3f m at 100 m; APE %.4f / %.4f m\n", gate_scene,
              gate_range, scene_scale.ape_rmse, sensor_range.ape_rmse);
  EXPECT_LT(gate_scene, 0.5 * gate_range);
  EXPECT_GE(gate_scene, 0.3 - 1e-12) << "never below 3x the deviation floor (0.1 m)";
  EXPECT_LT(scene_scale.ape_rmse, 0.05);
}

// A walker's bob and a hand's shake change the velocity within a tenth of a second. The start
// pose interpolated between two registered mid-scan poses follows that; extrapolating back from
// one mid-scan pose with the previous scan's velocity puts its error into every pose.
TEST(OdometryIntegration, InterpolatedStartPosesFollowAHandHeldWalk) {
  const bench::SimSequence seq = HandheldCorridorVlp16(/*seed=*/2, /*scans=*/120);
  auto run_with = [&](bool interpolate) {
    OdometryConfig config;
    config.interpolate_start_pose = interpolate;
    return RunPipeline(seq, config);
  };
  const auto interpolated = run_with(true);
  const auto extrapolated = run_with(false);
  std::printf("RPE %.4f m interpolated, %.4f m extrapolated; APE %.4f / %.4f m\n",
              interpolated.rpe_rmse, extrapolated.rpe_rmse, interpolated.ape_rmse,
              extrapolated.ape_rmse);
  ASSERT_EQ(interpolated.registered, seq.scans.size());
  EXPECT_LT(interpolated.rpe_rmse, 0.7 * extrapolated.rpe_rmse);
  EXPECT_LT(interpolated.ape_rmse, extrapolated.ape_rmse);
}

// A recorder that motion-compensates the cloud itself writes every point's time as 0: there is
// nothing left to deskew, and deskewing with those times bent the cloud (0.5-3 deg a step on a
// real hand-held recording). Such a cloud is registered as instantaneous: the same poses to the
// bit with deskew on and off, tracked as well as the compensated cloud allows.
TEST(OdometryIntegration, CompensatedCloudsWithZeroTimesAreNotDeskewedAgain) {
  bench::SimSequence seq = HandheldCorridorVlp16(/*seed=*/1, /*scans=*/41);
  const bench::SimSequence timed_seq = [&] {
    bench::SimSequence first = seq;
    first.scans.resize(10);
    first.ground_truth.resize(10);
    return first;
  }();
  // Compensate each scan with the true motion to its start frame, as the recorder did.
  for (std::size_t i = 0; i + 1 < seq.scans.size(); ++i) {
    Scan& scan = seq.scans[i];
    const Eigen::Isometry3d T_start_end = seq.ground_truth[i].T.inverse() * seq.ground_truth[i + 1].T;
    const double period = seq.ground_truth[i + 1].t - seq.ground_truth[i].t;
    for (std::size_t k = 0; k < scan.size(); ++k) {
      scan.points[k] = ScaleMotion(T_start_end, scan.times[k] / period) * scan.points[k];
      scan.times[k] = 0.0f;
    }
  }
  seq.scans.pop_back();
  seq.ground_truth.pop_back();
  auto run_with = [&](bool deskew) {
    OdometryConfig config;
    config.deskew = deskew;
    return RunPipeline(seq, config);
  };
  const auto on = run_with(true);
  const auto off = run_with(false);
  ASSERT_EQ(on.registered, seq.scans.size());
  for (const OdometryResult& r : on.results) EXPECT_EQ(r.point_times, PointTimeCheck::kConstant);
  for (std::size_t i = 0; i < seq.scans.size(); ++i) {
    EXPECT_TRUE(on.estimate[i].T.matrix() == off.estimate[i].T.matrix()) << "scan " << i;
  }
  std::printf("compensated, zero times: APE %.4f m\n", on.ape_rmse);
  EXPECT_LT(on.ape_rmse, 0.05);
  // The same scans with their firing times are deskewed.
  const auto timed = RunPipeline(timed_seq, OdometryConfig{});
  for (const OdometryResult& r : timed.results) EXPECT_EQ(r.point_times, PointTimeCheck::kUsable);
}

// A known rigid motion between two real-geometry scans (outdoor scene, 5 scans apart).
TEST(OdometryIntegration, KnownMotionBetweenTwoScansIsRecovered) {
  // The simulated drive starts from rest: take two scans after the 2 s ramp-up.
  const auto seq = GenerateSequence(sim::SceneKind::Outdoor, sim::Os1_64(), 34);
  OdometryPipeline pipeline(OdometryConfig{}, seq.model);
  const OdometryResult first = pipeline.Process(seq.scans[30]);
  ASSERT_EQ(first.status, OdometryStatus::kFirstScan);
  const OdometryResult r = pipeline.Process(seq.scans[33]);
  ASSERT_TRUE(Registered(r.status));
  // The search's work is reported: none for the first scan (no map yet), and every pair found
  // was looked up at least once.
  EXPECT_EQ(first.searched_points, 0u);
  EXPECT_GT(r.num_correspondences, 0u);
  EXPECT_GE(r.searched_points, r.num_correspondences);
  const Eigen::Isometry3d gt = seq.ground_truth[30].T.inverse() * seq.ground_truth[33].T;
  const Vector6d error = LogSE3(gt.inverse() * r.T_world_sensor);
  EXPECT_GT(gt.translation().norm(), 0.3);  // the motion is not trivial
  EXPECT_LT(error.head<3>().norm(), 0.05);
  EXPECT_LT(error.tail<3>().norm(), 0.5 * M_PI / 180.0);
}

}  // namespace
}  // namespace dammloam
