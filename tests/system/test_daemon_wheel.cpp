// dammloamd's wheel-odometry input in-process over DDS (issue 55; loopback, own domain per test):
// bad wheel samples (NaN, an absurd speed, a duplicate and an out-of-order stamp, stamps on
// another clock, a silence) are counted in Status by reason while every scan is still
// registered, without a jump; ROS 2 nav_msgs/Odometry on rt/odom gives the poses the native
// WheelOdometry topic gives; wheel.time_offset puts a shifted stream back on the LiDAR's clock.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/inertial/wheel_horizon.hpp"
#include "services/dammloamd/daemon.hpp"
#include "services/dds/inertial_messages.hpp"
#include "services/dds/ros2_messages.hpp"
#include "tests/system/daemon_test_config.hpp"
#include "tests/system/dds_test_client.hpp"
#include "tests/system/expect_tracked.hpp"
#include "tools/simulate/inertial_streams.hpp"
#include "tools/simulate/simulator.hpp"

namespace dammloam::test {
namespace {

using std::chrono::milliseconds;
constexpr milliseconds kPoseTimeout(60000);  // sanitizer builds are slow

// A differential-drive robot in the zigzag corridor (VLP-16, 900 columns): its wheel.csv stream.
sim::Simulator WheeledSimulator(int num_scans) {
  sim::SensorSpec spec = sim::Vlp16();
  spec.columns = 900;
  sim::SimOptions options;
  options.num_scans = num_scans;
  options.motion = sim::MotionKind::Wheeled;
  return sim::Simulator(sim::SceneKind::Zigzag, spec, options);
}

// A wheel sample as sent (stamp on the wheels' clock); injected ones are extra copies that do not
// mark the end of a scan's samples.
struct Sent {
  WheelSample sample;
  bool injected = false;
};

// A robot's wheel-odometry writer: the native WheelOdometry topic or ROS 2 nav_msgs/Odometry on
// rt/odom (what diff_drive_controller publishes).
class WheelWriter {
 public:
  WheelWriter(std::uint32_t domain, bool ros2) : participant_(static_cast<dds_domainid_t>(domain)) {
    if (ros2) {
      topic_.emplace(participant_, nav_msgs_msg_dds__Odometry__desc, dds::Ros2TopicName("/odom"),
                     dds::Ros2OdometryQos());
      ros2_.emplace(participant_, *topic_, dds::TopicQos{true, 100, false});
    } else {
      topic_.emplace(participant_, dammloam_msg_WheelOdometry_desc, dds::TopicNames{}.wheel_odometry,
                     dds::WheelOdometryQos());
      native_.emplace(participant_, *topic_, dds::WheelOdometryQos());
    }
  }
  bool WaitForDaemon(milliseconds timeout) const {
    return native_ ? native_->WaitForReaders(1, timeout) : ros2_->WaitForReaders(1, timeout);
  }
  void Write(const WheelSample& s) {
    if (native_) {
      native_->Write(dds::ToWheelMessage(s, 0.01, 0.005, base_, seq_++));
      return;
    }
    nav_msgs_msg_dds__Odometry_ m{};
    const dammloam_msg_Time t = dds::ToMsgTime(s.t);
    m.header.stamp.sec = t.sec;
    m.header.stamp.nanosec = t.nanosec;
    m.header.frame_id = const_cast<char*>(odom_.c_str());
    m.child_frame_id = const_cast<char*>(base_.c_str());
    m.pose.pose.orientation.w = 1.0;  // the robot's own integration: not read
    m.twist.twist.linear = {s.linear_velocity.x(), s.linear_velocity.y(), s.linear_velocity.z()};
    m.twist.twist.angular = {s.angular_velocity.x(), s.angular_velocity.y(), s.angular_velocity.z()};
    ros2_->Write(m);
  }

