// Runs the built dammloam-odometry on a short simulated outdoor VLP-16 sequence (written by
// the simulator, with exact ground truth): loop closure on and off, map save then localization,
// and the errors for a corrupt map or bad arguments.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <map>

#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"
#include "io/sequence_io.hpp"
#include "io/mapstore/map_store.hpp"
#include "tools/simulate/inertial_streams.hpp"
#include "tools/simulate/simulator.hpp"

namespace dammloam {
namespace {

constexpr int kScans = 30;
// The simulated drive starts from rest; the test sequence starts at cruise speed (after the
// simulator's 2 s ramp-up) so that it tests the runner rather than the odometry's start-up.
constexpr int kFirstScan = 25;

using test::CommandResult;

std::string Binary() { return DAMMLOAM_BIN_DIR "/dammloam-odometry"; }

// Output is stdout and stderr together.
CommandResult RunOdometry(const std::string& arguments) {
  return test::RunCommand(Binary() + " " + arguments + " 2>&1");
}

// Largest position difference between poses of equal stamps; fails if a stamp of `b` is
// missing from `a`.
// The largest position error of `est` against `gt` from their first poses on (each taken
// relative to its first pose, as the estimate starts at identity).
double MaxErrorFromStart(const std::vector<io::StampedPose>& est, const std::vector<io::StampedPose>& gt) {
  std::map<double, Eigen::Isometry3d> truth;
  for (const io::StampedPose& p : gt) truth[p.t] = p.T;
  if (est.empty()) return 1e9;
  const auto first = truth.lower_bound(est.front().t - 1e-6);
  if (first == truth.end()) return 1e9;
  double worst = 0.0;
  for (const io::StampedPose& p : est) {
    const auto it = truth.lower_bound(p.t - 1e-6);
    if (it == truth.end() || it->first > p.t + 1e-6) return 1e9;
    const Eigen::Vector3d t_gt = (first->second.inverse() * it->second).translation();
    const Eigen::Vector3d t_est = (est.front().T.inverse() * p.T).translation();
    worst = std::max(worst, (t_gt - t_est).norm());
  }
  return worst;
}

double MaxPositionDifference(const std::vector<io::StampedPose>& a,
                             const std::vector<io::StampedPose>& b) {
  std::map<double, Eigen::Vector3d> by_stamp;
  for (const io::StampedPose& p : a) by_stamp[p.t] = p.T.translation();
  double worst = 0.0;
  for (const io::StampedPose& p : b) {
    const auto it = by_stamp.lower_bound(p.t - 1e-6);
    if (it == by_stamp.end() || it->first > p.t + 1e-6) {
      ADD_FAILURE() << "stamp " << p.t << " missing";
      return 1e9;
    }
    worst = std::max(worst, (it->second - p.T.translation()).norm());
  }
  return worst;
}

class RunnerCli : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(Binary())) GTEST_SKIP() << Binary() << " not built";
    sim::SimOptions options;
    options.num_scans = kFirstScan + kScans;
    sim::SensorSpec sensor = sim::Vlp16();
    sensor.columns = 900;  // half the azimuth resolution: fast enough under the sanitizers
    const sim::Simulator simulator(sim::SceneKind::Outdoor, sensor, options);
    io::SequenceWriter writer(tmp_ / "seq",
                              io::SequenceMeta{"vlp-16-900", simulator.sensor_model(),
                                               io::PointLayout::kXYZITR});
    std::vector<io::StampedPose> gt;
    for (int i = 0; i < kScans; ++i) {
      const Scan scan = simulator.SimulateScan(kFirstScan + i);
      writer.Write(scan);
      gt.push_back({scan.t_start, simulator.PoseAt(scan.t_start)});
    }
    writer.WriteGroundTruth(gt);
    gt_ = gt;
  }
  std::string Path(const std::string& name) const { return (tmp_ / name).string(); }
  std::string Sequence() const { return Path("seq"); }

  test::TempDir tmp_;
  std::vector<io::StampedPose> gt_;
};

