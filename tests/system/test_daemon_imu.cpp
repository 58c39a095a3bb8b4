// dammloamd's IMU input in-process over DDS (issue 55; loopback, own domain per test): bad IMU
// samples (NaN, clipped, a gap, a duplicate and an out-of-order stamp, stamps on another clock)
// are counted in Status by reason while every scan is still registered, without a jump; and
// ROS 2 sensor_msgs/Imu on rt/imu gives the poses the native Imu topic gives.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/inertial/imu_horizon.hpp"
#include "services/dammloamd/daemon.hpp"
#include "services/dds/inertial_messages.hpp"
#include "services/dds/ros2_messages.hpp"
#include "tests/system/daemon_test_config.hpp"
#include "tests/system/dds_test_client.hpp"
#include "tests/system/expect_tracked.hpp"
#include "tests/system/sim_sequence.hpp"
#include "tools/simulate/inertial_streams.hpp"

namespace dammloam::test {
namespace {

using std::chrono::milliseconds;
constexpr milliseconds kPoseTimeout(60000);  // sanitizer builds are slow

// An IMU sample as sent (stamp on the IMU's clock); injected ones are extra copies that do not
// mark the end of a scan's samples.
struct Sent {
  ImuSample sample;
  bool injected = false;
};

// A driver's IMU writer: the native Imu topic or ROS 2 sensor_msgs/Imu on rt/imu.
class ImuWriter {
 public:
  ImuWriter(std::uint32_t domain, bool ros2) : participant_(static_cast<dds_domainid_t>(domain)) {
    if (ros2) {
      topic_.emplace(participant_, sensor_msgs_msg_dds__Imu__desc, dds::Ros2TopicName("/imu"),
                     dds::Ros2SensorDataQos());
      ros2_.emplace(participant_, *topic_, dds::TopicQos{true, 200, false});
    } else {
      topic_.emplace(participant_, dammloam_msg_Imu_desc, dds::TopicNames{}.imu, dds::ImuQos());
      native_.emplace(participant_, *topic_, dds::ImuQos());
    }
  }
  bool WaitForDaemon(milliseconds timeout) const {
    return native_ ? native_->WaitForReaders(1, timeout) : ros2_->WaitForReaders(1, timeout);
  }
  void Write(const ImuSample& s) {
    if (native_) {
      native_->Write(dds::ToImuMessage(s, ImuNoise{}, 100.0, frame_, seq_++));
      return;
    }
    sensor_msgs_msg_dds__Imu_ m{};
    const dammloam_msg_Time t = dds::ToMsgTime(s.t);
    m.header.stamp.sec = t.sec;
    m.header.stamp.nanosec = t.nanosec;
    m.header.frame_id = const_cast<char*>(frame_.c_str());
    m.orientation.w = 1.0;
    m.orientation_covariance[0] = -1.0;  // no orientation
    m.angular_velocity = {s.angular_velocity.x(), s.angular_velocity.y(), s.angular_velocity.z()};
    m.linear_acceleration = {s.linear_acceleration.x(), s.linear_acceleration.y(),
                             s.linear_acceleration.z()};
    ros2_->Write(m);
  }

