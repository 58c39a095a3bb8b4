#include "services/dds/inertial_messages.hpp"

#include "services/dds/point_cloud.hpp"

namespace dammloam::dds {
namespace {

dammloam_msg_Vector3 ToVector(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
Eigen::Vector3d FromVector(const dammloam_msg_Vector3& v) { return {v.x, v.y, v.z}; }

dammloam_msg_MessageHeader Header(double t, const std::string& frame_id, std::uint64_t seq) {
  dammloam_msg_MessageHeader header{};
  header.stamp = ToMsgTime(t);
  header.frame_id = const_cast<char*>(frame_id.c_str());
  header.seq = seq;
  return header;
}

}  // namespace

dammloam_msg_Imu ToImuMessage(const ImuSample& sample, const ImuNoise& noise, double rate_hz,
                              const std::string& frame_id, std::uint64_t seq) {
  dammloam_msg_Imu m{};
  m.header = Header(sample.t, frame_id, seq);
  m.angular_velocity = ToVector(sample.angular_velocity);
  m.linear_acceleration = ToVector(sample.linear_acceleration);
  const double gyro_var = noise.gyro_noise_density * noise.gyro_noise_density * rate_hz;
  const double accel_var = noise.accel_noise_density * noise.accel_noise_density * rate_hz;
  for (int i = 0; i < 3; ++i) {
    m.angular_velocity_covariance[4 * i] = gyro_var;
    m.linear_acceleration_covariance[4 * i] = accel_var;
  }
  return m;
}

ImuSample FromImuMessage(const dammloam_msg_Imu& message) {
  return {ToSeconds(message.header.stamp), FromVector(message.angular_velocity),
          FromVector(message.linear_acceleration)};
}

ImuSample FromRos2Imu(const sensor_msgs_msg_dds__Imu_& message) {
  const auto& w = message.angular_velocity;
  const auto& a = message.linear_acceleration;
  return {ToSeconds(dammloam_msg_Time{message.header.stamp.sec, message.header.stamp.nanosec}),
          {w.x, w.y, w.z}, {a.x, a.y, a.z}};
}

dammloam_msg_WheelOdometry ToWheelMessage(const WheelSample& sample, double speed_sigma,
                                          double yaw_rate_sigma, const std::string& frame_id,
                                          std::uint64_t seq) {
  constexpr double kUnmeasured = 1e6;
  dammloam_msg_WheelOdometry m{};
  m.header = Header(sample.t, frame_id, seq);
  m.linear_velocity = ToVector(sample.linear_velocity);
  m.angular_velocity = ToVector(sample.angular_velocity);
  for (int i = 0; i < 6; ++i) m.covariance[7 * i] = kUnmeasured;
  m.covariance[0] = speed_sigma * speed_sigma;
  m.covariance[35] = yaw_rate_sigma * yaw_rate_sigma;
  return m;
}

WheelSample FromWheelMessage(const dammloam_msg_WheelOdometry& message) {
  return {ToSeconds(message.header.stamp), FromVector(message.linear_velocity),
          FromVector(message.angular_velocity)};
}

WheelSample FromRos2WheelOdometry(const nav_msgs_msg_dds__Odometry_& message) {
  const auto& v = message.twist.twist.linear;
  const auto& w = message.twist.twist.angular;
  return {ToSeconds(dammloam_msg_Time{message.header.stamp.sec, message.header.stamp.nanosec}),
          {v.x, v.y, v.z}, {w.x, w.y, w.z}};
}

}  // namespace dammloam::dds