TEST_F(RunnerCli, WritesOnePosePerScanWithTheStampsOfTimesTxt) {
  const CommandResult run = RunOdometry(Sequence() + " --out " + Path("corrected.tum") +
                                        " --odometry-out " + Path("odometry.tum") + " --events " +
                                        Path("events.jsonl"));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto times = io::SequenceReader::Open(tmp_ / "seq").times();
  for (const char* file : {"corrected.tum", "odometry.tum"}) {
    const auto poses = io::ReadTum(tmp_ / file);
    ASSERT_EQ(poses.size(), times.size()) << file;
    for (std::size_t i = 0; i < poses.size(); ++i) EXPECT_NEAR(poses[i].t, times[i], 1e-9) << file;
  }
  EXPECT_TRUE(std::filesystem::exists(tmp_ / "events.jsonl"));
  // Both trajectories are evaluated against gt.tum. No loop is found in 3 m, so the corrected
  // trajectory is the odometry one (the odometry's accuracy is tests/odometry's business).
  EXPECT_NE(run.output.find("odometry vs gt.tum: APE RMSE"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("corrected vs gt.tum: APE RMSE"), std::string::npos) << run.output;
  EXPECT_EQ(test::ReadText(tmp_ / "events.jsonl").find("\"accepted\":true"), std::string::npos);
  EXPECT_LT(MaxPositionDifference(io::ReadTum(tmp_ / "odometry.tum"),
                                  io::ReadTum(tmp_ / "corrected.tum")), 1e-9);
}

TEST_F(RunnerCli, NoLoopClosureWritesTheOdometryTrajectory) {
  const CommandResult with = RunOdometry(Sequence() + " --quiet --out " + Path("corrected.tum") +
                                         " --odometry-out " + Path("odometry.tum"));
  ASSERT_EQ(with.exit_code, 0) << with.output;
  const CommandResult without =
      RunOdometry(Sequence() + " --no-loop-closure --out " + Path("plain.tum"));
  ASSERT_EQ(without.exit_code, 0) << without.output;
  EXPECT_EQ(without.output.find("corrected vs gt.tum"), std::string::npos) << without.output;
  const auto plain = io::ReadTum(tmp_ / "plain.tum");
  const auto odometry = io::ReadTum(tmp_ / "odometry.tum");
  ASSERT_EQ(plain.size(), static_cast<std::size_t>(kScans));
  ASSERT_EQ(odometry.size(), plain.size());
  EXPECT_LT(MaxPositionDifference(odometry, plain), 1e-6);
  // --events needs the loop-closing back-end.
  const CommandResult conflict = RunOdometry(Sequence() + " --no-loop-closure --out " +
                                             Path("x.tum") + " --events " + Path("e.jsonl"));
  EXPECT_NE(conflict.exit_code, 0) << conflict.output;
}

TEST_F(RunnerCli, SavedMapLocalizesTheSameSequence) {
  const CommandResult mapping = RunOdometry(Sequence() + " --quiet --out " +
                                            Path("corrected.tum") + " --save-map " + Path("map"));
  ASSERT_EQ(mapping.exit_code, 0) << mapping.output;
  const std::string map_json = test::ReadText(tmp_ / "map" / "map.json");

  const CommandResult localizing = RunOdometry(Sequence() + " --load-map " + Path("map") +
                                               " --localize --out " + Path("localized.tum"));
  ASSERT_EQ(localizing.exit_code, 0) << localizing.output;
  EXPECT_NE(localizing.output.find("localized vs gt.tum: APE RMSE"), std::string::npos)
      << localizing.output;
  const auto localized = io::ReadTum(tmp_ / "localized.tum");
  // Stated bounds: at least 80% of the scans localized, the scans that became keyframes found
  // within 0.10 m of their keyframe poses (same map frame, no alignment): the map was
  // built from exactly those clouds.
  EXPECT_GE(localized.size(), static_cast<std::size_t>(0.8 * kScans)) << localizing.output;
  const backend::MapData map = mapstore::LoadMap(tmp_ / "map");
  ASSERT_GE(map.keyframes.size(), 2u);
  std::vector<io::StampedPose> keyframes;
  for (const backend::Keyframe& kf : map.keyframes) keyframes.push_back({kf.stamp, kf.T_world_sensor});
  std::vector<io::StampedPose> localized_keyframes;
  for (const io::StampedPose& p : localized) {
    for (const io::StampedPose& k : keyframes) {
      if (std::abs(k.t - p.t) < 1e-6) localized_keyframes.push_back(p);
    }
  }
  EXPECT_GE(localized_keyframes.size(), keyframes.size() - 1);
  const double error = MaxPositionDifference(keyframes, localized_keyframes);
  std::printf("localized keyframe scans: max position error %.3f m\n", error);
  EXPECT_LT(error, 0.10);
  // Every localized scan against where the mapping run put it (its odometry between keyframes).
  const double track_error = MaxPositionDifference(io::ReadTum(tmp_ / "corrected.tum"), localized);
  std::printf("localized scans vs mapping run: max position error %.3f m\n", track_error);
  EXPECT_LT(track_error, 0.25);  // between keyframes this also includes odometry jitter
  // Localization does not touch the map.
  EXPECT_EQ(test::ReadText(tmp_ / "map" / "map.json"), map_json);
}

TEST_F(RunnerCli, CorruptMapFailsWithExitCodeOneNamingTheProblem) {
  const CommandResult mapping = RunOdometry(Sequence() + " --quiet --max-scans 12 --out " +
                                            Path("corrected.tum") + " --save-map " + Path("map"));
  ASSERT_EQ(mapping.exit_code, 0) << mapping.output;
  const auto keyframes = tmp_ / "map" / "keyframes.bin";
  ASSERT_TRUE(std::filesystem::exists(keyframes));
  std::filesystem::resize_file(keyframes, std::filesystem::file_size(keyframes) / 2);

  const CommandResult truncated = RunOdometry(Sequence() + " --load-map " + Path("map") +
                                              " --localize --out " + Path("localized.tum"));
  EXPECT_EQ(truncated.exit_code, 1) << truncated.output;
  EXPECT_NE(truncated.output.find("keyframes.bin"), std::string::npos) << truncated.output;
  EXPECT_FALSE(std::filesystem::exists(tmp_ / "localized.tum"));

  std::filesystem::remove(tmp_ / "map" / "map.json");
  const CommandResult no_meta = RunOdometry(Sequence() + " --load-map " + Path("map") +
                                            " --localize --out " + Path("localized.tum"));
  EXPECT_EQ(no_meta.exit_code, 1) << no_meta.output;
  EXPECT_NE(no_meta.output.find("map.json"), std::string::npos) << no_meta.output;
}

// --backend-config reaches the loop-closing back-end (keyframe selection, Scan Context) and the
// localizer; a mistake in it fails the run before it starts, naming file and key.
TEST_F(RunnerCli, BackendConfigIsReadAndItsMistakesNameTheKey) {
  test::WriteText(tmp_ / "one-keyframe.yaml",
                  "loop_closing:\n  keyframes: {min_distance: 1000.0, min_rotation_rad: 100.0}\n"
                  "  scan_context: {rings: 12}\n");
  const CommandResult mapping =
      RunOdometry(Sequence() + " --quiet --max-scans 12 --out " + Path("corrected.tum") +
                  " --save-map " + Path("map") + " --backend-config " + Path("one-keyframe.yaml"));
  ASSERT_EQ(mapping.exit_code, 0) << mapping.output;
  const backend::MapData map = mapstore::LoadMap(tmp_ / "map");
  EXPECT_EQ(map.keyframes.size(), 1u);
  EXPECT_EQ(map.scan_context.rings, 12);

  // A localizer that counts only millimetre-close points as overlap places no scan.
  test::WriteText(tmp_ / "strict.yaml",
                  "localizer:\n  relocalize_icp: {inlier_distance: 0.001}\n");
  const CommandResult localizing =
      RunOdometry(Sequence() + " --max-scans 6 --load-map " + Path("map") + " --localize --out " +
                  Path("localized.tum") + " --backend-config " + Path("strict.yaml"));
  EXPECT_EQ(localizing.exit_code, 1) << localizing.output;
  EXPECT_NE(localizing.output.find("could be localized"), std::string::npos) << localizing.output;

  test::WriteText(tmp_ / "typo.yaml", "loop_closing:\n  scan_context: {ringz: 12}\n");
  const CommandResult typo = RunOdometry(Sequence() + " --out " + Path("x.tum") +
                                         " --backend-config " + Path("typo.yaml"));
  EXPECT_EQ(typo.exit_code, 1) << typo.output;
  EXPECT_NE(typo.output.find("typo.yaml: loop_closing.scan_context.ringz: unknown key"),
            std::string::npos) << typo.output;
  test::WriteText(tmp_ / "negative.yaml", "loop_closing:\n  scan_context: {rings: -20}\n");
  const CommandResult negative = RunOdometry(Sequence() + " --out " + Path("x.tum") +
                                             " --backend-config " + Path("negative.yaml"));
  EXPECT_EQ(negative.exit_code, 1) << negative.output;
  EXPECT_NE(negative.output.find("loop_closing.scan_context.rings: must be >= 1"),
            std::string::npos) << negative.output;
  EXPECT_FALSE(std::filesystem::exists(tmp_ / "x.tum"));
}

TEST_F(RunnerCli, RefusesToSaveTheMapOverSomethingElse) {
  test::WriteText(tmp_ / "precious.txt", "not a map\n");
  const CommandResult run = RunOdometry(Sequence() + " --out " + Path("corrected.tum") +
                                        " --save-map " + Path("precious.txt"));
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("precious.txt"), std::string::npos) << run.output;
  EXPECT_EQ(test::ReadText(tmp_ / "precious.txt"), "not a map\n");
  EXPECT_FALSE(std::filesystem::exists(tmp_ / "corrected.tum"));
  // --localize without a map is a usage error.
  EXPECT_NE(RunOdometry(Sequence() + " --localize --out " + Path("x.tum")).exit_code, 0);
}