 private:
  dds::Participant participant_;
  std::optional<dds::Topic> topic_;
  std::optional<dds::Writer<dammloam_msg_Imu>> native_;
  std::optional<dds::Writer<sensor_msgs_msg_dds__Imu_>> ros2_;
  std::string frame_ = "imu";
  std::uint64_t seq_ = 0;
};

struct Driven {
  std::vector<ReceivedPose> poses;
  ReceivedStatus status;  // the last one, after every scan
};

// Lock-step, as dammloam-replay does it: before each scan the samples up to its horizon and the
// first regular one past it, then the cloud, then wait for its pose.
Driven Drive(std::uint32_t domain, bool ros2, const sim::Simulator& simulator, int scans,
          const std::vector<Sent>& sent, double time_offset,
          const OdometryConfig& odometry = OdometryConfig{}) {
  daemon::DaemonConfig config = PipelineTestConfig(domain, simulator);
  config.ros2.enabled = ros2;
  config.imu.description.time_offset = time_offset;
  daemon::Daemon daemon(config, odometry);
  daemon.Start();
  DdsTestClient client(domain);
  ImuWriter imu(domain, ros2);
  EXPECT_TRUE(client.WaitForDaemon(milliseconds(10000)));
  EXPECT_TRUE(imu.WaitForDaemon(milliseconds(10000)));
  const double period = simulator.sensor_model().scan_period;
  std::size_t next = 0;
  for (int i = 0; i < scans; ++i) {
    const double horizon = ImuHorizon(simulator.ScanStartTime(i), period);
    for (bool past = false; next < sent.size() && !past; ++next) {
      imu.Write(sent[next].sample);
      past = !sent[next].injected && sent[next].sample.t - time_offset > horizon;
    }
    const dds::CloudMessage cloud = dds::ScanToCloud(simulator.SimulateScan(i), "lidar", i);
    client.Publish(cloud);
    EXPECT_TRUE(client.WaitForPose(cloud.stamp, kPoseTimeout)) << "no pose for scan " << i;
  }
  const auto counted = [&] {
    return !client.statuses.empty() &&
           client.statuses.back().processed >= static_cast<std::uint64_t>(scans) &&
           client.statuses.back().imu_samples >= sent.size();
  };
  EXPECT_TRUE(client.WaitUntil(counted, milliseconds(5000)));
  daemon.Stop();
  client.WaitUntil([] { return false; }, milliseconds(200));
  Driven run{client.poses, client.statuses.empty() ? ReceivedStatus{} : client.statuses.back()};
  return run;
}

class DaemonImu : public ::testing::Test {
 protected:
  void SetUp() override { UseLoopbackDds(); }
};

// The clean stream's sample nearest `t` (IMU clock).
std::size_t Nearest(const std::vector<Sent>& sent, double t) {
  std::size_t best = 0;
  for (std::size_t k = 0; k < sent.size(); ++k) {
    if (std::abs(sent[k].sample.t - t) < std::abs(sent[best].sample.t - t)) best = k;
  }
  return best;
}

TEST_F(DaemonImu, BadSamplesAreCountedByReasonAndEveryScanIsStillTrackedWithoutAJump) {
  constexpr std::uint32_t kDomain = 161;
  constexpr int kScans = 12;
  const sim::Simulator simulator = SmallSimulator(kScans);
  const sim::InertialStreams streams = sim::SimulateInertialStreams(simulator, kScans, {});
  const double offset = streams.imu_options.description.time_offset;
  std::vector<Sent> sent;
  for (const ImuSample& s : *streams.imu) sent.push_back({s});
  // In the middle of scan k, on the IMU's clock.
  const auto mid = [&](int k) { return simulator.ScanStartTime(k) + 0.05 + offset; };
  sent[Nearest(sent, mid(3))].sample.angular_velocity.x() = std::numeric_limits<double>::quiet_NaN();
  sent[Nearest(sent, mid(6))].sample.angular_velocity.x() = 40.0;  // beyond 2000 deg/s: clipped
  // Injected copies, from the last scan back so that the indices stay valid.
  const std::size_t far = Nearest(sent, mid(10));
  ImuSample ahead = sent[far].sample, behind = sent[far].sample;
  ahead.t += 30.0;
  behind.t -= 30.0;
  sent.insert(sent.begin() + static_cast<std::ptrdiff_t>(far) + 1, {{ahead, true}, {behind, true}});
  const double gap_from = mid(8) - 0.03, gap_to = mid(8) + 0.03;  // 60 ms without samples
  std::erase_if(sent, [&](const Sent& s) { return s.sample.t > gap_from && s.sample.t < gap_to; });
  const std::size_t late = Nearest(sent, mid(5));
  sent.insert(sent.begin() + static_cast<std::ptrdiff_t>(late) + 1, {sent[late - 3].sample, true});
  const std::size_t twice = Nearest(sent, mid(4));
  sent.insert(sent.begin() + static_cast<std::ptrdiff_t>(twice) + 1, {sent[twice].sample, true});

  const Driven run = Drive(kDomain, false, simulator, kScans, sent, offset);
  ASSERT_EQ(run.poses.size(), static_cast<std::size_t>(kScans));
  const ReceivedStatus& s = run.status;
  EXPECT_EQ(s.imu_samples, sent.size());
  EXPECT_EQ(s.imu_samples_dropped, 4u);
  EXPECT_EQ(s.imu_by_reason.at("sample:duplicate_stamp"), 1u);
  EXPECT_EQ(s.imu_by_reason.at("sample:out_of_order_stamp"), 1u);
  EXPECT_EQ(s.imu_by_reason.at("sample:clock_offset"), 2u);
  EXPECT_EQ(s.imu_by_reason.at("sample:non_finite"), 1u);
  EXPECT_EQ(s.imu_by_reason.at("sample:saturated"), 1u);
  EXPECT_EQ(s.imu_by_reason.at("sample:gap"), 1u);
  // The scans the NaN, the clipped reading and the gap fall in (through the scan, or from the
  // previous scan's middle) are the LiDAR's alone, each with the estimator's reason.
  EXPECT_GE(s.imu_by_reason.count("scan:non_finite"), 1u);
  EXPECT_GE(s.imu_by_reason.count("scan:saturated"), 1u);
  EXPECT_GE(s.imu_by_reason.count("scan:gap"), 1u);
  EXPECT_GE(s.scans_without_imu, 3u);
  EXPECT_LE(s.scans_without_imu, 6u);
  EXPECT_EQ(s.scans_with_imu + s.scans_without_imu, static_cast<std::uint64_t>(kScans));
  EXPECT_EQ(s.receive_errors, 0u);

  // Every scan registered and tracked, and every step as the simulator moved (no jump where
  // the gyro dropped out or came back).
  ExpectTrackedAsSimulated(run.poses, simulator, kScans);
}

TEST_F(DaemonImu, Ros2ImuGivesThePosesOfTheNativeImuTopic) {
  constexpr int kScans = 6;
  const sim::Simulator simulator = SmallSimulator(kScans);
  const sim::InertialStreams streams = sim::SimulateInertialStreams(simulator, kScans, {});
  const double offset = streams.imu_options.description.time_offset;
  std::vector<Sent> sent;
  for (const ImuSample& s : *streams.imu) sent.push_back({s});

  const Driven native = Drive(162, false, simulator, kScans, sent, offset);
  const Driven ros2 = Drive(163, true, simulator, kScans, sent, offset);
  ASSERT_EQ(native.poses.size(), static_cast<std::size_t>(kScans));
  ASSERT_EQ(ros2.poses.size(), static_cast<std::size_t>(kScans));
  for (const Driven* run : {&native, &ros2}) {
    EXPECT_EQ(run->status.scans_with_imu, static_cast<std::uint64_t>(kScans));
    EXPECT_EQ(run->status.imu_samples_dropped, 0u);
  }
  for (int i = 0; i < kScans; ++i) {
    const auto k = static_cast<std::size_t>(i);
    EXPECT_LT((native.poses[k].T.translation() - ros2.poses[k].T.translation()).norm(), 1e-9)
        << "scan " << i;
    EXPECT_LT(Eigen::AngleAxisd(native.poses[k].T.linear().transpose() * ros2.poses[k].T.linear())
                  .angle(),
              1e-9)
        << "scan " << i;
  }
}

// The accelerometer on (odometry config): once gravity is learned (a one-second warm-up, then
// about two seconds of registered velocity changes) its velocity change drives the motion
// prior, and Status counts the scans it drove and why the others it did not; a NaN force costs
// its interval the accelerometer, never the scan.
TEST_F(DaemonImu, TheAccelerometersScansAreCountedAndANanForceCostsOnlyItsInterval) {
  constexpr int kScans = 60;
  const sim::Simulator simulator = SmallSimulator(kScans);
  const sim::InertialStreams streams = sim::SimulateInertialStreams(simulator, kScans, {});
  const double offset = streams.imu_options.description.time_offset;
  std::vector<Sent> sent;
  for (const ImuSample& s : *streams.imu) sent.push_back({s});
  const double nan_at = simulator.ScanStartTime(50) + 0.05 + offset;
  sent[Nearest(sent, nan_at)].sample.linear_acceleration.y() =
      std::numeric_limits<double>::quiet_NaN();
  OdometryConfig odometry;
  odometry.accelerometer.enabled = true;

  const Driven run = Drive(166, false, simulator, kScans, sent, offset, odometry);
  ASSERT_EQ(run.poses.size(), static_cast<std::size_t>(kScans));
  const ReceivedStatus& s = run.status;
  // Not within the first 10 scans (the warm-up), then on most scans.
  EXPECT_GE(s.scans_with_accelerometer, 15u);
  EXPECT_LE(s.scans_with_accelerometer, static_cast<std::uint64_t>(kScans - 10));
  EXPECT_GE(s.accelerometer_by_reason.count("scan:non_finite"), 1u);
  // Every scan after the first has an interval, and each is counted once.
  EXPECT_EQ(s.scans_with_accelerometer + s.scans_without_accelerometer,
            static_cast<std::uint64_t>(kScans - 1));
  ExpectTrackedAsSimulated(run.poses, simulator, kScans);
}

// An IMU on another clock (its stamps 100 s ahead, no time offset configured): every sample is
// dropped as clock_offset, the gyro is never enabled, and every scan is the LiDAR's alone.
TEST_F(DaemonImu, AnImuOnAnotherClockIsDroppedAndTheScansAreTheLidarsAlone) {
  constexpr int kScans = 5;
  const sim::Simulator simulator = SmallSimulator(kScans);
  const sim::InertialStreams streams = sim::SimulateInertialStreams(simulator, kScans, {});
  std::vector<Sent> sent;
  for (ImuSample s : *streams.imu) {
    s.t += 100.0;
    sent.push_back({s, true});  // never past a horizon of the LiDAR's clock: all go out first
  }
  const Driven run = Drive(165, false, simulator, kScans, sent, 0.0);
  ASSERT_EQ(run.poses.size(), static_cast<std::size_t>(kScans));
  for (const ReceivedPose& p : run.poses) {
    EXPECT_TRUE(p.registered) << p.status;
    EXPECT_EQ(p.tracking, "tracking");
  }
  EXPECT_EQ(run.status.imu_samples, sent.size());
  EXPECT_EQ(run.status.imu_samples_dropped, sent.size());
  EXPECT_EQ(run.status.imu_by_reason.at("sample:clock_offset"), sent.size());
  EXPECT_EQ(run.status.scans_with_imu + run.status.scans_without_imu, 0u);
}

}  // namespace
}  // namespace dammloam::test
