#pragma once
#include <Eigen/Core>

#include "core/inertial/inertial_config.hpp"

// The gyroscope's bias, estimated online (issue 55): a three-state Kalman filter whose
// measurements are how far the rotation the LiDAR registered between two scans departs from
// the rotation the gyro integrated over the same interval with the current bias estimate.
namespace dammloam {

struct GyroBiasConfig {
  // Prior on the bias at start-up, 1 sigma per axis, rad/s: a turned-on ICM-20948 is within
  // ~0.3 deg/s (docs/presets.md); 0.5 deg/s leaves room for an untrimmed part.
  double initial_sigma = 0.5 * 3.14159265358979323846 / 180.0;
  // A departure beyond this chi-square (3 degrees of freedom, 99.9 %) is shortened to it (a
  // Huber weight), so one slipped registration moves the bias little. Rejecting it outright locked a wrong estimate in: once confident, the filter
  // refused every departure that would have corrected it (a 2 Hz look-around run kept its y
  // bias 0.78 deg/s off, every scan's rotation 0.4 deg off the gyro's).
  double gate_chi2 = 16.27;
  // The estimate's uncertainty never falls below this (rad/s, 1 sigma per axis), so that it
  // keeps following the data (0.02 deg/s).
  double min_sigma = 0.02 * 3.14159265358979323846 / 180.0;
  // The bias at start-up (IMU frame, rad/s): a calibration's, else zero.
  Eigen::Vector3d initial_bias = Eigen::Vector3d::Zero();
  // false: the bias stays at initial_bias (a calibrated unit; comparisons).
  bool estimate = true;
};

class GyroBiasFilter {
 public:
  GyroBiasFilter(const ImuNoise& noise, const GyroBiasConfig& config);

  const Eigen::Vector3d& bias() const { return bias_; }              // rad/s, IMU frame
  const Eigen::Matrix3d& covariance() const { return covariance_; }  // IMU frame
  // The bias walks between measurements: its uncertainty grows over dt seconds.
  void Propagate(double dt);
  // `departure` = Log(R_gyro^T R_measured) over `interval` seconds (sensor frame at the end),
  // with the measurement's own covariance (sensor frame; the gyro's white noise is added here).
  // A rate bias db rotates the gyro's estimate by about interval * db, so the departure is
  // -interval * R_sensor_imu * db. Returns false when it lay beyond the gate (down-weighted).
  bool Update(const Eigen::Vector3d& departure, const Eigen::Matrix3d& measurement_covariance,
              double interval, const Eigen::Matrix3d& R_sensor_imu);

 private:
  ImuNoise noise_;
  GyroBiasConfig config_;
  Eigen::Vector3d bias_ = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance_;
};

}  // namespace dammloam
