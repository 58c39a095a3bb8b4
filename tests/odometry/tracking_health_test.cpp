// Tracking health: each state from its own evidence, and on simulated sequences with injected
// failures (a scan turned by 90 deg, the sensor covered for 2 s, the sensor carried elsewhere)
// the state goes to lost and back, and no lost scan enters the map; scans kept at 2 Hz are
// followed through a swing and along a corridor.
#include "core/odometry/tracking_health.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/odometry/pipeline.hpp"
#include "tools/benchmark/sim_run.hpp"
#include "tools/simulate/presets.hpp"
#include "tools/simulate/simulator.hpp"

namespace dammloam {
namespace {

FitEvidence GoodFit() { return {true, 0.8, 0.01, 0.3}; }

TrackingHealth AfterGoodScans() {
  TrackingHealth health{TrackingHealthConfig{}};
  for (double share : {0.78, 0.8, 0.82, 0.79, 0.81}) health.Record(share);
  return health;
}

TEST(TrackingHealth, AFitLikeRecentOnesIsTracking) {
  EXPECT_EQ(AfterGoodScans().Judge(GoodFit()), Tracking::kTracking);
  EXPECT_NEAR(AfterGoodScans().ReferenceShare(), 0.8, 1e-12);
}

TEST(TrackingHealth, UnconvergedOrFarFromThePredictionIsDegraded) {
  FitEvidence unconverged = GoodFit();
  unconverged.converged = false;
  EXPECT_EQ(AfterGoodScans().Judge(unconverged), Tracking::kDegraded);
  FitEvidence far = GoodFit();
  far.innovation = 0.5;  // beyond the 0.3 m gate
  EXPECT_EQ(AfterGoodScans().Judge(far), Tracking::kDegraded);
}

TEST(TrackingHealth, PairsFallingToHalfIsDegradedToAQuarterLost) {
  FitEvidence half = GoodFit();
  half.paired_share = 0.4;
  EXPECT_EQ(AfterGoodScans().Judge(half), Tracking::kDegraded);
  half.converged = false;  // and the solve ran to its cap
  EXPECT_EQ(AfterGoodScans().Judge(half), Tracking::kLost);
  FitEvidence quarter = GoodFit();
  quarter.paired_share = 0.2;
  EXPECT_EQ(AfterGoodScans().Judge(quarter), Tracking::kLost);
}

TEST(TrackingHealth, NothingToCompareWithAtTheStart) {
  TrackingHealth health{TrackingHealthConfig{}};
  FitEvidence poor = GoodFit();
  poor.paired_share = 0.05;
  EXPECT_EQ(health.Judge(poor), Tracking::kTracking);
  health.Record(0.8);
  health.Record(0.8);
  health.Record(0.8);
  EXPECT_EQ(health.Judge(poor), Tracking::kLost);
  health.Clear();
  EXPECT_EQ(health.Judge(poor), Tracking::kTracking);
}

// The first scans of wheeled-zigzag (VLP-16, seed 1), with poses at every scan start.
const bench::SimSequence& Zigzag() {
  static const bench::SimSequence seq = bench::RecordSequence(
      sim::Simulator(*sim::FindPreset("wheeled-zigzag"), sim::Vlp16(), 1), 100);
  return seq;
}

std::vector<OdometryResult> RunScans(const std::vector<Scan>& scans, const SensorModel& model) {
  OdometryPipeline pipeline(OdometryConfig{}, model);
  std::vector<OdometryResult> out;
  for (const Scan& scan : scans) out.push_back(pipeline.Process(scan));
  return out;
}

Scan TurnedAboutZ(Scan scan, double degrees) {
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (Eigen::Vector3d& p : scan.points) p = R * p;
  return scan;
}

TEST(TrackingHealthOnSequences, AScanTurnedBy90DegreesIsLostAndNeverMapped) {
  const bench::SimSequence& seq = Zigzag();
  constexpr std::size_t kBad = 30;
  std::vector<Scan> with_bad(seq.scans.begin(), seq.scans.begin() + 45);
  with_bad[kBad] = TurnedAboutZ(with_bad[kBad], 90.0);
  std::vector<Scan> without(with_bad);
  without.erase(without.begin() + kBad);
  const auto bad_run = RunScans(with_bad, seq.model);
  const auto clean_run = RunScans(without, seq.model);
  for (std::size_t i = 1; i < kBad; ++i) EXPECT_EQ(bad_run[i].tracking, Tracking::kTracking) << i;
  EXPECT_EQ(bad_run[kBad].tracking, Tracking::kLost);
  EXPECT_EQ(bad_run[kBad].status, OdometryStatus::kLost);
  std::printf("turned scan: paired share %.3f against %.3f before\n", bad_run[kBad].paired_share,
              bad_run[kBad - 1].paired_share);
  for (std::size_t i = kBad + 1; i < with_bad.size(); ++i) {
    EXPECT_EQ(bad_run[i].tracking, Tracking::kTracking) << i;
    // Nothing of the turned scan stayed behind: every later pose is what it is without it.
    EXPECT_TRUE(bad_run[i].T_world_sensor.matrix() == clean_run[i - 1].T_world_sensor.matrix()) << i;
  }
}

// Scans kept at 2 Hz (every 5th), without point times, and the sensor swung 50 deg about the
// vertical between two of them (a hand-held sensor turned sharply): the prediction is 50 deg off and its registration
// pairs far fewer points than the scans before; the search over turned predictions finds the
// swing and tracking goes on. Without the search the scan sits 25 deg off in a wrong basin.
TEST(TrackingHealthOnSequences, ASwingOf50DegreesBetweenSparseScansIsFound) {
  const bench::SimSequence& seq = Zigzag();
  constexpr std::size_t kEvery = 5, kSwing = 12;
  constexpr double kDegrees = 50.0;
  std::vector<Scan> scans;
  std::vector<Eigen::Isometry3d> truth;
  for (std::size_t i = 0; i < seq.scans.size(); i += kEvery) {
    scans.push_back(seq.scans[i]);
    // As the recording of issue 58: compensated by the recorder, no point times. (With times,
    // the scan after the swing is deskewed with the swing's 100 deg/s and bent by 10 deg.)
    scans.back().times.clear();
    truth.push_back(seq.ground_truth[i].T);
  }
  // From kSwing on the sensor is turned by +kDegrees about its z axis: it sees the world
  // turned by -kDegrees.
  const Eigen::Isometry3d turn(Eigen::AngleAxisd(kDegrees * std::numbers::pi / 180.0, Eigen::Vector3d::UnitZ()));
  for (std::size_t i = kSwing; i < scans.size(); ++i) {
    scans[i] = TurnedAboutZ(scans[i], -kDegrees);
    truth[i] = truth[i] * turn;
  }
  auto run_with = [&](double max_turn_rate) {
    OdometryConfig config;
    config.health.max_turn_rate_deg_s = max_turn_rate;
    OdometryPipeline pipeline(config, seq.model);
    std::vector<OdometryResult> out;
    for (const Scan& scan : scans) out.push_back(pipeline.Process(scan));
    return out;
  };
  auto step_error = [&](const std::vector<OdometryResult>& run, std::size_t i) {
    const Eigen::Isometry3d step = run[i - 1].T_world_sensor.inverse() * run[i].T_world_sensor;
    const Eigen::Isometry3d error = (truth[i - 1].inverse() * truth[i]).inverse() * step;
    return std::pair{error.translation().norm(),
                     Eigen::AngleAxisd(error.rotation()).angle() * 180.0 / std::numbers::pi};
  };
  const auto searched = run_with(TrackingHealthConfig{}.max_turn_rate_deg_s);
  const auto [metres, degrees] = step_error(searched, kSwing);
  std::printf("swing of %.0f deg at 2 Hz: step error %.3f m %.2f deg, %s\n", kDegrees, metres,
              degrees, std::string(Name(searched[kSwing].tracking)).c_str());
  EXPECT_EQ(searched[kSwing].status, OdometryStatus::kOk);
  EXPECT_EQ(searched[kSwing].tracking, Tracking::kDegraded);  // re-acquired
  EXPECT_LT(metres, 0.05);
  EXPECT_LT(degrees, 1.0);
  for (std::size_t i = kSwing + 1; i < scans.size(); ++i) {
    // The scan after is predicted to swing on and is found by search again (degraded).
    if (i > kSwing + 1) {
      EXPECT_EQ(searched[i].tracking, Tracking::kTracking) << i;
    }
    EXPECT_LT(step_error(searched, i).first, 0.05) << i;
    EXPECT_LT(step_error(searched, i).second, 1.0) << i;
  }
  const auto unsearched = run_with(0.0);  // only the prediction itself is tried again
  const auto [metres_without, degrees_without] = step_error(unsearched, kSwing);
  std::printf("without the search: %.3f m %.2f deg\n", metres_without, degrees_without);
  EXPECT_GT(degrees_without, 5.0);
}

// The hand-held corridor (VLP-16, seed 1) kept at 2 Hz: the walls leave the axis degenerate,
// so between scans 0.5 s apart the position along it rests on the motion prior. With the
// prior's position sigma growing as dt^2 (0.5 m at 2 Hz) thinned scan 60 followed a door
// recess a stride back (0.58 m) and the estimate lagged the walk from there on (21 % of the
// whole walk's steps tracked). With the gait's part bounded (motion_prior.gait_time) and a
// registration far off the prediction along the axis held there, every step is tracked.
TEST(TrackingHealthOnSequences, SparseCorridorScansKeepUpWithTheWalk) {
  constexpr std::size_t kEvery = 5, kKept = 70;
  const bench::SimSequence seq = bench::RecordSequence(
      sim::Simulator(*sim::FindPreset("handheld-corridor"), sim::Vlp16(), 1), kEvery * kKept);
  std::vector<Scan> scans;
  std::vector<Eigen::Isometry3d> truth;
  for (std::size_t i = 0; i < seq.scans.size(); i += kEvery) {
    scans.push_back(seq.scans[i]);
    truth.push_back(seq.ground_truth[i].T);
  }
  auto worst_step = [&](const OdometryConfig& config) {
    OdometryPipeline pipeline(config, seq.model);
    std::vector<OdometryResult> run;
    for (const Scan& scan : scans) run.push_back(pipeline.Process(scan));
    std::pair<double, double> worst{0.0, 0.0};  // metres, degrees
    for (std::size_t i = 1; i < run.size(); ++i) {
      const Eigen::Isometry3d step = run[i - 1].T_world_sensor.inverse() * run[i].T_world_sensor;
      const Eigen::Isometry3d error = (truth[i - 1].inverse() * truth[i]).inverse() * step;
      worst.first = std::max(worst.first, error.translation().norm());
      worst.second = std::max(worst.second, Eigen::AngleAxisd(error.rotation()).angle() * 180.0 / std::numbers::pi);
    }
    return worst;
  };
  const auto [metres, degrees] = worst_step(OdometryConfig{});
  OdometryConfig unbounded;
  unbounded.motion_prior.gait_time = 1.0;
  unbounded.degenerate_gate_sigmas = 0.0;
  const auto [metres_before, degrees_before] = worst_step(unbounded);
  std::printf("2 Hz corridor, worst step: %.3f m %.2f deg (prior as dt^2, never held: %.3f m %.2f deg)\n",
              metres, degrees, metres_before, degrees_before);
  EXPECT_LT(metres, 0.1);
  EXPECT_LT(degrees, 2.0);
  EXPECT_GT(metres_before, 0.3);
}

// Position error of each pose against the truth, both taken relative to the first scan.
std::vector<double> PositionErrors(const std::vector<OdometryResult>& run, const bench::SimSequence& seq) {
  std::vector<double> errors;
  for (std::size_t i = 0; i < run.size(); ++i) {
    const Eigen::Vector3d truth =
        (seq.ground_truth[0].T.inverse() * seq.ground_truth[i].T).translation();
    errors.push_back((run[i].T_world_sensor.translation() - truth).norm());
  }
  return errors;
}

TEST(TrackingHealthOnSequences, CoveredFor2SecondsIsLostThenTrackingAgain) {
  const bench::SimSequence& seq = Zigzag();
  std::vector<Scan> scans(seq.scans.begin(), seq.scans.begin() + 75);
  constexpr std::size_t kCovered = 35, kUncovered = 55;
  for (std::size_t i = kCovered; i < kUncovered; ++i) {
    const double t = scans[i].t_start;
    scans[i] = Scan{};
    scans[i].t_start = t;
  }
  const auto run = RunScans(scans, seq.model);
  const std::vector<double> errors = PositionErrors(run, seq);
  for (std::size_t i = kCovered; i < kUncovered; ++i) EXPECT_EQ(run[i].tracking, Tracking::kLost) << i;
  std::size_t back = kUncovered;
  while (back < run.size() && run[back].tracking != Tracking::kTracking) ++back;
  std::printf("covered 2 s: moved %.2f m meanwhile; tracking again %zu scans later, error %.3f m there, "
              "%.3f m at the end\n",
              (seq.ground_truth[kCovered - 1].T.translation() - seq.ground_truth[kUncovered].T.translation()).norm(),
              back - kUncovered, errors[back], errors.back());
  EXPECT_LE(back, kUncovered + 3);
  EXPECT_LT(errors.back(), 0.1);
}

// Carried to a place the map never saw (the robot moved while the odometry was down): every
// scan is lost against the old map, until after restart_after_lost_scans the map starts over
// there and tracking resumes in it.
TEST(TrackingHealthOnSequences, CarriedElsewhereIsLostThenTheMapStartsOver) {
  const bench::SimSequence& zigzag = Zigzag();
  const bench::SimSequence outdoor = bench::GenerateSequence(sim::SceneKind::Outdoor, sim::Vlp16(), 45);
  constexpr std::size_t kAway = 25;
  std::vector<Scan> scans(zigzag.scans.begin(), zigzag.scans.begin() + kAway);
  for (std::size_t i = 20; i < outdoor.scans.size(); ++i) {
    scans.push_back(outdoor.scans[i]);
    scans.back().t_start = scans[scans.size() - 2].t_start + 0.1;
  }
  const auto run = RunScans(scans, zigzag.model);
  const int limit = TrackingHealthConfig{}.restart_after_lost_scans;
  for (int k = 0; k + 1 < limit; ++k) {
    EXPECT_FALSE(Registered(run[kAway + k].status)) << kAway + k;  // lost, or no pairs at all
    EXPECT_EQ(run[kAway + k].tracking, Tracking::kLost) << kAway + k;
  }
  const std::size_t restart = kAway + static_cast<std::size_t>(limit) - 1;
  EXPECT_EQ(run[restart].status, OdometryStatus::kRestarted);
  std::size_t tracked_after = 0;
  for (std::size_t i = restart + 1; i < run.size(); ++i) {
    tracked_after += run[i].tracking == Tracking::kTracking;
    // The outdoor drive's own steps are followed in the new map.
    const Eigen::Isometry3d truth = outdoor.ground_truth[i - kAway + 19].T.inverse() * outdoor.ground_truth[i - kAway + 20].T;
    const Eigen::Isometry3d step = run[i - 1].T_world_sensor.inverse() * run[i].T_world_sensor;
    // The first step starts from rest in a one-scan map while the sensor drives on (as a
    // fresh start does): within the tracked-step bound; the rest within 5 cm.
    EXPECT_LT((truth.inverse() * step).translation().norm(), i == restart + 1 ? 0.1 : 0.05) << i;
  }
  EXPECT_GE(tracked_after, run.size() - restart - 4);
}

}  // namespace
}  // namespace dammloam
