#pragma once
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "core/inertial/gyro_integration.hpp"
#include "core/inertial/imu_sample.hpp"

// What the accelerometer measured between two scans (issues 52, 55): the specific force at the
// LiDAR sensor's origin, turned into the sensor frame at the interval's start by the gyro's
// track, integrated once (a velocity change) and twice (a displacement). Gravity and the
// accelerometer's bias are left in: GravityEstimate knows them in the world frame.
namespace dammloam {

enum class AccelCoverage : std::uint8_t {
  kCovered = 0,
  kNoRotation,  // the gyro does not cover the interval: the force's direction is unknown
  kNonFinite,   // a NaN or infinite reading
  kSaturated,   // a reading at the full scale: the true force is unknown
};
const char* Name(AccelCoverage coverage);

struct VelocityIncrement {
  AccelCoverage coverage = AccelCoverage::kNoRotation;
  bool covered() const { return coverage == AccelCoverage::kCovered; }
  double duration = 0.0;  // s
  // Sensor frame at the interval's start: integral of R_t0_t f(t) dt (m/s) and its integral
  // over the interval (m).
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  Eigen::Vector3d displacement = Eigen::Vector3d::Zero();
  // Integral of R_t0_t R_sensor_imu dt (s): how a constant bias (IMU frame) enters `velocity`.
  Eigen::Matrix3d bias_to_velocity = Eigen::Matrix3d::Zero();
};

// `rotation` is the gyro's track over the interval (its t0 and t1 define it); `samples` sorted by
// strictly increasing stamp. The IMU sits at T_sensor_imu's translation: the sensor's origin
// feels the turn's centripetal and tangential accelerations on top of the IMU's.
// `saturation`: a reading at or beyond it on any axis counts as clipped (m/s^2).
VelocityIncrement IntegrateSpecificForce(std::span<const ImuSample> samples, const GyroTrack& rotation,
                                         const Eigen::Isometry3d& T_sensor_imu, double saturation);

// Where the sensor's origin went within an interval beyond what its velocity at t0 carried it:
// the twice-integrated acceleration (gravity and the bias taken out), in the sensor frame at t0,
// at t0 and every knot. Within a scan the error of a gravity or bias estimate hardly counts
// (0.5 m/s^2 off moves the middle of a 0.1 s scan by 0.6 mm), while a running bounce's 10 m/s^2
// bends it by a centimetre.
struct AccelerationTrack {
  std::vector<double> times;
  std::vector<Eigen::Vector3d> displacement;  // m
  std::vector<Eigen::Vector3d> velocity;      // m/s: the velocity gained since t0
  // Linear between knots, held outside.
  Eigen::Vector3d At(double t) const { return Interpolate(displacement, t); }
  Eigen::Vector3d VelocityAt(double t) const { return Interpolate(velocity, t); }

 private:
  Eigen::Vector3d Interpolate(const std::vector<Eigen::Vector3d>& values, double t) const;
};
// Over `rotation`'s interval, as IntegrateSpecificForce; `bias` (IMU frame) and `gravity_start`
// (the sensor frame at t0) in m/s^2. Nothing where the force is not covered.
std::optional<AccelerationTrack> TrackAcceleration(std::span<const ImuSample> samples,
                                                   const GyroTrack& rotation,
                                                   const Eigen::Isometry3d& T_sensor_imu,
                                                   double saturation, const Eigen::Vector3d& bias,
                                                   const Eigen::Vector3d& gravity_start);

}  // namespace dammloam
