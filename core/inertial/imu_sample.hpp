#pragma once
#include <Eigen/Core>

namespace dammloam {

// One IMU reading, in the IMU's own frame, stamped in the LiDAR's clock (the sequence's
// times.txt clock; a known clock offset is removed before the estimator sees it).
struct ImuSample {
  double t = 0.0;                                            // seconds
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  // rad/s
  // Specific force, what an accelerometer reads: +9.81 on z when level and at rest.
  Eigen::Vector3d linear_acceleration = Eigen::Vector3d::Zero();  // m/s^2
};

}  // namespace dammloam
