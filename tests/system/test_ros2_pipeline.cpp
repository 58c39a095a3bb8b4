// dammloamd speaking ROS 2 on the wire, Cyclone DDS on both ends (loopback, own domains): a
// simulated sequence published as ROS 2 PointCloud2 in the ouster-ros layout gives one
// nav_msgs/Odometry per scan with the poses of the native-input run of the same scans, /tf with
// map->odom and odom->sensor, the labelled cloud; a cloud the ROS 2 input cannot use is
// rejected by name while the native topics keep working.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "services/dammloamd/daemon.hpp"
#include "services/dds/ros2_messages.hpp"
#include "tests/system/daemon_test_config.hpp"
#include "tests/system/dds_test_client.hpp"
#include "tests/system/sim_sequence.hpp"

namespace dammloam::test {
namespace {

using std::chrono::milliseconds;
constexpr milliseconds kPoseTimeout(60000);  // sanitizer builds are slow
constexpr int kScans = 6;

// A simulated scan as ouster-ros publishes it: ouster_ros::Point (x y z float32 at 0 4 8,
// intensity float32 16, t uint32 ns 20, reflectivity uint16 24, ring uint16 26, ambient uint16
// 28, range uint32 32; point_step 48), organized rings x columns, dense, zero points for
// no-returns.
dds::CloudMessage OusterCloud(const Scan& scan, const SensorModel& sensor) {
  const std::uint32_t rings = static_cast<std::uint32_t>(sensor.rings);
  const std::uint32_t columns = static_cast<std::uint32_t>(sensor.columns);
  dds::CloudMessage msg;
  msg.stamp = dds::ToMsgTime(scan.t_start);
  msg.frame_id = "os_sensor";
  msg.height = rings;
  msg.width = columns;
  const std::uint8_t f32 = dammloam_msg_DATATYPE_FLOAT32, u16 = dammloam_msg_DATATYPE_UINT16,
                     u32 = dammloam_msg_DATATYPE_UINT32;
  msg.fields = {{"x", 0, f32, 1},           {"y", 4, f32, 1},     {"z", 8, f32, 1},
                {"intensity", 16, f32, 1},  {"t", 20, u32, 1},    {"reflectivity", 24, u16, 1},
                {"ring", 26, u16, 1},       {"ambient", 28, u16, 1}, {"range", 32, u32, 1}};
  msg.point_step = 48;
  msg.row_step = msg.point_step * columns;
  msg.data.assign(std::size_t{msg.row_step} * rings, 0);
  msg.is_dense = true;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const auto column = static_cast<std::uint32_t>(
        std::lround(scan.times[i] / sensor.scan_period * sensor.columns));
    const auto ring = static_cast<std::uint32_t>(scan.rings[i]);
    std::uint8_t* p = msg.data.data() + ring * msg.row_step + column * msg.point_step;
    const float xyz[3] = {static_cast<float>(scan.points[i].x()),
                          static_cast<float>(scan.points[i].y()),
                          static_cast<float>(scan.points[i].z())};
    const auto t_ns = static_cast<std::uint32_t>(std::llround(scan.times[i] * 1e9));
    const auto ring16 = static_cast<std::uint16_t>(ring);
    const auto range_mm = static_cast<std::uint32_t>(scan.points[i].norm() * 1000.0);
    std::memcpy(p, xyz, sizeof(xyz));
    std::memcpy(p + 16, &scan.intensities[i], 4);
    std::memcpy(p + 20, &t_ns, 4);
    std::memcpy(p + 26, &ring16, 2);
    std::memcpy(p + 32, &range_mm, 4);
  }
  return msg;
}

// A simulated scan as the ROS 2 velodyne_pointcloud driver publishes it: packed fields (x y z
// intensity float32, ring uint16 at 16, time float32 s at 18, point_step 22), one row, stamped
// with the last packet, so the per-point times run from -scan_period to about 0.
dds::CloudMessage VelodyneCloud(const Scan& scan, double scan_period) {
  dds::CloudMessage msg;
  msg.stamp = dds::ToMsgTime(scan.t_start + scan_period);
  msg.frame_id = "velodyne";
  msg.width = static_cast<std::uint32_t>(scan.size());
  const std::uint8_t f32 = dammloam_msg_DATATYPE_FLOAT32, u16 = dammloam_msg_DATATYPE_UINT16;
  msg.fields = {{"x", 0, f32, 1}, {"y", 4, f32, 1}, {"z", 8, f32, 1}, {"intensity", 12, f32, 1},
                {"ring", 16, u16, 1}, {"time", 18, f32, 1}};
  msg.point_step = 22;
  msg.row_step = msg.point_step * msg.width;
  msg.data.assign(msg.row_step, 0);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    std::uint8_t* p = msg.data.data() + i * msg.point_step;
    const float values[4] = {static_cast<float>(scan.points[i].x()),
                             static_cast<float>(scan.points[i].y()),
                             static_cast<float>(scan.points[i].z()), scan.intensities[i]};
    const auto ring = static_cast<std::uint16_t>(scan.rings[i]);
    const auto time = static_cast<float>(scan.times[i] - scan_period);
    std::memcpy(p, values, sizeof(values));
    std::memcpy(p + 16, &ring, 2);
    std::memcpy(p + 18, &time, 4);
  }
  return msg;
}

