#pragma once

#include "core/inertial/gyro_bias_filter.hpp"
#include "core/inertial/gyro_integration.hpp"

namespace dammloam {

// How the odometry uses a gyroscope (issue 55): the prediction's rotation, the per-point
// deskew's rotation and the rotation prior of the registration come from its integrated rates,
// its bias is estimated online. Plain values with defaults for the ICM-20948 of Ouster sensors.
struct GyroUseConfig {
  GyroIntegrationConfig integration;
  GyroBiasConfig bias;
  // What the noise model leaves out, 1 sigma per interval, rad, added to the gyro's covariance
  // in the registration's prior: rates sampled at 100 Hz and interpolated linearly miss part
  // of a hand's 6-18 Hz shake (trapezoid error ~(h w)^2 / 12 of its 0.15 deg, a few 1e-4 rad
  // within a scan), and the extrinsic and the clock offset are known only so well.
  double model_error = 3e-4;
  // The scan's own turn rate may depart from the gyro's by this much (rad/s, 1 sigma), its
  // angular acceleration by this (rad/s^2; 0: not estimated): the gyro measured both.
  double in_scan_rate_sigma = 0.002;
  double in_scan_angular_acceleration_sigma = 0.0;
  // Bias learning: the LiDAR's rotation between scans counts with at least this sigma (rad): its
  // own covariance assumes the map exact.
  double min_measurement_sigma = 2e-4;
  // Standing still: the registration moved the sensor less than these since the last scan;
  // the true rotation is then taken as zero to within standstill_sigma (rad).
  double standstill_translation = 0.001;  // m
  double standstill_rotation = 1e-4;      // rad
  double standstill_sigma = 5e-5;         // rad
  // Samples older than this before the last scan are dropped from the buffer, s.
  double history = 1.0;
};

}  // namespace dammloam
