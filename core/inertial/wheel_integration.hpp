#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <span>

#include "core/inertial/wheel_sample.hpp"

// Wheel odometry's motion of the LiDAR sensor over an interval (issue 55): the base frame's
// twist integrated between two scan times and carried to the sensor through T_sensor_base,
// with a covariance built from the errors wheel odometry really has.
namespace dammloam {

// What wheel odometry gets wrong, 1 sigma. Defaults: a small differential-drive robot on an
// indoor floor (the simulator's wheeled carrier, docs/presets.md, draws errors of this size).
struct WheelNoise {
  // White noise per reported sample (encoder quantisation, the controller's jitter).
  double speed_noise = 0.01;      // m/s
  double yaw_rate_noise = 0.005;  // rad/s
  // A worn tyre or a wrong wheel radius scales the distance, a wrong track width the turn: a
  // calibrated robot is within 1-2 %. Taken as independent per interval, so an interval's
  // position is known to 2 % of its length however many intervals came before.
  double speed_scale = 0.02;     // of the distance driven
  double yaw_rate_scale = 0.02;  // of the angle turned
  // In a turn the tyres slide: skid-steer wheels report more turn than the body makes, and the
  // body drifts outwards, both in proportion to the lateral acceleration (v * yaw rate).
  double yaw_slip = 0.03;      // rad/s per m/s^2
  double lateral_slip = 0.02;  // m/s per m/s^2
  // The sensor rides on the body's suspension while the wheels measure the chassis: vertical
  // and lateral vibration of ~2 mm RMS differs by ~3 mm between two scan middles. Along the
  // drive only the body's pitch (0.1 deg at half a metre) moves it, ~1 mm. A differential drive
  // reports neither; these also cover the extrinsic's and the clock's small errors.
  double vibration = 0.003;               // m per interval, lateral and vertical
  double longitudinal_model_error = 0.001;  // m per interval
};

struct WheelIntegrationConfig {
  // Longest time between two samples (or from the interval's end to the nearest sample) that is
  // bridged, s: 3.5 periods of a 50 Hz controller. A longer gap is a stalled driver, and what
  // the wheels did within it is unknown.
  double max_gap = 0.07;
  WheelNoise noise;
};

// Whether the samples measure the whole interval, or why not (the caller then falls back to the
// LiDAR and its constant-velocity model for that interval).
enum class WheelCoverage : std::uint8_t {
  kCovered = 0,
  kNoSamples,  // none reaches the interval (no wheel odometry yet, or it stopped)
  kGap,        // a gap longer than max_gap inside or at an end
};
const char* Name(WheelCoverage coverage);

// The sensor's motion over [t0, t1] by wheel odometry. Only meaningful when covered().
struct WheelTrack {
  WheelCoverage coverage = WheelCoverage::kNoSamples;
  double t0 = 0.0, t1 = 0.0;
  // T_sensor(t0)_sensor(t1).
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  // Of motion's translation, in the sensor frame at t0, m^2.
  Eigen::Matrix3d translation_covariance = Eigen::Matrix3d::Zero();
  // Of the turn about the base's vertical, rad^2.
  double yaw_variance = 0.0;
  double distance = 0.0;  // path length of the base, m
  bool covered() const { return coverage == WheelCoverage::kCovered; }
};

// Integrates `samples` (sorted by strictly increasing stamp, LiDAR clock, finite) over
// [t0, t1]: the base twist linearly interpolated between samples (held beyond the outer
// samples by up to max_gap), each step exact for its mean twist.
WheelTrack IntegrateWheel(std::span<const WheelSample> samples, double t0, double t1,
                          const Eigen::Isometry3d& T_sensor_base,
                          const WheelIntegrationConfig& config);

}  // namespace dammloam