// The ROS 2 side: what a ROS 2 driver, RViz and robot_localization would be, without ROS.
class Ros2Peer {
 public:
  explicit Ros2Peer(std::uint32_t domain)
      : participant_(static_cast<dds_domainid_t>(domain)),
        points_topic_(participant_, sensor_msgs_msg_dds__PointCloud2__desc, "rt/points",
                      dds::Ros2SensorDataQos()),
        odometry_topic_(participant_, nav_msgs_msg_dds__Odometry__desc, "rt/dammloam/odometry",
                        dds::Ros2OdometryQos()),
        labelled_topic_(participant_, sensor_msgs_msg_dds__PointCloud2__desc,
                        "rt/dammloam/labelled_cloud", dds::Ros2LabelledCloudQos()),
        tf_topic_(participant_, tf2_msgs_msg_dds__TFMessage__desc, "rt/tf", dds::Ros2TfQos()),
        // Reliable like a driver on loopback would be; a reliable writer serves the daemon's
        // best-effort reader.
        points_(participant_, points_topic_, {true, 16, false}),
        odometry_(participant_, odometry_topic_, {true, 1000, false}),
        labelled_(participant_, labelled_topic_, {true, 100, false}),
        tf_(participant_, tf_topic_, {true, 1000, false}) {}