// imu.csv and wheel.csv are read, counted and logged (a NaN sample dropped with its reason) and
// drive the estimate; --no-imu / --no-wheel ignore them.
TEST_F(RunnerCli, ImuStreamDrivesTheGyroAndBadSamplesAreNamed) {
  const std::string args = " --no-loop-closure --max-scans 8 --out ";
  const CommandResult plain = RunOdometry(Sequence() + args + Path("plain.tum"));
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  EXPECT_EQ(plain.output.find("imu.csv"), std::string::npos) << plain.output;

  sim::SimOptions options;
  options.num_scans = kFirstScan + kScans;
  const sim::Simulator simulator(sim::SceneKind::Outdoor, sim::Vlp16(), options);
  sim::InertialStreamOptions streams_options;
  streams_options.imu.description.time_offset = 0.0;
  const sim::InertialStreams streams = sim::SimulateInertialStreams(simulator, kFirstScan + kScans, streams_options);
  io::WriteImuCsv(tmp_ / "seq" / "imu.csv", *streams.imu);
  // Wheel odometry of the true motion (speed and turn rate along the sensor axes, the base taken
  // at the sensor): the wheels are used too, and a made-up speed would move the estimate.
  std::vector<WheelSample> wheel;
  const double t0 = simulator.options().t0, h = 0.005;
  for (const ImuSample& s : *streams.imu) {
    const Eigen::Isometry3d a = simulator.trajectory().Pose(s.t - t0 - h);
    const Eigen::Isometry3d b = simulator.trajectory().Pose(s.t - t0 + h);
    const Eigen::Isometry3d step = a.inverse() * b;
    const Eigen::AngleAxisd turn(step.rotation());
    wheel.push_back({s.t, step.translation() / (2 * h), turn.axis() * turn.angle() / (2 * h)});
  }
  io::WriteWheelCsv(tmp_ / "seq" / "wheel.csv", wheel);
  std::ofstream(tmp_ / "seq" / "imu.csv", std::ios::app) << "1800000000,nan,0,0,0,0,9.81\n"
                                                         << "1800000001,0,0,0,0,0,9.81\n";

  // The gyro's run (its own figures below); the wheels' run follows.
  const CommandResult with = RunOdometry(Sequence() + args + Path("with.tum") + " --no-wheel");
  ASSERT_EQ(with.exit_code, 0) << with.output;
  EXPECT_NE(with.output.find("read " + std::to_string(streams.imu->size() + 1) + " IMU samples"),
            std::string::npos) << with.output;
  // Every scan lies inside the stream (the NaN sample is dropped, the late one is past the run).
  EXPECT_NE(with.output.find("IMU: gyro used on 8 of 8 scans, 0 fell back"), std::string::npos) << with.output;
  EXPECT_NE(with.output.find("dropped 1: 1 NaN/inf value (first at line " +
                             std::to_string(streams.imu->size() + 2) + ": NaN/inf value)"),
            std::string::npos) << with.output;
  EXPECT_NE(with.output.find("a gap of 99999995.500 s after t 1700000005.500"), std::string::npos) << with.output;
  EXPECT_NE(with.output.find("no \"imu_extrinsic\" in meta.json"), std::string::npos) << with.output;
  // The gyro changes the estimate (it drives the rotation) and it stays on the true path: within
  // 5 cm of gt.tum, as the LiDAR alone.
  EXPECT_NE(test::ReadText(tmp_ / "with.tum"), test::ReadText(tmp_ / "plain.tum"));
  const auto truth = io::ReadTum(tmp_ / "seq" / "gt.tum");
  EXPECT_LT(MaxErrorFromStart(io::ReadTum(tmp_ / "plain.tum"), truth), 0.05);
  EXPECT_LT(MaxErrorFromStart(io::ReadTum(tmp_ / "with.tum"), truth), 0.05);
  // Both streams: the wheels are read and used, and the run stays on the true path. The sequence
  // starts while driving at 1.5 m/s: the first scan deskewed as if at rest left the whole run
  // 7.6 cm behind before the wheels' motion deskewed it (1.8 cm now).
  const CommandResult both = RunOdometry(Sequence() + args + Path("both.tum"));
  ASSERT_EQ(both.exit_code, 0) << both.output;
  EXPECT_NE(both.output.find("wheel odometry samples"), std::string::npos) << both.output;
  EXPECT_NE(test::ReadText(tmp_ / "both.tum"), test::ReadText(tmp_ / "with.tum"));
  EXPECT_LT(MaxErrorFromStart(io::ReadTum(tmp_ / "both.tum"), truth), 0.05);

  const CommandResult ignored = RunOdometry(Sequence() + args + Path("ignored.tum") + " --no-imu --no-wheel");
  ASSERT_EQ(ignored.exit_code, 0) << ignored.output;
  EXPECT_NE(ignored.output.find("ignored (--no-imu)"), std::string::npos) << ignored.output;
  EXPECT_NE(ignored.output.find("ignored (--no-wheel)"), std::string::npos) << ignored.output;
  EXPECT_EQ(ignored.output.find("IMU samples"), std::string::npos) << ignored.output;
  EXPECT_EQ(test::ReadText(tmp_ / "ignored.tum"), test::ReadText(tmp_ / "plain.tum"));

  // A malformed file stops the run with file and line, before any scan.
  test::WriteText(tmp_ / "seq" / "wheel.csv", "t,vx,vy,vz,wx,wy,wz\n1,2,3\n");
  const CommandResult broken = RunOdometry(Sequence() + args + Path("broken.tum"));
  EXPECT_EQ(broken.exit_code, 1);
  EXPECT_NE(broken.output.find("wheel.csv:2: has 3 fields, expected 7"), std::string::npos) << broken.output;
}

}  // namespace
}  // namespace dammloam
