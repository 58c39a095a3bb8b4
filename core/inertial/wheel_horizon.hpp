#pragma once

// Up to which stamp the odometry is to have wheel samples before it registers a scan (issue 55).
// One rule for every feeder (dammloam-odometry's WheelFeed, dammloamd, and dammloam-replay, which
// publishes ahead of each scan what the daemon will wait for), as ImuHorizon is for the IMU: a
// live run then hands the estimator the same samples as the offline runner.
namespace dammloam {

// Two periods of a 50 Hz wheel controller past the scan's end: the interval the wheels measure
// ends at the scan's middle, and its bracketing sample comes after that.
inline constexpr double kWheelLookAhead = 0.04;  // s

// LiDAR clock: every sample stamped at or before this is handed over before the scan.
inline double WheelHorizon(double t_start, double scan_period) {
  return t_start + scan_period + kWheelLookAhead;
}

}  // namespace dammloam