  // with_tf false: the daemon has no /tf writer (publish_tf: false).
  bool WaitForDaemon(milliseconds timeout, bool with_tf = true) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      if (points_.MatchedReaders() > 0 && odometry_.MatchedWriters() > 0 &&
          labelled_.MatchedWriters() > 0 && (!with_tf || tf_.MatchedWriters() > 0)) {
        return true;
      }
      std::this_thread::sleep_for(milliseconds(10));
    }
    return false;
  }

  void Publish(const dds::CloudMessage& cloud) { points_.Write(dds::Ros2CloudView(cloud).get()); }

  struct Pose {
    dammloam_msg_Time stamp{};
    std::string frame_id, child_frame_id;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    double covariance_xx = 0.0;
  };
  struct Transform {
    dammloam_msg_Time stamp{};
    std::string parent, child;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  };
  struct Labelled {
    std::string frame_id;
    std::size_t points = 0;
    std::string error;
  };

  void Poll() {
    odometry_.TakeEach([this](const nav_msgs_msg_dds__Odometry_& m, const dds_sample_info_t&) {
      const auto& p = m.pose.pose;
      poses.push_back({{m.header.stamp.sec, m.header.stamp.nanosec}, m.header.frame_id,
                       m.child_frame_id,
                       ToIsometry(p.position.x, p.position.y, p.position.z, p.orientation),
                       m.pose.covariance[0]});
    }, 64);
    tf_.TakeEach([this](const tf2_msgs_msg_dds__TFMessage_& m, const dds_sample_info_t&) {
      for (std::uint32_t i = 0; i < m.transforms._length; ++i) {
        const auto& t = m.transforms._buffer[i];
        const auto& v = t.transform.translation;
        transforms.push_back({{t.header.stamp.sec, t.header.stamp.nanosec}, t.header.frame_id,
                              t.child_frame_id, ToIsometry(v.x, v.y, v.z, t.transform.rotation)});
      }
    }, 64);
    labelled_.TakeEach([this](const sensor_msgs_msg_dds__PointCloud2_& m, const dds_sample_info_t&) {
      dds::CloudLimits limits;
      const dds::CloudConversion c = dds::CloudToScan(dds::ViewOf(m), limits);
      clouds.push_back({m.header.frame_id, c.scan ? c.scan->size() : 0, c.error});
    }, 16);
  }

  bool WaitUntil(const std::function<bool()>& pred, milliseconds timeout) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (true) {
      Poll();
      if (pred()) return true;
      if (std::chrono::steady_clock::now() >= deadline) return false;
      std::this_thread::sleep_for(milliseconds(5));
    }
  }

  std::size_t CountPoses(const dammloam_msg_Time& stamp) const {
    std::size_t n = 0;
    for (const auto& p : poses) n += SameStamp(p.stamp, stamp) ? 1 : 0;
    return n;
  }

  std::vector<Pose> poses;
  std::vector<Transform> transforms;
  std::vector<Labelled> clouds;

 private:
  static Eigen::Isometry3d ToIsometry(double x, double y, double z,
                                      const geometry_msgs_msg_dds__Quaternion_& q) {
    return dds::FromMsgPose({{x, y, z}, {q.x, q.y, q.z, q.w}});
  }

  dds::Participant participant_;
  dds::Topic points_topic_, odometry_topic_, labelled_topic_, tf_topic_;
  dds::Writer<sensor_msgs_msg_dds__PointCloud2_> points_;
  dds::Reader<nav_msgs_msg_dds__Odometry_> odometry_;
  dds::Reader<sensor_msgs_msg_dds__PointCloud2_> labelled_;
  dds::Reader<tf2_msgs_msg_dds__TFMessage_> tf_;
};

double AngleBetween(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.rotation().transpose() * b.rotation()).angle();
}

class Ros2Pipeline : public ::testing::Test {
 protected:
  void SetUp() override { UseLoopbackDds(); }
};

