#pragma once
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>

#include "core/inertial/wheel_integration.hpp"

namespace dammloam {

// How the odometry uses wheel odometry (issue 55): the base twist integrated from the previous
// scan's middle to this one's is the prediction's translation (and its rotation without a
// gyro), and a translation prior of the registration weighted by its covariance, so that a
// direction the scan leaves unobserved follows the wheels. Plain values with defaults.
struct WheelUseConfig {
  // base frame in the sensor frame: p_sensor = T_sensor_base p_base (meta.json base_extrinsic).
  Eigen::Isometry3d T_sensor_base = Eigen::Isometry3d::Identity();
  WheelIntegrationConfig integration;
  // A reading beyond these is no robot's motion (a corrupted message, a unit error): dropped.
  // Well above a delivery robot's 2 m/s and a skid-steer's 3 rad/s spin, below anything a
  // rolling carrier that carries a LiDAR does.
  double max_speed = 20.0;     // m/s
  double max_yaw_rate = 10.0;  // rad/s (any axis)
  // Samples older than this before the last scan are dropped from the buffer, s.
  double history = 1.0;
};

// Why AddWheel refused samples, counted.
struct WheelRejections {
  std::size_t not_enabled = 0;   // no EnableWheel
  std::size_t non_finite = 0;    // a NaN or infinite stamp or value
  std::size_t duplicate = 0;     // the same stamp as the previous sample
  std::size_t out_of_order = 0;  // older than the previous sample
  std::size_t absurd = 0;        // beyond max_speed or max_yaw_rate
  std::size_t total() const { return not_enabled + non_finite + duplicate + out_of_order + absurd; }
};

}  // namespace dammloam