 private:
  dds::Participant participant_;
  std::optional<dds::Topic> topic_;
  std::optional<dds::Writer<dammloam_msg_WheelOdometry>> native_;
  std::optional<dds::Writer<nav_msgs_msg_dds__Odometry_>> ros2_;
  std::string odom_ = "odom", base_ = "base_link";
  std::uint64_t seq_ = 0;
};

struct Driven {
  std::vector<ReceivedPose> poses;
  ReceivedStatus status;  // the last one, after every scan
};

// Lock-step, as dammloam-replay does it: before each scan the samples up to its horizon and the
// first regular one past it, then the cloud, then wait for its pose.
Driven Drive(std::uint32_t domain, bool ros2, const sim::Simulator& simulator, int scans,
             const Eigen::Isometry3d& T_sensor_base, const std::vector<Sent>& sent,
             double time_offset) {
  daemon::DaemonConfig config = PipelineTestConfig(domain, simulator);
  config.ros2.enabled = ros2;
  config.imu.enabled = false;
  config.wheel.T_sensor_base = T_sensor_base;
  config.wheel.time_offset = time_offset;
  daemon::Daemon daemon(config, OdometryConfig{});
  daemon.Start();
  DdsTestClient client(domain);
  WheelWriter wheel(domain, ros2);
  EXPECT_TRUE(client.WaitForDaemon(milliseconds(10000)));
  EXPECT_TRUE(wheel.WaitForDaemon(milliseconds(10000)));
  const double period = simulator.sensor_model().scan_period;
  std::size_t next = 0;
  for (int i = 0; i < scans; ++i) {
    const double horizon = WheelHorizon(simulator.ScanStartTime(i), period);
    for (bool past = false; next < sent.size() && !past; ++next) {
      wheel.Write(sent[next].sample);
      past = !sent[next].injected && sent[next].sample.t - time_offset > horizon;
    }
    const dds::CloudMessage cloud = dds::ScanToCloud(simulator.SimulateScan(i), "lidar", i);
    client.Publish(cloud);
    EXPECT_TRUE(client.WaitForPose(cloud.stamp, kPoseTimeout)) << "no pose for scan " << i;
  }
  const auto counted = [&] {
    return !client.statuses.empty() &&
           client.statuses.back().processed >= static_cast<std::uint64_t>(scans) &&
           client.statuses.back().wheel_samples >= sent.size();
  };
  EXPECT_TRUE(client.WaitUntil(counted, milliseconds(5000)));
  daemon.Stop();
  client.WaitUntil([] { return false; }, milliseconds(200));
  return {client.poses, client.statuses.empty() ? ReceivedStatus{} : client.statuses.back()};
}

class DaemonWheel : public ::testing::Test {
 protected:
  void SetUp() override { UseLoopbackDds(); }
};

// The clean stream's sample nearest `t`.
std::size_t Nearest(const std::vector<Sent>& sent, double t) {
  std::size_t best = 0;
  for (std::size_t k = 0; k < sent.size(); ++k) {
    if (std::abs(sent[k].sample.t - t) < std::abs(sent[best].sample.t - t)) best = k;
  }
  return best;
}

std::vector<Sent> Clean(const sim::InertialStreams& streams) {
  std::vector<Sent> sent;
  for (const WheelSample& s : *streams.wheel) sent.push_back({s});
  return sent;
}

void ExpectSamePoses(const Driven& a, const Driven& b, double tolerance) {
  ASSERT_EQ(a.poses.size(), b.poses.size());
  for (std::size_t k = 0; k < a.poses.size(); ++k) {
    EXPECT_LT((a.poses[k].T.translation() - b.poses[k].T.translation()).norm(), tolerance)
        << "scan " << k;
    EXPECT_LT(Eigen::AngleAxisd(a.poses[k].T.linear().transpose() * b.poses[k].T.linear()).angle(),
              tolerance)
        << "scan " << k;
  }
}

TEST_F(DaemonWheel, BadSamplesAreCountedByReasonAndEveryScanIsStillTrackedWithoutAJump) {
  constexpr std::uint32_t kDomain = 171;
  constexpr int kScans = 12;
  const sim::Simulator simulator = WheeledSimulator(kScans);
  const sim::InertialStreams streams = sim::SimulateInertialStreams(simulator, kScans, {});
  ASSERT_TRUE(streams.wheel);
  std::vector<Sent> sent = Clean(streams);
  const auto mid = [&](int k) { return simulator.ScanStartTime(k) + 0.05; };
  sent[Nearest(sent, mid(3))].sample.linear_velocity.x() = std::numeric_limits<double>::quiet_NaN();
  sent[Nearest(sent, mid(6))].sample.linear_velocity.x() = 300.0;  // a unit error: km/h as m/s, say
  // Injected copies, from the last scan back so that the indices stay valid.
  const std::size_t far = Nearest(sent, mid(10));
  WheelSample ahead = sent[far].sample, behind = sent[far].sample;
  ahead.t += 30.0;
  behind.t -= 30.0;
  sent.insert(sent.begin() + static_cast<std::ptrdiff_t>(far) + 1, {{ahead, true}, {behind, true}});
  // 120 ms without samples: longer than the 70 ms the wheels bridge.
  const double gap_from = mid(8) - 0.06, gap_to = mid(8) + 0.06;
  std::erase_if(sent, [&](const Sent& s) { return s.sample.t > gap_from && s.sample.t < gap_to; });
  const std::size_t late = Nearest(sent, mid(5));
  sent.insert(sent.begin() + static_cast<std::ptrdiff_t>(late) + 1, {sent[late - 2].sample, true});
  const std::size_t twice = Nearest(sent, mid(4));
  sent.insert(sent.begin() + static_cast<std::ptrdiff_t>(twice) + 1, {sent[twice].sample, true});

  const Driven run = Drive(kDomain, false, simulator, kScans, streams.T_sensor_base, sent, 0.0);
  ASSERT_EQ(run.poses.size(), static_cast<std::size_t>(kScans));
  const ReceivedStatus& s = run.status;
  EXPECT_EQ(s.wheel_samples, sent.size());
  EXPECT_EQ(s.wheel_samples_dropped, 6u);
  EXPECT_EQ(s.wheel_by_reason.at("sample:non_finite"), 1u);
  EXPECT_EQ(s.wheel_by_reason.at("sample:absurd_speed"), 1u);
  EXPECT_EQ(s.wheel_by_reason.at("sample:duplicate_stamp"), 1u);
  EXPECT_EQ(s.wheel_by_reason.at("sample:out_of_order_stamp"), 1u);
  EXPECT_EQ(s.wheel_by_reason.at("sample:clock_offset"), 2u);
  EXPECT_EQ(s.wheel_by_reason.at("sample:gap"), 1u);
  // The intervals across the silence (previous scan's middle to this one's) fall back to the
  // LiDAR's motion model; a single dropped sample leaves a hole the wheels still bridge.
  EXPECT_EQ(s.wheel_by_reason.at("scan:gap"), 2u);
  EXPECT_EQ(s.scans_without_wheel, 2u);
  // The first scan has no interval.
  EXPECT_EQ(s.scans_with_wheel + s.scans_without_wheel, static_cast<std::uint64_t>(kScans - 1));
  EXPECT_EQ(s.receive_errors, 0u);

  ExpectTrackedAsSimulated(run.poses, simulator, kScans);
}

// ROS 2 nav_msgs/Odometry's twist gives the native topic's poses; a stream stamped 0.25 s ahead
// with wheel.time_offset 0.25 gives them too (within the stamps' rounding).
TEST_F(DaemonWheel, Ros2OdometryAndAnOffsetClockGiveThePosesOfTheNativeTopic) {
  constexpr int kScans = 6;
  const sim::Simulator simulator = WheeledSimulator(kScans);
  const sim::InertialStreams streams = sim::SimulateInertialStreams(simulator, kScans, {});
  ASSERT_TRUE(streams.wheel);
  const std::vector<Sent> sent = Clean(streams);
  std::vector<Sent> shifted = sent;
  for (Sent& s : shifted) s.sample.t += 0.25;

  const Driven native = Drive(172, false, simulator, kScans, streams.T_sensor_base, sent, 0.0);
  const Driven ros2 = Drive(173, true, simulator, kScans, streams.T_sensor_base, sent, 0.0);
  const Driven offset = Drive(174, false, simulator, kScans, streams.T_sensor_base, shifted, 0.25);
  ASSERT_EQ(native.poses.size(), static_cast<std::size_t>(kScans));
  for (const Driven* run : {&native, &ros2, &offset}) {
    EXPECT_EQ(run->status.scans_with_wheel, static_cast<std::uint64_t>(kScans - 1));
    EXPECT_EQ(run->status.wheel_samples, sent.size());
    EXPECT_EQ(run->status.wheel_samples_dropped, 0u);
  }
  ExpectSamePoses(native, ros2, 1e-9);
  ExpectSamePoses(native, offset, 1e-6);
}

// Wheels on another clock (stamps 100 s ahead, no time offset configured): every sample is
// dropped as clock_offset, the wheels are never enabled, and every scan is the LiDAR's alone.
TEST_F(DaemonWheel, WheelsOnAnotherClockAreDroppedAndTheScansAreTheLidarsAlone) {
  constexpr int kScans = 5;
  const sim::Simulator simulator = WheeledSimulator(kScans);
  const sim::InertialStreams streams = sim::SimulateInertialStreams(simulator, kScans, {});
  ASSERT_TRUE(streams.wheel);
  std::vector<Sent> sent;
  for (WheelSample s : *streams.wheel) {
    s.t += 100.0;
    sent.push_back({s, true});  // never past a horizon of the LiDAR's clock: all go out first
  }
  const Driven run = Drive(175, false, simulator, kScans, streams.T_sensor_base, sent, 0.0);
  ASSERT_EQ(run.poses.size(), static_cast<std::size_t>(kScans));
  for (const ReceivedPose& p : run.poses) {
    EXPECT_TRUE(p.registered) << p.status;
    EXPECT_EQ(p.tracking, "tracking");
  }
  EXPECT_EQ(run.status.wheel_samples, sent.size());
  EXPECT_EQ(run.status.wheel_samples_dropped, sent.size());
  EXPECT_EQ(run.status.wheel_by_reason.at("sample:clock_offset"), sent.size());
  EXPECT_EQ(run.status.scans_with_wheel + run.status.scans_without_wheel, 0u);
}

}  // namespace
}  // namespace dammloam::test
