#pragma once
// ImuSample / WheelSample (core/inertial) <-> the Imu and WheelOdometry samples, and ROS 2
// sensor_msgs/Imu -> ImuSample, nav_msgs/Odometry's twist -> WheelSample (issue 55).
#include <string>

#include "core/inertial/imu_sample.hpp"
#include "core/inertial/inertial_config.hpp"
#include "core/inertial/wheel_sample.hpp"
#include "dammloam.h"
#include "nav_msgs.h"
#include "sensor_msgs.h"

namespace dammloam::dds {

// The covariances are the white noise per sample at `rate_hz` (density^2 * rate) on the
// diagonal. frame_id must outlive the returned sample (it is pointed to, not copied).
dammloam_msg_Imu ToImuMessage(const ImuSample& sample, const ImuNoise& noise, double rate_hz,
                              const std::string& frame_id, std::uint64_t seq);
ImuSample FromImuMessage(const dammloam_msg_Imu& message);
// ROS 2 sensor_msgs/Imu (its orientation, if any, is not read).
ImuSample FromRos2Imu(const sensor_msgs_msg_dds__Imu_& message);

// Variances: `speed_sigma`^2 on vx, `yaw_rate_sigma`^2 on wz, 1e6 on the unmeasured components.
dammloam_msg_WheelOdometry ToWheelMessage(const WheelSample& sample, double speed_sigma,
                                          double yaw_rate_sigma, const std::string& frame_id,
                                          std::uint64_t seq);
WheelSample FromWheelMessage(const dammloam_msg_WheelOdometry& message);
// ROS 2 nav_msgs/Odometry from a wheel controller (diff_drive_controller's /odom): its twist, in
// child_frame_id (the base frame); its pose, integrated by the robot, is not read.
WheelSample FromRos2WheelOdometry(const nav_msgs_msg_dds__Odometry_& message);

}  // namespace dammloam::dds
