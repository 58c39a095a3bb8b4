// ROS 2 PointCloud2 input as the three common ROS 2 LiDAR drivers lay it out (ouster-ros,
// velodyne_pointcloud, nebula), through the same validation as the native input; and the ROS 2
// output conversions (topic names, covariance order, labelled cloud, TF).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "services/dds/ros2_messages.hpp"

namespace dammloam::dds {
namespace {

constexpr std::uint8_t kU8 = dammloam_msg_DATATYPE_UINT8;
constexpr std::uint8_t kU16 = dammloam_msg_DATATYPE_UINT16;
constexpr std::uint8_t kU32 = dammloam_msg_DATATYPE_UINT32;
constexpr std::uint8_t kF32 = dammloam_msg_DATATYPE_FLOAT32;

template <typename T>
void Put(CloudMessage& msg, std::uint32_t row, std::uint32_t column, std::uint32_t offset,
         T value) {
  std::memcpy(msg.data.data() + row * msg.row_step + column * msg.point_step + offset, &value,
              sizeof(T));
}

void PutXyz(CloudMessage& msg, std::uint32_t row, std::uint32_t column, const Eigen::Vector3f& p) {
  Put(msg, row, column, 0, p.x());
  Put(msg, row, column, 4, p.y());
  Put(msg, row, column, 8, p.z());
}

CloudMessage Empty(std::uint32_t height, std::uint32_t width, std::uint32_t point_step,
                   std::vector<CloudField> fields) {
  CloudMessage msg;
  msg.stamp = {1700000000, 500000000};
  msg.frame_id = "os_sensor";
  msg.height = height;
  msg.width = width;
  msg.fields = std::move(fields);
  msg.point_step = point_step;
  msg.row_step = point_step * width;
  msg.data.assign(std::size_t{msg.row_step} * height, 0);
  msg.is_dense = true;
  return msg;
}

Eigen::Vector3f PointAt(std::uint32_t row, std::uint32_t column) {
  const float a = 0.3f * static_cast<float>(column);
  return {10.0f * std::cos(a), 10.0f * std::sin(a), 0.5f * static_cast<float>(row) - 1.0f};
}

// The whole ROS 2 path: CloudMessage -> PointCloud2_ sample -> neutral view -> Scan.
CloudConversion ConvertRos2(const CloudMessage& msg, PointTimes times = PointTimes::kRequired) {
  CloudLimits limits;
  limits.max_ring = 128;
  limits.point_times = times;
  limits.missing_time_hint = "set dammloamd.ros2.deskew: off";
  limits.stamp_may_end_scan = true;  // as the daemon's ROS 2 input
  const Ros2CloudView sample(msg);
  return CloudToScan(ViewOf(sample.get()), limits);
}

void ExpectError(const CloudConversion& c, const std::string& code, const std::string& text) {
  EXPECT_FALSE(c.scan.has_value());
  EXPECT_EQ(c.code, code) << c.error;
  EXPECT_NE(c.error.find(text), std::string::npos) << "error was: " << c.error;
}

// ouster-ros ouster_ros::Point (os_point.h, PCL struct, EIGEN_ALIGN16): organized beams x
// columns, dense, no-returns are zero points; t in uint32 ns since header.stamp.
constexpr std::uint32_t kBeams = 4, kColumns = 16;
CloudMessage OusterCloud() {
  CloudMessage msg = Empty(kBeams, kColumns, 48,
                           {{"x", 0, kF32, 1}, {"y", 4, kF32, 1}, {"z", 8, kF32, 1},
                            {"intensity", 16, kF32, 1}, {"t", 20, kU32, 1},
                            {"reflectivity", 24, kU16, 1}, {"ring", 26, kU16, 1},
                            {"ambient", 28, kU16, 1}, {"range", 32, kU32, 1}});
  for (std::uint32_t row = 0; row < kBeams; ++row) {
    for (std::uint32_t column = 0; column < kColumns; ++column) {
      if (row == 2 && column == 5) continue;  // no return: all zero
      PutXyz(msg, row, column, PointAt(row, column));
      Put(msg, row, column, 16, 100.0f + static_cast<float>(column));
      Put(msg, row, column, 20, static_cast<std::uint32_t>(6250000u * column));  // 10 Hz / 16
      Put(msg, row, column, 24, static_cast<std::uint16_t>(7));
      Put(msg, row, column, 26, static_cast<std::uint16_t>(row));
      Put(msg, row, column, 28, static_cast<std::uint16_t>(300));
      Put(msg, row, column, 32, static_cast<std::uint32_t>(10000));
    }
  }
  return msg;
}

TEST(Ros2PointCloud, OusterRosLayoutGivesPointsRingsAndNanosecondTimesInSeconds) {
  const CloudConversion c = ConvertRos2(OusterCloud());
  ASSERT_TRUE(c.scan) << c.error;
  EXPECT_EQ(c.skipped_points, 1u);
  ASSERT_EQ(c.scan->size(), kBeams * kColumns - 1);
  EXPECT_DOUBLE_EQ(c.scan->t_start, 1700000000.5);
  ASSERT_TRUE(c.scan->has_times());
  ASSERT_TRUE(c.scan->has_rings());
  // Row 1, column 9 is index 16 + 9 (the skipped point is in row 2).
  const std::size_t i = kColumns + 9;
  EXPECT_LT((c.scan->points[i] - PointAt(1, 9).cast<double>()).norm(), 1e-6);
  EXPECT_FLOAT_EQ(c.scan->times[i], 0.05625f);
  EXPECT_EQ(c.scan->rings[i], 1);
  EXPECT_FLOAT_EQ(c.scan->intensities[i], 109.0f);
  // After the skipped no-return in row 2 everything shifts by one.
  const std::size_t j = 3 * kColumns + 15 - 1;
  EXPECT_LT((c.scan->points[j] - PointAt(3, 15).cast<double>()).norm(), 1e-6);
  EXPECT_FLOAT_EQ(c.scan->times[j], 0.09375f);
  EXPECT_EQ(c.scan->rings[j], 3);
}

// velodyne_pointcloud PointcloudXYZIRT as the ROS 2 driver publishes it: fields added with
// sensor_msgs' PointCloud2Modifier, which packs them: ring at 16, time (float32 s) at 18,
// point_step 22, one row, dense. velodyne_driver stamps the scan with its last packet, so the
// times run from about -scan_period up to 0.
CloudMessage VelodyneDriverCloud(std::uint32_t n) {
  CloudMessage msg = Empty(1, n, 22,
                           {{"x", 0, kF32, 1}, {"y", 4, kF32, 1}, {"z", 8, kF32, 1},
                            {"intensity", 12, kF32, 1}, {"ring", 16, kU16, 1},
                            {"time", 18, kF32, 1}});
  msg.frame_id = "velodyne";
  for (std::uint32_t k = 0; k < n; ++k) {
    PutXyz(msg, 0, k, PointAt(k % 16, k / 16));
    Put(msg, 0, k, 12, 5.0f);
    Put(msg, 0, k, 16, static_cast<std::uint16_t>(k % 16));
    Put(msg, 0, k, 18, -0.1f + 0.001f * static_cast<float>(k / 16));
  }
  return msg;
}

// The same fields from a pcl::PointCloud<velodyne_pcl::PointXYZIRT> (PCL_ADD_POINT4D padding,
// EIGEN_ALIGN16): intensity 16, ring 20, time 24, point_step 32.
CloudMessage VelodynePclCloud(std::uint32_t n) {
  CloudMessage msg = Empty(1, n, 32,
                           {{"x", 0, kF32, 1}, {"y", 4, kF32, 1}, {"z", 8, kF32, 1},
                            {"intensity", 16, kF32, 1}, {"ring", 20, kU16, 1},
                            {"time", 24, kF32, 1}});
  for (std::uint32_t k = 0; k < n; ++k) {
    PutXyz(msg, 0, k, PointAt(k % 16, k / 16));
    Put(msg, 0, k, 16, 5.0f);
    Put(msg, 0, k, 20, static_cast<std::uint16_t>(k % 16));
    Put(msg, 0, k, 24, 0.001f * static_cast<float>(k / 16));
  }
  return msg;
}

TEST(Ros2PointCloud, VelodyneLayoutsGiveFloatSecondTimes) {
  for (const CloudMessage& msg : {VelodyneDriverCloud(64), VelodynePclCloud(64)}) {
    SCOPED_TRACE("point_step " + std::to_string(msg.point_step));
    const CloudConversion c = ConvertRos2(msg);
    ASSERT_TRUE(c.scan) << c.error;
    ASSERT_EQ(c.scan->size(), 64u);
    EXPECT_LT((c.scan->points[37] - PointAt(5, 2).cast<double>()).norm(), 1e-6);
    EXPECT_NEAR(c.scan->times[37], 0.002f, 1e-6);
    EXPECT_EQ(c.scan->rings[37], 5);
    EXPECT_FLOAT_EQ(c.scan->intensities[37], 5.0f);
  }
  // Driver stamp = last packet: the scan starts at the first point, 0.1 s before the stamp.
  const CloudConversion c = ConvertRos2(VelodyneDriverCloud(64));
  ASSERT_TRUE(c.scan) << c.error;
  EXPECT_NEAR(c.start_offset, -0.1, 1e-6);
  EXPECT_NEAR(c.scan->t_start, 1700000000.4, 1e-6);
  EXPECT_FLOAT_EQ(c.scan->times[0], 0.0f);
  // Native input keeps rejecting negative times (its stamps are the start of the sweep).
  CloudLimits native;
  native.max_ring = 128;
  const CloudConversion rejected = CloudToScan(ViewOf(Ros2CloudView(VelodyneDriverCloud(64)).get()), native);
  EXPECT_EQ(rejected.code, "point_time") << rejected.error;
}

// nebula PointXYZIRCAEDT (no PCL padding): uint8 intensity 12, return_type 13, uint16 channel
// 14 (the ring), azimuth/elevation/distance float32, time_stamp uint32 ns at 28; point_step 32.
CloudMessage NebulaCloud(std::uint32_t n) {
  CloudMessage msg = Empty(1, n, 32,
                           {{"x", 0, kF32, 1}, {"y", 4, kF32, 1}, {"z", 8, kF32, 1},
                            {"intensity", 12, kU8, 1}, {"return_type", 13, kU8, 1},
                            {"channel", 14, kU16, 1}, {"azimuth", 16, kF32, 1},
                            {"elevation", 20, kF32, 1}, {"distance", 24, kF32, 1},
                            {"time_stamp", 28, kU32, 1}});
  msg.frame_id = "hesai_lidar";
  for (std::uint32_t k = 0; k < n; ++k) {
    const Eigen::Vector3f p = PointAt(k % 32, k / 32);
    PutXyz(msg, 0, k, p);
    Put(msg, 0, k, 12, static_cast<std::uint8_t>(200));
    Put(msg, 0, k, 13, static_cast<std::uint8_t>(1));
    Put(msg, 0, k, 14, static_cast<std::uint16_t>(k % 32));
    Put(msg, 0, k, 16, std::atan2(p.y(), p.x()));
    Put(msg, 0, k, 20, 0.0f);
    Put(msg, 0, k, 24, p.norm());
    Put(msg, 0, k, 28, static_cast<std::uint32_t>(55555u * (k / 32)));
  }
  return msg;
}

TEST(Ros2PointCloud, NebulaLayoutReadsChannelAsRingAndTimeStampNanoseconds) {
  const CloudConversion c = ConvertRos2(NebulaCloud(96));
  ASSERT_TRUE(c.scan) << c.error;
  ASSERT_EQ(c.scan->size(), 96u);
  EXPECT_LT((c.scan->points[70] - PointAt(6, 2).cast<double>()).norm(), 1e-6);
  EXPECT_FLOAT_EQ(c.scan->times[70], 0.00011111f);
  EXPECT_EQ(c.scan->rings[70], 6);
  EXPECT_FLOAT_EQ(c.scan->intensities[70], 200.0f);
}

TEST(Ros2PointCloud, LayoutWithoutXIsRejectedNamingTheField) {
  CloudMessage msg = NebulaCloud(8);
  msg.fields[0].name = "px";
  ExpectError(ConvertRos2(msg), "missing_field", "required field 'x' is missing");
}

TEST(Ros2PointCloud, WrongTypeForTimeIsRejectedNamingTheField) {
  CloudMessage ouster = OusterCloud();
  ouster.fields[4].datatype = kU16;
  ExpectError(ConvertRos2(ouster), "field_type", "field 't' is uint16");
  CloudMessage nebula = NebulaCloud(8);
  nebula.fields[9].datatype = kU8;
  ExpectError(ConvertRos2(nebula), "field_type", "field 'time_stamp' is uint8");
}

TEST(Ros2PointCloud, TruncatedDataIsRejected) {
  CloudMessage msg = OusterCloud();
  ASSERT_GE(msg.data.size(), msg.point_step);
  msg.data.erase(msg.data.end() - msg.point_step, msg.data.end());
  ExpectError(ConvertRos2(msg), "payload_size", "payload is 3024 bytes but height x row_step = "
                                                "3072 (truncated)");
}

TEST(Ros2PointCloud, MissingTimeIsAnErrorNamingTheOptionUnlessDeskewIsOff) {
  CloudMessage msg = VelodyneDriverCloud(32);
  msg.fields.pop_back();  // time
  const CloudConversion rejected = ConvertRos2(msg, PointTimes::kRequired);
  ExpectError(rejected, "missing_time", "no per-point time field");
  EXPECT_NE(rejected.error.find("dammloamd.ros2.deskew: off"), std::string::npos);

  const CloudConversion accepted = ConvertRos2(msg, PointTimes::kIgnored);
  ASSERT_TRUE(accepted.scan) << accepted.error;
  EXPECT_EQ(accepted.scan->size(), 32u);
  EXPECT_FALSE(accepted.scan->has_times());
}

TEST(Ros2PointCloud, DeskewOffIgnoresTimesEvenWhenPresent) {
  const CloudConversion c = ConvertRos2(OusterCloud(), PointTimes::kIgnored);
  ASSERT_TRUE(c.scan) << c.error;
  EXPECT_FALSE(c.scan->has_times());
  EXPECT_TRUE(c.scan->has_rings());
}

TEST(Ros2Messages, TopicNamesGetTheRtPrefix) {
  EXPECT_EQ(Ros2TopicName("/points"), "rt/points");
  EXPECT_EQ(Ros2TopicName("points"), "rt/points");
  EXPECT_EQ(Ros2TopicName("/dammloam/odometry"), "rt/dammloam/odometry");
}

TEST(Ros2Messages, PoseCovarianceMovesRotationUncertaintyIntoPositionByTheLeverArm) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(10.0, 0.0, 0.0);
  Matrix6d sigma = Matrix6d::Zero();
  sigma.diagonal() << 0.01, 0.01, 0.01, 0.0, 0.0, 1e-4;  // yaw only
  const Matrix6d ros = PoseCovarianceToRos(sigma, T);
  // A yaw of phi at 10 m from the origin moves the position by 10 phi along y.
  EXPECT_NEAR(ros(1, 1), 0.01 + 100.0 * 1e-4, 1e-12);
  EXPECT_NEAR(ros(0, 0), 0.01, 1e-12);
  EXPECT_NEAR(ros(5, 5), 1e-4, 1e-12);
  EXPECT_NEAR(ros(1, 5), 10.0 * 1e-4, 1e-12);
  EXPECT_TRUE(ros.isApprox(ros.transpose()));
  // At the origin nothing changes.
  EXPECT_TRUE(PoseCovarianceToRos(sigma, Eigen::Isometry3d::Identity()).isApprox(sigma));
}

TEST(Ros2Messages, OdometryHasFramesPoseAndTwistInTheChildFrame) {
  OdometryResult r;
  r.T_world_sensor.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  r.T_world_sensor.translation() = Eigen::Vector3d(1.0, 2.0, 3.0);
  r.velocity << 1.0, 0.0, 0.0, 0.0, 0.0, 0.2;
  const std::string odom = "odom", sensor = "os_sensor";
  const auto msg = ToRos2Odometry(r, {12, 34}, odom, sensor, 0.1);
  EXPECT_STREQ(msg.header.frame_id, "odom");
  EXPECT_STREQ(msg.child_frame_id, "os_sensor");
  EXPECT_EQ(msg.header.stamp.sec, 12);
  EXPECT_EQ(msg.header.stamp.nanosec, 34u);
  EXPECT_DOUBLE_EQ(msg.pose.pose.position.y, 2.0);
  EXPECT_NEAR(msg.pose.pose.orientation.z, std::sin(0.25), 1e-12);
  EXPECT_NEAR(msg.pose.pose.orientation.w, std::cos(0.25), 1e-12);
  EXPECT_DOUBLE_EQ(msg.twist.twist.linear.x, 1.0);
  EXPECT_DOUBLE_EQ(msg.twist.twist.angular.z, 0.2);
  for (int k = 0; k < 6; ++k) EXPECT_GT(msg.twist.covariance[7 * k], 0.0);
}

TEST(Ros2Messages, TransformCarriesParentChildAndPose) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(4.0, 5.0, 6.0);
  const std::string map = "map", odom = "odom";
  const auto tf = ToRos2Transform(T, {7, 8}, map, odom);
  EXPECT_STREQ(tf.header.frame_id, "map");
  EXPECT_STREQ(tf.child_frame_id, "odom");
  EXPECT_DOUBLE_EQ(tf.transform.translation.z, 6.0);
  EXPECT_DOUBLE_EQ(tf.transform.rotation.w, 1.0);
}

