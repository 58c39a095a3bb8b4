// Imu and WheelOdometry samples (issue 55) <-> ImuSample / WheelSample: values and stamps come
// back exact (stamps to the nanosecond), covariances are the per-sample white noise; ROS 2
// nav_msgs/Odometry -> WheelSample.
#include <gtest/gtest.h>

#include <cstring>

#include "services/dds/inertial_messages.hpp"

namespace dammloam::dds {
namespace {

TEST(InertialMessages, ImuRoundTripAndCovariance) {
  const ImuSample sample{1700000000.123456789, {0.1, -0.2, 3.0}, {0.05, -0.01, 9.81}};
  const std::string frame = "imu";
  ImuNoise noise;
  const dammloam_msg_Imu m = ToImuMessage(sample, noise, 100.0, frame, 42);
  EXPECT_STREQ(m.header.frame_id, "imu");
  EXPECT_EQ(m.header.seq, 42u);
  EXPECT_EQ(m.header.stamp.sec, 1700000000);
  EXPECT_EQ(m.header.stamp.nanosec, 123456717u);  // the double (..716537) rounded
  const ImuSample back = FromImuMessage(m);
  EXPECT_NEAR(back.t, sample.t, 3e-7);  // a double near 1.7e9 s resolves 2.4e-7 s
  EXPECT_EQ(back.angular_velocity, sample.angular_velocity);
  EXPECT_EQ(back.linear_acceleration, sample.linear_acceleration);
  const double gyro_var = noise.gyro_noise_density * noise.gyro_noise_density * 100.0;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_DOUBLE_EQ(m.angular_velocity_covariance[3 * r + c], r == c ? gyro_var : 0.0);
      EXPECT_GT(m.linear_acceleration_covariance[3 * r + r], 0.0);
    }
  }
}

TEST(InertialMessages, WheelRoundTripMarksTheUnmeasuredComponents) {
  const WheelSample sample{12.5, {0.8, 0.0, 0.0}, {0.0, 0.0, -0.3}};
  const std::string frame = "base";
  const dammloam_msg_WheelOdometry m = ToWheelMessage(sample, 0.01, 0.005, frame, 7);
  const WheelSample back = FromWheelMessage(m);
  EXPECT_DOUBLE_EQ(back.t, 12.5);
  EXPECT_EQ(back.linear_velocity, sample.linear_velocity);
  EXPECT_EQ(back.angular_velocity, sample.angular_velocity);
  EXPECT_DOUBLE_EQ(m.covariance[0], 1e-4);
  EXPECT_DOUBLE_EQ(m.covariance[35], 2.5e-5);
  for (const int unmeasured : {7, 14, 21, 28}) EXPECT_GE(m.covariance[unmeasured], 1e6);
  EXPECT_DOUBLE_EQ(m.covariance[1], 0.0);
}

// A wheel controller's nav_msgs/Odometry (diff_drive_controller's /odom): its stamp and twist,
// never the pose it integrated.
TEST(InertialMessages, Ros2OdometryGivesItsTwistNotItsPose) {
  nav_msgs_msg_dds__Odometry_ m{};
  m.header.stamp.sec = 1700000000;
  m.header.stamp.nanosec = 250000000;
  m.pose.pose.position = {4.0, 5.0, 6.0};
  m.pose.pose.orientation.w = 1.0;
  m.twist.twist.linear = {0.8, 0.01, 0.0};
  m.twist.twist.angular = {0.0, 0.0, -0.3};
  const WheelSample s = FromRos2WheelOdometry(m);
  EXPECT_DOUBLE_EQ(s.t, 1700000000.25);
  EXPECT_EQ(s.linear_velocity, Eigen::Vector3d(0.8, 0.01, 0.0));
  EXPECT_EQ(s.angular_velocity, Eigen::Vector3d(0.0, 0.0, -0.3));
}

}  // namespace
}  // namespace dammloam::dds