TEST_F(Ros2Pipeline, OusterRosCloudsGiveOdometryEqualToTheNativeRunAndTf) {
  constexpr std::uint32_t kNativeDomain = 121, kRos2Domain = 122;
  const sim::Simulator simulator = SmallSimulator(kScans);
  std::vector<dds::CloudMessage> ouster, native;
  for (int i = 0; i < kScans; ++i) {
    ouster.push_back(OusterCloud(simulator.SimulateScan(i), simulator.sensor_model()));
    // The native run gets exactly what the ROS 2 input reads (same points in the same order).
    dds::CloudConversion read = dds::CloudToScan(dds::ViewOf(dds::Ros2CloudView(ouster.back()).get()), {});
    ASSERT_TRUE(read.scan) << read.error;
    native.push_back(dds::ScanToCloud(*read.scan, "os_sensor", static_cast<std::uint64_t>(i)));
  }

  std::vector<Eigen::Isometry3d> native_poses;
  {
    daemon::Daemon daemon(PipelineTestConfig(kNativeDomain, simulator), OdometryConfig{});
    daemon.Start();
    DdsTestClient client(kNativeDomain);
    ASSERT_TRUE(client.WaitForDaemon(milliseconds(10000)));
    for (const auto& cloud : native) {
      client.Publish(cloud);
      ASSERT_TRUE(client.WaitForPose(cloud.stamp, kPoseTimeout));
    }
    daemon.Stop();
    ASSERT_EQ(client.poses.size(), static_cast<std::size_t>(kScans));
    for (const auto& pose : client.poses) native_poses.push_back(pose.T);
  }

  daemon::DaemonConfig config = PipelineTestConfig(kRos2Domain, simulator);
  config.ros2.enabled = true;  // the defaults, as --ros2 gives them
  daemon::Daemon daemon(config, OdometryConfig{});
  daemon.Start();
  Ros2Peer ros2(kRos2Domain);
  DdsTestClient native_client(kRos2Domain);  // the native topics keep working alongside
  ASSERT_TRUE(ros2.WaitForDaemon(milliseconds(10000)));
  ASSERT_TRUE(native_client.WaitForDaemon(milliseconds(10000)));
  for (const auto& cloud : ouster) {
    ros2.Publish(cloud);
    ASSERT_TRUE(ros2.WaitUntil([&] { return ros2.CountPoses(cloud.stamp) > 0; }, kPoseTimeout))
        << "no nav_msgs/Odometry for stamp " << cloud.stamp.sec << "." << cloud.stamp.nanosec;
  }
  ros2.WaitUntil([&] { return ros2.clouds.size() >= static_cast<std::size_t>(kScans) &&
                              ros2.transforms.size() >= 2u * kScans; }, milliseconds(5000));
  ros2.WaitUntil([] { return false; }, milliseconds(300));  // no late duplicates either
  native_client.WaitUntil([&] { return native_client.poses.size() >= kScans; }, milliseconds(5000));

  ASSERT_EQ(ros2.poses.size(), static_cast<std::size_t>(kScans));
  for (int i = 0; i < kScans; ++i) {
    const auto& pose = ros2.poses[static_cast<std::size_t>(i)];
    const auto& expected = native_poses[static_cast<std::size_t>(i)];
    EXPECT_EQ(ros2.CountPoses(ouster[static_cast<std::size_t>(i)].stamp), 1u) << i;
    EXPECT_EQ(pose.frame_id, "odom");
    EXPECT_EQ(pose.child_frame_id, "os_sensor");
    EXPECT_LT((pose.T.translation() - expected.translation()).norm(), 1e-6) << i;
    EXPECT_LT(AngleBetween(pose.T, expected), 1e-6) << i;
    EXPECT_GT(pose.covariance_xx, 0.0) << i;
  }
  // The scans moved the sensor: equal poses are not trivially identities.
  EXPECT_GT((ros2.poses.back().T.translation() - ros2.poses.front().T.translation()).norm(), 0.01);

  // /tf: map->odom (identity: no localization) and odom->os_sensor = the pose, per scan.
  ASSERT_EQ(ros2.transforms.size(), 2u * kScans);
  for (int i = 0; i < kScans; ++i) {
    const auto& map_odom = ros2.transforms[2 * static_cast<std::size_t>(i)];
    const auto& odom_sensor = ros2.transforms[2 * static_cast<std::size_t>(i) + 1];
    EXPECT_EQ(map_odom.parent, "map");
    EXPECT_EQ(map_odom.child, "odom");
    EXPECT_TRUE(map_odom.T.isApprox(Eigen::Isometry3d::Identity()));
    EXPECT_EQ(odom_sensor.parent, "odom");
    EXPECT_EQ(odom_sensor.child, "os_sensor");
    EXPECT_TRUE(SameStamp(odom_sensor.stamp, ouster[static_cast<std::size_t>(i)].stamp));
    EXPECT_LT((odom_sensor.T.translation() - native_poses[static_cast<std::size_t>(i)].translation())
                  .norm(), 1e-6);
  }

  ASSERT_EQ(ros2.clouds.size(), static_cast<std::size_t>(kScans));
  for (const auto& cloud : ros2.clouds) {
    EXPECT_TRUE(cloud.error.empty()) << cloud.error;
    EXPECT_EQ(cloud.frame_id, "os_sensor");
    EXPECT_GT(cloud.points, 1000u);
  }
  // The native Odometry of the same scans, with the ROS 2 input's assigned sequence numbers.
  ASSERT_EQ(native_client.poses.size(), static_cast<std::size_t>(kScans));
  for (int i = 0; i < kScans; ++i) {
    EXPECT_EQ(native_client.poses[static_cast<std::size_t>(i)].input_seq,
              static_cast<std::uint64_t>(i));
  }

  // A cloud without per-point time (deskew: auto) is rejected naming the option; the daemon
  // keeps running.
  dds::CloudMessage no_time = ouster.back();
  no_time.fields.erase(no_time.fields.begin() + 4);  // t
  no_time.stamp.sec += 1;
  ros2.Publish(no_time);
  const auto error = native_client.WaitForError("dammloamd.ros2.deskew: off", milliseconds(20000));
  ASSERT_TRUE(error) << "no Status error naming ros2.deskew";
  EXPECT_NE(error->find("ROS 2 PointCloud2 #6 on rt/points"), std::string::npos) << *error;
  EXPECT_NE(error->find("[missing_time]"), std::string::npos) << *error;
  daemon.Stop();
  EXPECT_EQ(daemon.Stats().processed, static_cast<std::uint64_t>(kScans));
  EXPECT_EQ(daemon.Stats().rejected, 1u);
}

