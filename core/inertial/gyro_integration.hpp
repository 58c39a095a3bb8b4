#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

#include "core/inertial/imu_sample.hpp"

// The gyroscope's rotation of the LiDAR sensor frame over an interval (issue 55): what turned
// the sensor between two scans and within one, measured at 100 Hz instead of assumed constant.
namespace dammloam {

struct GyroIntegrationConfig {
  // Longest time between two samples (or from the interval's end to the nearest sample) that is
  // bridged, s: 3.5 periods of the OS1's 100 Hz. A longer gap is a stalled driver or lost
  // packets, and the turn within it is unknown.
  double max_gap = 0.035;
  // A reading at or beyond this on any axis is taken as clipped, rad/s: the ICM-20948's full
  // scale of 2000 deg/s less 50 deg/s, since a clipped reading may sit a little below it.
  double saturation_rate = 1950.0 * 3.14159265358979323846 / 180.0;
};

// Whether the samples measure the whole interval, or why not (the caller then falls back to the
// LiDAR alone for that scan).
enum class GyroCoverage : std::uint8_t {
  kCovered = 0,
  kNoSamples,   // none reaches the interval (no IMU yet, or it stopped)
  kGap,         // a gap longer than max_gap inside or at an end
  kSaturated,   // a reading at the full scale: the true rate is unknown
  kNonFinite,   // a NaN or infinite reading
};
const char* Name(GyroCoverage coverage);

// How the gyroscope is read: its mounting, its bias and how well both are known.
struct GyroCalibration {
  Eigen::Matrix3d R_sensor_imu = Eigen::Matrix3d::Identity();  // the extrinsic's rotation
  Eigen::Vector3d bias = Eigen::Vector3d::Zero();               // rad/s, IMU frame
  Eigen::Matrix3d bias_covariance = Eigen::Matrix3d::Zero();    // rad^2/s^2, IMU frame
  double noise_density = 0.0;       // white rate noise, rad/s/sqrt(Hz)
  double bias_random_walk = 0.0;    // rad/s^2/sqrt(Hz)
};

// The sensor's orientation over [t0, t1] relative to t0, from bias-corrected rates in the
// sensor frame, linearly interpolated between samples (and held beyond the outer samples by up
// to max_gap). Only meaningful when covered().
class GyroTrack {
 public:
  GyroCoverage coverage() const { return coverage_; }
  bool covered() const { return coverage_ == GyroCoverage::kCovered; }
  double t0() const { return t0_; }
  double t1() const { return t1_; }
  // R_t0_t: the orientation at t (clamped to [t0, t1]) in the sensor frame at t0.
  Eigen::Matrix3d At(double t) const;
  Eigen::Matrix3d Rotation() const { return At(t1_); }
  // Of Rotation(), as a right perturbation (sensor frame at t1), rad^2: the rate noise's angle
  // random walk, the bias uncertainty times the interval, and the bias's walk within it.
  const Eigen::Matrix3d& covariance() const { return covariance_; }

 private:
  friend GyroTrack IntegrateGyro(std::span<const ImuSample>, double, double,
                                 const GyroCalibration&, const GyroIntegrationConfig&);
  GyroCoverage coverage_ = GyroCoverage::kNoSamples;
  double t0_ = 0.0, t1_ = 0.0;
  // Knots: t0, the sample times inside (t0, t1), t1; the rate (sensor frame, bias-corrected)
  // and the orientation at each.
  std::vector<double> times_;
  std::vector<Eigen::Vector3d> rates_;
  std::vector<Eigen::Matrix3d> rotations_;
  Eigen::Matrix3d covariance_ = Eigen::Matrix3d::Zero();
};

// Integrates `samples` (sorted by strictly increasing stamp, LiDAR clock) over [t0, t1].
GyroTrack IntegrateGyro(std::span<const ImuSample> samples, double t0, double t1,
                        const GyroCalibration& calibration, const GyroIntegrationConfig& config);

}  // namespace dammloam
