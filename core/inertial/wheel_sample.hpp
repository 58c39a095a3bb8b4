#pragma once
#include <Eigen/Core>

namespace dammloam {

// One wheel-odometry reading: the carrier's body twist in its base frame (x forward, z up, on
// the ground under the sensor), as nav_msgs/Odometry's twist. A differential drive measures
// only vx and wz; the other components are then reported as 0.
struct WheelSample {
  double t = 0.0;                                          // seconds, LiDAR clock
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();   // m/s
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  // rad/s
};

}  // namespace dammloam
