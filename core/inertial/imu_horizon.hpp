#pragma once

// Up to which stamp the odometry is to have IMU samples before it registers a scan (issue 55).
// One rule for every feeder (dammloam-odometry's ImuFeed, dammloamd, and dammloam-replay, which
// publishes ahead of each scan what the daemon will wait for), so that a live run hands the
// estimator the same samples as the offline runner.
namespace dammloam {

// Two periods of the OS1's 100 Hz past the scan's end: the gyro track is interpolated at the end.
inline constexpr double kImuLookAhead = 0.02;  // s

// LiDAR clock: every sample stamped at or before this is handed over before the scan.
inline double ImuHorizon(double t_start, double scan_period) {
  return t_start + scan_period + kImuLookAhead;
}

}  // namespace dammloam
