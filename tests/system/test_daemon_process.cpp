// dammloamd, dammloam-replay and dammloam-record as separate processes on loopback DDS, each
// test on its own domain: clean SIGTERM, refusal without CYCLONEDDS_URI, a replay killed and
// restarted mid-stream, and the lock-step trajectory equal to the offline runner's, without and
// with an IMU or wheel odometry (issue 55).
#include <fcntl.h>
#include <gtest/gtest.h>

#include "tests/system/child_process.hpp"
#include "tests/system/dds_test_client.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/system/sim_sequence.hpp"
#include "io/motion_csv.hpp"
#include "io/tum.hpp"
#include "tools/simulate/inertial_meta.hpp"
#include "tools/simulate/inertial_streams.hpp"
#include "tools/simulate/wheel_model.hpp"
#include "tests/bag/bag_fixture.hpp"

#include <nlohmann/json.hpp>

namespace dammloam::test {
namespace {

using std::chrono::milliseconds;

// The daemon's poses are the offline runner's: same stamps, within 1e-6 m and 1e-6 rad.
void ExpectSamePoses(const std::vector<io::StampedPose>& online, const std::vector<io::StampedPose>& offline) {
  ASSERT_EQ(offline.size(), online.size());
  for (std::size_t i = 0; i < online.size(); ++i) {
    EXPECT_NEAR(online[i].t, offline[i].t, 1e-6);
    EXPECT_LT((online[i].T.translation() - offline[i].T.translation()).norm(), 1e-6) << "scan " << i;
    const Eigen::AngleAxisd dR(online[i].T.rotation().transpose() * offline[i].T.rotation());
    EXPECT_LT(std::abs(dR.angle()), 1e-6) << "scan " << i;
  }
}

// How far apart two runs' poses come, the larger of metres and radians over every scan: shows
// that an input (the gyro, the wheels) changed the poses at all.
double LargestDeparture(const std::vector<io::StampedPose>& a, const std::vector<io::StampedPose>& b) {
  double largest = 0.0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    largest = std::max({largest, (a[i].T.translation() - b[i].T.translation()).norm(),
                        Eigen::AngleAxisd(a[i].T.rotation().transpose() * b[i].T.rotation()).angle()});
  }
  return largest;
}

// The exact twist of a base at T_sensor_base on the simulated carrier, 50 Hz over `scans` scans
// (the carrier is nonholonomic at the sensor: a base elsewhere also slides sideways in turns).
std::vector<WheelSample> ExactBaseTwists(const sim::Simulator& simulator,
                                         const Eigen::Isometry3d& T_sensor_base, int scans) {
  const sim::PoseOfTime chassis = [&](double t) { return simulator.trajectory().ChassisPose(t); };
  const double end = scans * simulator.sensor().scan_period;
  std::vector<WheelSample> samples;
  for (int k = 0; 0.02 * k <= end + 1e-9; ++k) {
    const sim::BaseTwist twist = sim::TrueBaseTwistAt(chassis, T_sensor_base, 0.02 * k);
    samples.push_back({simulator.options().t0 + 0.02 * k, twist.linear, twist.angular});
  }
  return samples;
}

std::vector<std::string> DaemonArgs(std::uint32_t domain, const std::filesystem::path& seq) {
  return {"--domain", std::to_string(domain), "--sensor-meta", (seq / "meta.json").string(),
          "--no-loop-closure"};
}

class DaemonProcess : public ::testing::Test {
 protected:
  void SetUp() override {
    UseLoopbackDds();
    for (const char* tool : {"dammloamd", "dammloam-replay", "dammloam-record"}) {
      if (!ToolExists(tool)) GTEST_SKIP() << tool << " not built in " << DAMMLOAM_BIN_DIR;
    }
  }
};

TEST_F(DaemonProcess, SigtermStopsTheDaemonCleanlyWithinOneSecond) {
  constexpr std::uint32_t kDomain = 81;
  const test::TempDir dir("system-sigterm");
  const sim::Simulator simulator = SmallSimulator(2);
  WriteSequence(simulator, 2, dir / "seq");
  ChildProcess daemon("dammloamd", DaemonArgs(kDomain, dir / "seq"), dir / "daemon.log");
  ASSERT_TRUE(daemon.started());
  DdsTestClient client(kDomain);
  ASSERT_TRUE(client.WaitForDaemon(milliseconds(20000))) << daemon.Log();
  // Give it work in flight, then stop it.
  const dds::CloudMessage cloud = dds::ScanToCloud(simulator.SimulateScan(0), "lidar", 0);
  client.Publish(cloud);
  ASSERT_TRUE(client.WaitForPose(cloud.stamp, milliseconds(60000))) << daemon.Log();
  const auto t0 = std::chrono::steady_clock::now();
  daemon.Signal(SIGTERM);
  const std::optional<int> code = daemon.Wait(milliseconds(5000));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(code) << "dammloamd did not stop within 5 s\n" << daemon.Log();
  EXPECT_EQ(*code, 0) << daemon.Log();
  EXPECT_LT(seconds, 1.0);
  EXPECT_NE(daemon.Log().find("stopped: 1 received, 1 processed"), std::string::npos) << daemon.Log();
}

TEST_F(DaemonProcess, EveryToolRefusesToStartWithoutCycloneDdsUri) {
  const test::TempDir dir("system-no-uri");
  const std::string saved = std::getenv("CYCLONEDDS_URI");
  unsetenv("CYCLONEDDS_URI");
  ChildProcess daemon("dammloamd", {"--domain", "82"}, dir / "daemon.log");
  ChildProcess record("dammloam-record", {"--poses", (dir / "p.tum").string()}, dir / "rec.log");
  setenv("CYCLONEDDS_URI", saved.c_str(), 1);
  for (ChildProcess* p : {&daemon, &record}) {
    const auto code = p->Wait(milliseconds(10000));
    ASSERT_TRUE(code);
    EXPECT_EQ(*code, 2);
    EXPECT_NE(p->Log().find("CYCLONEDDS_URI is not set"), std::string::npos) << p->Log();
    EXPECT_NE(p->Log().find("--allow-default-network"), std::string::npos);
  }
}

// Replays `seq` in lock-step into a fresh dammloamd; with kill_after > 0 the replay is killed
// once that many poses arrived and restarted from the first scan without a pose.
std::vector<ReceivedPose> LockstepRun(std::uint32_t domain, const std::filesystem::path& dir,
                                      int num_scans, std::size_t kill_after) {
  const auto seq = dir / "seq";
  ChildProcess daemon("dammloamd", DaemonArgs(domain, seq),
                      dir / ("daemon-" + std::to_string(domain) + ".log"));
  DdsTestClient client(domain);
  EXPECT_TRUE(client.WaitForDaemon(milliseconds(20000))) << daemon.Log();
  const std::vector<std::string> args = {seq.string(), "--domain", std::to_string(domain),
                                         "--lockstep", "--lockstep-timeout", "60"};
  std::size_t restart_index = 0;
  if (kill_after > 0) {
    ChildProcess replay("dammloam-replay", args, dir / "replay-killed.log");
    EXPECT_TRUE(client.WaitUntil([&] { return client.poses.size() >= kill_after; },
                                 milliseconds(120000)))
        << replay.Log() << daemon.Log();
    replay.Signal(SIGKILL);
    replay.Wait(milliseconds(5000));
    client.WaitUntil([] { return false; }, milliseconds(300));
    restart_index = client.poses.size();
    EXPECT_LT(restart_index, static_cast<std::size_t>(num_scans)) << "not stopped mid-stream";
  }
  // The scan in flight when the replay died may come again: dammloamd rejects the duplicate
  // stamp and the restarted replay sees that scan's latched pose.
  auto restart_args = args;
  restart_args.insert(restart_args.end(), {"--start-index", std::to_string(restart_index)});
  ChildProcess replay("dammloam-replay", restart_args, dir / "replay.log");
  const auto code = replay.Wait(milliseconds(180000));
  EXPECT_TRUE(code && *code == 0) << replay.Log() << daemon.Log();
  client.WaitUntil([&] { return client.poses.size() >= static_cast<std::size_t>(num_scans); },
                   milliseconds(10000));
  client.WaitUntil([] { return false; }, milliseconds(300));
  return client.poses;
}

TEST_F(DaemonProcess, ReplayKilledAndRestartedMidStreamIsPickedUpAgain) {
  constexpr int kScans = 12;
  const test::TempDir dir("system-restart");
  const sim::Simulator simulator = SmallSimulator(kScans);
  WriteSequence(simulator, kScans, dir / "seq");
  const auto restarted = LockstepRun(83, dir.path(), kScans, 5);
  const auto uninterrupted = LockstepRun(85, dir.path(), kScans, 0);

  // Every scan got exactly one pose, and tracking went on across the restart exactly as in an
  // uninterrupted run.
  ASSERT_EQ(restarted.size(), static_cast<std::size_t>(kScans));
  ASSERT_EQ(uninterrupted.size(), static_cast<std::size_t>(kScans));
  for (std::size_t i = 0; i < restarted.size(); ++i) {
    EXPECT_NEAR(dds::ToSeconds(restarted[i].stamp), simulator.ScanStartTime(static_cast<int>(i)), 1e-6);
    EXPECT_TRUE(SameStamp(restarted[i].stamp, uninterrupted[i].stamp));
    EXPECT_TRUE(restarted[i].registered) << restarted[i].status;
    EXPECT_LT((restarted[i].T.translation() - uninterrupted[i].T.translation()).norm(), 1e-4)
        << "scan " << i;
  }
}

TEST_F(DaemonProcess, LockstepTrajectoryOverDdsEqualsTheOfflineRunner) {
  constexpr std::uint32_t kDomain = 84;
  constexpr int kScans = 10;
  if (!ToolExists("dammloam-odometry")) GTEST_SKIP() << "dammloam-odometry not built";
  const test::TempDir dir("system-equivalence");
  const sim::Simulator simulator = SmallSimulator(kScans);
  WriteSequence(simulator, kScans, dir / "seq");

  ChildProcess offline("dammloam-odometry",
                       {(dir / "seq").string(), "--out", (dir / "offline.tum").string(), "--quiet"},
                       dir / "offline.log");
  ChildProcess daemon("dammloamd", DaemonArgs(kDomain, dir / "seq"), dir / "daemon.log");
  ChildProcess record("dammloam-record",
                      {"--domain", std::to_string(kDomain), "--poses", (dir / "dds.tum").string(),
                       "--mcap", (dir / "dds.mcap").string(),
                       "--count", std::to_string(kScans), "--timeout", "120"},
                      dir / "record.log");
  ChildProcess replay("dammloam-replay",
                      {(dir / "seq").string(), "--domain", std::to_string(kDomain), "--lockstep",
                       "--lockstep-timeout", "60", "--wait-subscriber", "30"},
                      dir / "replay.log");
  const auto replay_code = replay.Wait(milliseconds(300000));
  ASSERT_TRUE(replay_code);
  ASSERT_EQ(*replay_code, 0) << replay.Log() << daemon.Log();
  const auto record_code = record.Wait(milliseconds(60000));
  ASSERT_TRUE(record_code);
  ASSERT_EQ(*record_code, 0) << record.Log();
  const auto offline_code = offline.Wait(milliseconds(300000));
  ASSERT_TRUE(offline_code);
  ASSERT_EQ(*offline_code, 0) << offline.Log();

  const auto online_poses = io::ReadTum(dir / "dds.tum");
  const auto offline_poses = io::ReadTum(dir / "offline.tum");
  ASSERT_EQ(online_poses.size(), static_cast<std::size_t>(kScans));
  ExpectSamePoses(online_poses, offline_poses);

  // dammloam-record --mcap, read back by @mcap/core (an independent reader): the same poses as
  // ROS 2 messages, their transforms, the labelled clouds and the daemon's status.
  if (const std::string why = NodeMissing(); !why.empty()) GTEST_SKIP() << why;
  const CommandResult read = RunCommand("node " + (BagTestDir() / "node" / "read_mcap.cjs").string() + " " +
                                        (dir / "dds.mcap").string());
  ASSERT_EQ(read.exit_code, 0) << read.output.substr(0, 2000);
  const auto mcap = nlohmann::json::parse(read.output, nullptr, false);
  ASSERT_FALSE(mcap.is_discarded()) << read.output.substr(0, 2000);
  std::map<std::string, std::string> schema_of;
  for (const auto& c : mcap["channels"]) schema_of[c["topic"]] = c["schema"];
  EXPECT_EQ(schema_of, (std::map<std::string, std::string>{
                           {"/dammloam/odometry", "nav_msgs/msg/Odometry"},
                           {"/tf", "tf2_msgs/msg/TFMessage"},
                           {"/dammloam/labelled_cloud", "sensor_msgs/msg/PointCloud2"},
                           {"/dammloam/loop_closures", "visualization_msgs/msg/MarkerArray"},
                           {"/dammloam/status", "std_msgs/msg/String"}}));
  const auto& odometry = mcap["topics"]["/dammloam/odometry"];
  const auto& tf = mcap["topics"]["/tf"];
  ASSERT_EQ(odometry.size(), online_poses.size());
  ASSERT_EQ(tf.size(), online_poses.size());
  for (std::size_t i = 0; i < online_poses.size(); ++i) {
    const auto& p = odometry[i]["value"]["pose"]["pose"]["position"];
    const Eigen::Vector3d position(p["x"], p["y"], p["z"]);
    EXPECT_LT((position - online_poses[i].T.translation()).norm(), 1e-9) << "scan " << i;
    EXPECT_EQ(tf[i]["value"]["transforms"][0]["transform"]["translation"]["x"], p["x"]);
  }
  EXPECT_EQ(mcap["topics"]["/dammloam/labelled_cloud"].size(), online_poses.size());
  ASSERT_GE(mcap["topics"]["/dammloam/status"].size(), 1u);
  const auto status = nlohmann::json::parse(
      mcap["topics"]["/dammloam/status"].back()["value"]["data"].get<std::string>(), nullptr, false);
  EXPECT_EQ(status["type"], "status");
}

// A hand-held walk with its imu.csv (issue 55) replayed in lock-step: dammloamd takes the Imu
// topic and registers each scan with the samples dammloam-odometry uses, so its poses are the
// offline runner's with the IMU, not those of --no-imu; Status says every scan had the gyro.
TEST_F(DaemonProcess, LockstepWithImuEqualsTheOfflineRunnerWithImu) {
  constexpr std::uint32_t kDomain = 164;
  constexpr int kScans = 10;
  if (!ToolExists("dammloam-odometry")) GTEST_SKIP() << "dammloam-odometry not built";
  const test::TempDir dir("system-imu-equivalence");
  sim::SensorSpec spec = sim::Vlp16();
  spec.columns = 900;
  sim::SimOptions options;
  options.num_scans = kScans;
  options.motion = sim::MotionKind::Handheld;
  const sim::Simulator simulator(sim::SceneKind::Zigzag, spec, options);
  // The simulator's IMU (ICM-20948 noise and biases, a 3 ms clock offset): meta.json carries its
  // extrinsic, noise and offset, and gives them to dammloamd through --sensor-meta.
  const sim::InertialStreams streams = sim::SimulateInertialStreams(simulator, kScans, {});
  ASSERT_NE(streams.imu_options.description.time_offset, 0.0);
  io::SequenceMeta meta;
  meta.sensor = "vlp-16-900";
  meta.model = simulator.sensor_model();
  sim::DescribeStreams(streams, &meta);
  const auto seq = dir / "seq";
  {
    io::SequenceWriter writer(seq, meta, /*overwrite=*/true);
    for (int i = 0; i < kScans; ++i) writer.Write(simulator.SimulateScan(i));
  }
  io::WriteImuCsv(seq / "imu.csv", *streams.imu);

  ChildProcess offline("dammloam-odometry",
                       {seq.string(), "--out", (dir / "offline.tum").string(), "--no-loop-closure"},
                       dir / "offline.log");
  ChildProcess lidar_only("dammloam-odometry",
                          {seq.string(), "--out", (dir / "lidar.tum").string(), "--quiet",
                           "--no-loop-closure", "--no-imu"},
                          dir / "lidar.log");
  ChildProcess daemon("dammloamd", DaemonArgs(kDomain, seq), dir / "daemon.log");
  DdsTestClient client(kDomain);
  ChildProcess record("dammloam-record",
                      {"--domain", std::to_string(kDomain), "--poses", (dir / "dds.tum").string(),
                       "--count", std::to_string(kScans), "--timeout", "120"},
                      dir / "record.log");
  ChildProcess replay("dammloam-replay",
                      {seq.string(), "--domain", std::to_string(kDomain), "--lockstep",
                       "--lockstep-timeout", "60", "--wait-subscriber", "30"},
                      dir / "replay.log");
  const auto replay_code = replay.Wait(milliseconds(300000));
  ASSERT_TRUE(replay_code);
  ASSERT_EQ(*replay_code, 0) << replay.Log() << daemon.Log();
  const auto record_code = record.Wait(milliseconds(60000));
  ASSERT_TRUE(record_code && *record_code == 0) << record.Log();
  for (ChildProcess* run : {&offline, &lidar_only}) {
    const auto code = run->Wait(milliseconds(300000));
    ASSERT_TRUE(code && *code == 0) << run->Log();
  }
  EXPECT_NE(offline.Log().find("IMU: gyro used on 10 of 10 scans"), std::string::npos)
      << offline.Log();
  const auto counted = [&] {
    return !client.statuses.empty() &&
           client.statuses.back().scans_with_imu + client.statuses.back().scans_without_imu >=
               static_cast<std::uint64_t>(kScans);
  };
  ASSERT_TRUE(client.WaitUntil(counted, milliseconds(5000))) << daemon.Log();
  const ReceivedStatus& status = client.statuses.back();
  EXPECT_EQ(status.scans_with_imu, static_cast<std::uint64_t>(kScans)) << daemon.Log();
  EXPECT_EQ(status.imu_samples, streams.imu->size());
  EXPECT_EQ(status.imu_samples_dropped, 0u);

  const auto online_poses = io::ReadTum(dir / "dds.tum");
  const auto offline_poses = io::ReadTum(dir / "offline.tum");
  const auto lidar_poses = io::ReadTum(dir / "lidar.tum");
  ASSERT_EQ(online_poses.size(), static_cast<std::size_t>(kScans));
  ASSERT_EQ(offline_poses.size(), online_poses.size());
  ASSERT_EQ(lidar_poses.size(), online_poses.size());
  ExpectSamePoses(online_poses, offline_poses);
  // The gyro drove the daemon's rotation: its poses are not the LiDAR's alone.
  EXPECT_GT(LargestDeparture(online_poses, lidar_poses), 1e-4);
}

// A wheeled robot's run with its wheel.csv (issue 55) replayed in lock-step: dammloamd takes the
// WheelOdometry topic and registers each scan with the samples dammloam-odometry uses (the base
// extrinsic from meta.json through --sensor-meta), so its poses are the offline runner's with the
// wheels, not those of --no-wheel; Status says every scan interval had the wheels.
TEST_F(DaemonProcess, LockstepWithWheelsEqualsTheOfflineRunnerWithWheels) {
  constexpr std::uint32_t kDomain = 166;
  constexpr int kScans = 10;
  if (!ToolExists("dammloam-odometry")) GTEST_SKIP() << "dammloam-odometry not built";
  const test::TempDir dir("system-wheel-equivalence");
  sim::SensorSpec spec = sim::Vlp16();
  spec.columns = 900;
  sim::SimOptions options;
  options.num_scans = kScans;
  options.motion = sim::MotionKind::Wheeled;
  const sim::Simulator simulator(sim::SceneKind::Zigzag, spec, options);
  // Wheels only, their base (a carrier's rear axle) 1 m behind the sensor and on the ground,
  // given to both runs by meta.json's base_extrinsic: in the zigzag's turns the wheels' motion
  // reaches the sensor through that lever arm, so a daemon that left out --sensor-meta's
  // extrinsic departs from the runner (by 2e-5 m after 10 scans; a base right under the sensor
  // would not show it).
  sim::InertialStreams streams;
  streams.T_sensor_base = sim::SensorToBase(simulator);
  streams.T_sensor_base.translation().x() = -1.0;
  streams.wheel = ExactBaseTwists(simulator, streams.T_sensor_base, kScans);
  io::SequenceMeta meta;
  meta.sensor = "vlp-16-900";
  meta.model = simulator.sensor_model();
  sim::DescribeStreams(streams, &meta);
  const auto seq = dir / "seq";
  {
    io::SequenceWriter writer(seq, meta, /*overwrite=*/true);
    for (int i = 0; i < kScans; ++i) writer.Write(simulator.SimulateScan(i));
  }
  io::WriteWheelCsv(seq / "wheel.csv", *streams.wheel);

  ChildProcess offline("dammloam-odometry",
                       {seq.string(), "--out", (dir / "offline.tum").string(), "--no-loop-closure"},
                       dir / "offline.log");
  ChildProcess lidar_only("dammloam-odometry",
                          {seq.string(), "--out", (dir / "lidar.tum").string(), "--quiet",
                           "--no-loop-closure", "--no-wheel"},
                          dir / "lidar.log");
  ChildProcess daemon("dammloamd", DaemonArgs(kDomain, seq), dir / "daemon.log");
  DdsTestClient client(kDomain);
  ChildProcess record("dammloam-record",
                      {"--domain", std::to_string(kDomain), "--poses", (dir / "dds.tum").string(),
                       "--count", std::to_string(kScans), "--timeout", "120"},
                      dir / "record.log");
  ChildProcess replay("dammloam-replay",
                      {seq.string(), "--domain", std::to_string(kDomain), "--lockstep",
                       "--lockstep-timeout", "60", "--wait-subscriber", "30"},
                      dir / "replay.log");
  const auto replay_code = replay.Wait(milliseconds(300000));
  ASSERT_TRUE(replay_code);
  ASSERT_EQ(*replay_code, 0) << replay.Log() << daemon.Log();
  const auto record_code = record.Wait(milliseconds(60000));
  ASSERT_TRUE(record_code && *record_code == 0) << record.Log();
  for (ChildProcess* run : {&offline, &lidar_only}) {
    const auto code = run->Wait(milliseconds(300000));
    ASSERT_TRUE(code && *code == 0) << run->Log();
  }
  EXPECT_NE(offline.Log().find("wheel odometry: used on 9 of 10 scans"), std::string::npos)
      << offline.Log();
  EXPECT_NE(daemon.Log().find("T_sensor_base t [-1.0000 0.0000 "), std::string::npos)
      << daemon.Log();
  const auto counted = [&] {
    return !client.statuses.empty() &&
           client.statuses.back().scans_with_wheel + client.statuses.back().scans_without_wheel >=
               static_cast<std::uint64_t>(kScans - 1);
  };
  ASSERT_TRUE(client.WaitUntil(counted, milliseconds(5000))) << daemon.Log();
  const ReceivedStatus& status = client.statuses.back();
  EXPECT_EQ(status.scans_with_wheel, static_cast<std::uint64_t>(kScans - 1)) << daemon.Log();
  EXPECT_EQ(status.wheel_samples, streams.wheel->size());
  EXPECT_EQ(status.wheel_samples_dropped, 0u);

  const auto online_poses = io::ReadTum(dir / "dds.tum");
  const auto offline_poses = io::ReadTum(dir / "offline.tum");
  const auto lidar_poses = io::ReadTum(dir / "lidar.tum");
  ASSERT_EQ(online_poses.size(), static_cast<std::size_t>(kScans));
  ASSERT_EQ(offline_poses.size(), online_poses.size());
  ASSERT_EQ(lidar_poses.size(), online_poses.size());
  ExpectSamePoses(online_poses, offline_poses);
  // The wheels drove the daemon's translation: its poses are not the LiDAR's alone.
  EXPECT_GT(LargestDeparture(online_poses, lidar_poses), 1e-4);
}

}  // namespace
}  // namespace dammloam::test