TEST_F(Ros2Pipeline, DeskewOffAcceptsCloudsWithoutPerPointTime) {
  constexpr std::uint32_t kDomain = 123;
  const sim::Simulator simulator = SmallSimulator(2);
  daemon::DaemonConfig config = PipelineTestConfig(kDomain, simulator);
  config.ros2.enabled = true;
  config.ros2.deskew = dds::PointTimes::kIgnored;
  config.ros2.sensor_frame = "lidar_link";
  config.ros2.publish_tf = false;
  daemon::Daemon daemon(config, OdometryConfig{});
  daemon.Start();
  Ros2Peer ros2(kDomain);
  ASSERT_TRUE(ros2.WaitForDaemon(milliseconds(10000), /*with_tf=*/false));
  for (int i = 0; i < 2; ++i) {
    dds::CloudMessage cloud = OusterCloud(simulator.SimulateScan(i), simulator.sensor_model());
    cloud.fields.erase(cloud.fields.begin() + 4);  // no t
    ros2.Publish(cloud);
    ASSERT_TRUE(ros2.WaitUntil([&] { return ros2.CountPoses(cloud.stamp) > 0; }, kPoseTimeout));
  }
  ros2.WaitUntil([] { return false; }, milliseconds(300));
  daemon.Stop();
  ASSERT_EQ(ros2.poses.size(), 2u);
  EXPECT_EQ(ros2.poses[0].child_frame_id, "lidar_link");
  EXPECT_TRUE(ros2.transforms.empty()) << "publish_tf: false";
  EXPECT_EQ(daemon.Stats().rejected, 0u);
}

TEST_F(Ros2Pipeline, VelodyneCloudsStampedAtTheSweepEndGetTheStampOfTheirFirstPoint) {
  constexpr std::uint32_t kDomain = 124;
  const sim::Simulator simulator = SmallSimulator(3);
  const double period = simulator.sensor_model().scan_period;
  daemon::DaemonConfig config = PipelineTestConfig(kDomain, simulator);
  config.ros2.enabled = true;
  daemon::Daemon daemon(config, OdometryConfig{});
  daemon.Start();
  Ros2Peer ros2(kDomain);
  ASSERT_TRUE(ros2.WaitForDaemon(milliseconds(10000)));
  std::vector<double> starts;
  for (int i = 0; i < 3; ++i) {
    const Scan scan = simulator.SimulateScan(i);
    starts.push_back(scan.t_start);
    ros2.Publish(VelodyneCloud(scan, period));
    ASSERT_TRUE(ros2.WaitUntil([&] { return ros2.poses.size() > static_cast<std::size_t>(i); },
                               kPoseTimeout)) << "no pose for scan " << i;
  }
  ros2.WaitUntil([&] { return ros2.transforms.size() >= 6u; }, milliseconds(5000));
  daemon.Stop();
  ASSERT_EQ(ros2.poses.size(), 3u);
  ASSERT_EQ(ros2.transforms.size(), 6u);
  for (std::size_t i = 0; i < 3; ++i) {
    // The first point's time, not the last packet's: 0.1 s before the cloud's stamp.
    EXPECT_NEAR(dds::ToSeconds(ros2.poses[i].stamp), starts[i], 1e-6) << i;
    EXPECT_NEAR(dds::ToSeconds(ros2.transforms[2 * i + 1].stamp), starts[i], 1e-6) << i;
    EXPECT_EQ(ros2.poses[i].child_frame_id, "velodyne");
  }
  EXPECT_EQ(daemon.Stats().rejected, 0u);
  EXPECT_EQ(daemon.Stats().processed, 3u);
}

}  // namespace
}  // namespace dammloam::test
