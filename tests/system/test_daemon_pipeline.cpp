// dammloamd's pipeline in-process over DDS (loopback, own domain per test): one Odometry per
// scan, labelled clouds, every malformed input rejected by name while tracking continues, and
// overload drops counted. Runs under ASan/UBSan and TSan.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <limits>

#include "core/odometry/pipeline.hpp"
#include "services/dammloamd/daemon.hpp"
#include "tests/system/daemon_test_config.hpp"
#include "tests/system/dds_test_client.hpp"
#include "tests/system/sim_sequence.hpp"

namespace dammloam::test {
namespace {

using std::chrono::milliseconds;
constexpr milliseconds kPoseTimeout(60000);  // sanitizer builds are slow

class DaemonPipeline : public ::testing::Test {
 protected:
  void SetUp() override { UseLoopbackDds(); }
};

TEST_F(DaemonPipeline, EveryScanYieldsOneOdometryAndALabelledCloudWithValidLabels) {
  constexpr std::uint32_t kDomain = 71;
  constexpr int kScans = 8;
  const sim::Simulator simulator = SmallSimulator(kScans);
  daemon::Daemon daemon(PipelineTestConfig(kDomain, simulator), OdometryConfig{});
  daemon.Start();
  DdsTestClient client(kDomain);
  ASSERT_TRUE(client.WaitForDaemon(milliseconds(10000)));

  std::vector<dammloam_msg_Time> stamps;
  for (int i = 0; i < kScans; ++i) {
    const dds::CloudMessage cloud = dds::ScanToCloud(simulator.SimulateScan(i), "lidar", i);
    stamps.push_back(cloud.stamp);
    client.Publish(cloud);
    ASSERT_TRUE(client.WaitForPose(cloud.stamp, kPoseTimeout)) << "no pose for scan " << i;
  }
  client.WaitUntil([&] { return client.clouds.size() >= kScans; }, milliseconds(5000));
  client.WaitUntil([] { return false; }, milliseconds(300));  // no late duplicates either
  const daemon::StatusSnapshot stats = daemon.Stats();
  daemon.Stop();
  // In lock-step the labelled-cloud thread never falls behind the poses.
  EXPECT_EQ(stats.labelled_clouds_published, static_cast<std::uint64_t>(kScans));
  EXPECT_EQ(stats.labelled_clouds_skipped, 0u);

  ASSERT_EQ(client.poses.size(), static_cast<std::size_t>(kScans));
  for (int i = 0; i < kScans; ++i) {
    EXPECT_EQ(client.CountPoses(stamps[static_cast<std::size_t>(i)]), 1u) << "scan " << i;
    EXPECT_EQ(client.poses[static_cast<std::size_t>(i)].input_seq, static_cast<std::uint64_t>(i));
    EXPECT_TRUE(client.poses[static_cast<std::size_t>(i)].registered)
        << client.poses[static_cast<std::size_t>(i)].status;
    EXPECT_EQ(client.poses[static_cast<std::size_t>(i)].tracking, "tracking") << "scan " << i;
    EXPECT_EQ(client.poses[static_cast<std::size_t>(i)].point_times, "usable") << "scan " << i;
  }
  // The threaded daemon made the same core calls as the single-threaded pipeline (same
  // predicted orientation for the features): identical poses, whatever their accuracy.
  OdometryPipeline offline(OdometryConfig{}, simulator.sensor_model());
  for (int i = 0; i < kScans; ++i) {
    // The scan as it travels over DDS (float32 points, nanosecond stamp).
    const dds::CloudMessage cloud = dds::ScanToCloud(simulator.SimulateScan(i), "lidar", i);
    dds::CloudConversion received = dds::CloudToScan(dds::CloudView(cloud).get(), {});
    ASSERT_TRUE(received.scan) << received.error;
    const OdometryResult expected = offline.Process(std::move(*received.scan));
    const Eigen::Isometry3d& T = client.poses[static_cast<std::size_t>(i)].T;
    EXPECT_LT((T.translation() - expected.T_world_sensor.translation()).norm(), 1e-6) << i;
    EXPECT_LT(Eigen::AngleAxisd(T.rotation().transpose() * expected.T_world_sensor.rotation()).angle(),
              1e-6) << i;
  }

  ASSERT_EQ(client.clouds.size(), static_cast<std::size_t>(kScans));
  for (const auto& cloud : client.clouds) {
    EXPECT_TRUE(cloud.error.empty()) << cloud.error;
    EXPECT_GT(cloud.width, 1000u);
    ASSERT_EQ(cloud.raw_labels.size(), cloud.width);
    std::array<std::size_t, kNumPointClasses> per_class{};
    for (std::uint8_t label : cloud.raw_labels) {
      ASSERT_LE(label, dammloam_msg_CLASS_EDGE) << "invalid label";
      ++per_class[label];
    }
    EXPECT_GT(per_class[dammloam_msg_CLASS_GROUND], 0u) << "the zigzag scene has a floor";
    EXPECT_GT(per_class[dammloam_msg_CLASS_WALL], 0u) << "the zigzag scene has walls";
  }
}

// What a robot's own consumer of poses sees: a points writer and an Odometry reader, no
// LabelledCloud reader. The clouds are then never built (a 128-beam one takes longer than a scan
// period), and the poses are the same as with a reader.
TEST_F(DaemonPipeline, LabelledCloudsAreBuiltOnlyWhileSomeoneReadsThem) {
  constexpr std::uint32_t kDomain = 79;
  constexpr int kScans = 4;
  const sim::Simulator simulator = SmallSimulator(kScans);
  daemon::Daemon daemon(PipelineTestConfig(kDomain, simulator), OdometryConfig{});
  daemon.Start();
  const dds::TopicNames names;
  dds::Participant participant(kDomain);
  const dds::Topic points_topic(participant, dammloam_msg_PointCloud_desc, names.points,
                                dds::PointsQos());
  const dds::Topic odometry_topic(participant, dammloam_msg_Odometry_desc, names.odometry,
                                  dds::OdometryQos());
  const dds::Writer<dammloam_msg_PointCloud> points(participant, points_topic, dds::PointsQos());
  const dds::Reader<dammloam_msg_Odometry> odometry(participant, odometry_topic,
                                                    {true, 100, false});
  ASSERT_TRUE(points.WaitForReaders(1, milliseconds(10000)));
  std::size_t poses = 0;
  for (int i = 0; i < kScans; ++i) {
    const dds::CloudMessage cloud = dds::ScanToCloud(simulator.SimulateScan(i), "lidar", i);
    points.Write(dds::CloudView(cloud).get());
    const auto deadline = std::chrono::steady_clock::now() + kPoseTimeout;
    const std::size_t before = poses;
    while (poses == before && std::chrono::steady_clock::now() < deadline) {
      poses += static_cast<std::size_t>(
          odometry.TakeEach([](const dammloam_msg_Odometry&, const dds_sample_info_t&) {}, 8));
      std::this_thread::sleep_for(milliseconds(2));
    }
    ASSERT_EQ(poses, static_cast<std::size_t>(i + 1)) << "no pose for scan " << i;
  }
  const daemon::StatusSnapshot stats = daemon.Stats();
  daemon.Stop();
  EXPECT_EQ(stats.processed, static_cast<std::uint64_t>(kScans));
  EXPECT_EQ(stats.labelled_clouds_published, 0u);
  EXPECT_EQ(stats.labelled_clouds_skipped, 0u);
}

// A malformed variant of a valid cloud and the text its Status error must contain.
struct Malformed {
  std::string name;
  std::function<void(dds::CloudMessage&, const dammloam_msg_Time& previous)> corrupt;
  std::string expected_error;
};

TEST_F(DaemonPipeline, MalformedSamplesAreRejectedByNameWhileValidScansAreTracked) {
  constexpr std::uint32_t kDomain = 72;
  const std::vector<Malformed> cases = {
      {"missing field", [](dds::CloudMessage& m, const dammloam_msg_Time&) { m.fields.erase(m.fields.begin() + 1); },
       "required field 'y' is missing"},
      {"wrong field type", [](dds::CloudMessage& m, const dammloam_msg_Time&) { m.fields[2].datatype = dammloam_msg_DATATYPE_INT8; },
       "field 'z' is int8"},
      {"truncated payload", [](dds::CloudMessage& m, const dammloam_msg_Time&) { m.data.resize(m.data.size() / 2); },
       "(truncated)"},
      {"NaN point", [](dds::CloudMessage& m, const dammloam_msg_Time&) {
         const float nan = std::numeric_limits<float>::quiet_NaN();
         std::memcpy(m.data.data() + 10 * m.point_step, &nan, 4);
       }, "point 10 (row 0, column 10) has a non-finite coordinate"},
      {"zero points", [](dds::CloudMessage& m, const dammloam_msg_Time&) { m.width = 0; m.row_step = 0; m.data.clear(); },
       "cloud has zero points"},
      {"50 MB sample", [](dds::CloudMessage& m, const dammloam_msg_Time&) {
         m.width = 50u * 1000u * 1000u / m.point_step;
         m.row_step = m.width * m.point_step;
         m.data.assign(m.row_step, 1);
       }, "exceeds the limit of 33554432 bytes"},
      {"out-of-order stamp",
       [](dds::CloudMessage& m, const dammloam_msg_Time& previous) {
         m.stamp = previous;
         m.stamp.sec -= 1;
       }, "out-of-order stamp"},
      {"duplicate stamp",
       [](dds::CloudMessage& m, const dammloam_msg_Time& previous) { m.stamp = previous; },
       "duplicate stamp"},
  };
  const int num_scans = static_cast<int>(cases.size()) + 1;
  const sim::Simulator simulator = SmallSimulator(num_scans);
  daemon::Daemon daemon(PipelineTestConfig(kDomain, simulator), OdometryConfig{});
  daemon.Start();
  DdsTestClient client(kDomain);
  ASSERT_TRUE(client.WaitForDaemon(milliseconds(10000)));

  // valid 0, bad, valid 1, bad, ..., valid N: each bad sample is a corrupted copy of the next
  // valid scan.
  dds::CloudMessage previous = dds::ScanToCloud(simulator.SimulateScan(0), "lidar", 0);
  client.Publish(previous);
  ASSERT_TRUE(client.WaitForPose(previous.stamp, kPoseTimeout));
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const int index = static_cast<int>(k) + 1;
    const dds::CloudMessage valid = dds::ScanToCloud(simulator.SimulateScan(index), "lidar", index);
    dds::CloudMessage bad = valid;
    cases[k].corrupt(bad, previous.stamp);
    client.Publish(bad);
    const auto error = client.WaitForError(cases[k].expected_error, milliseconds(20000));
    ASSERT_TRUE(error) << cases[k].name << ": no Status error containing '"
                       << cases[k].expected_error << "'";
    client.Publish(valid);
    ASSERT_TRUE(client.WaitForPose(valid.stamp, kPoseTimeout)) << "after " << cases[k].name;
    previous = valid;
  }
  daemon.Stop();
  const auto stats = daemon.Stats();
  EXPECT_EQ(stats.rejected, cases.size());
  EXPECT_EQ(stats.processed, static_cast<std::uint64_t>(num_scans));
  EXPECT_EQ(client.poses.size(), static_cast<std::size_t>(num_scans));
  for (const auto& pose : client.poses) EXPECT_TRUE(pose.registered) << pose.status;
}

TEST_F(DaemonPipeline, OverloadDropsTheOldestScansAndCountsThem) {
  constexpr std::uint32_t kDomain = 73;
  constexpr int kScans = 10;
  const sim::Simulator simulator = SmallSimulator(kScans);
  std::vector<dds::CloudMessage> clouds;
  for (int i = 0; i < kScans; ++i) {
    clouds.push_back(dds::ScanToCloud(simulator.SimulateScan(i), "lidar", i));
  }
  daemon::DaemonConfig config = PipelineTestConfig(kDomain, simulator);
  config.input_depth = kScans;  // DDS keeps them all: any loss happens in the daemon, counted
  daemon::Daemon daemon(config, OdometryConfig{});
  daemon.Start();
  DdsTestClient client(kDomain);
  ASSERT_TRUE(client.WaitForDaemon(milliseconds(10000)));
  for (const auto& cloud : clouds) client.Publish(cloud);  // a burst: far faster than 10 Hz

  ASSERT_TRUE(client.WaitForPose(clouds.back().stamp, kPoseTimeout)) << "the newest scan survives";
  client.WaitUntil([] { return false; }, milliseconds(500));
  daemon.Stop();
  const auto stats = daemon.Stats();
  EXPECT_EQ(stats.received, static_cast<std::uint64_t>(kScans));
  EXPECT_GT(stats.dropped, 0u) << "a burst of 10 scans must overflow a backlog of 2";
  EXPECT_EQ(stats.processed + stats.dropped, static_cast<std::uint64_t>(kScans));
  EXPECT_EQ(client.poses.size(), stats.processed);
  for (std::size_t i = 1; i < client.poses.size(); ++i) {
    EXPECT_LT(dds::ToSeconds(client.poses[i - 1].stamp), dds::ToSeconds(client.poses[i].stamp));
  }
}

}  // namespace
}  // namespace dammloam::test