TEST(Ros2Messages, LabelledCloudHasXyzNormalsAndLabel) {
  LabelledPoints points;
  points.points_sensor = {{1.0, 2.0, 3.0}, {4.0, 5.0, 6.0}};
  points.points_map = points.points_sensor;
  points.normals = {{0.0f, 0.0f, 1.0f}, {1.0f, 0.0f, 0.0f}};
  points.labels = {PointClass::Ground, PointClass::Wall};
  const CloudMessage msg = LabelledToRos2Cloud(points, "os_sensor");
  ASSERT_EQ(msg.point_step, 28u);
  ASSERT_EQ(msg.data.size(), 56u);
  ASSERT_EQ(msg.fields.size(), 7u);
  EXPECT_EQ(msg.fields[6].name, "label");
  EXPECT_EQ(msg.fields[6].offset, 24u);
  EXPECT_EQ(msg.data[28 + 24], static_cast<std::uint8_t>(PointClass::Wall));
  // Readable by the input path too (a ROS 2 tool reads it the same way).
  CloudLimits limits;
  limits.point_times = PointTimes::kOptional;
  const CloudConversion back = CloudToScan(ViewOf(Ros2CloudView(msg).get()), limits);
  ASSERT_TRUE(back.scan) << back.error;
  EXPECT_EQ(back.scan->points[1], Eigen::Vector3d(4.0, 5.0, 6.0));
}

}  // namespace
}  // namespace dammloam::dds
