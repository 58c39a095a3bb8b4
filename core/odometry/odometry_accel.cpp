// The accelerometer in the odometry (issues 52, 55): the velocity change it integrated between
// the previous scan's middle and this one's drives the motion prior once gravity is learned.
#include "core/odometry/odometry.hpp"

#include <span>

namespace dammloam {

std::optional<VelocityIncrement> Odometry::TrackAccel(const GyroTracks& gyro,
                                                      std::optional<AccelCoverage>& why) const {
  if (!gravity_ || !initialised_) return std::nullopt;
  if (!gyro.interval) {
    why = AccelCoverage::kNoRotation;
    return std::nullopt;
  }
  VelocityIncrement increment =
      IntegrateSpecificForce(std::span<const ImuSample>(imu_samples_), *gyro.interval,
                             imu_->T_sensor_imu, config_.accelerometer.saturation);
  why = increment.coverage;
  if (!increment.covered()) return std::nullopt;
  return increment;
}

std::optional<AccelerationTrack> Odometry::TrackAccelInScan(
    const GyroTrack& scan_track, const Eigen::Matrix3d& R_world_start) const {
  if (!gravity_ || !gravity_->ready() || !config_.accelerometer.deskew) return std::nullopt;
  return TrackAcceleration(std::span<const ImuSample>(imu_samples_), scan_track,
                           imu_->T_sensor_imu, config_.accelerometer.saturation, gravity_->bias(),
                           R_world_start.transpose() * gravity_->gravity());
}

// Wheels measure the translation itself and take precedence; the velocity it starts from must
// be the registered one of the scan before.
bool Odometry::UsesAccel(const Frame& frame) const {
  return frame.accel_interval && gravity_ && gravity_->ready() && world_velocity_known_ &&
         !frame.wheel_interval && UsesMotionPrior(config_.registration.mode);
}

Odometry::AccelChange Odometry::VelocityChangeByAccel(const Frame& frame, double dt) const {
  const VelocityIncrement& increment = *frame.accel_interval;
  const Eigen::Matrix3d& R = T_world_last_.linear();
  return {gravity_->VelocityChange(R * increment.velocity, R * increment.bias_to_velocity, dt),
          gravity_->Trusted(R * increment.bias_to_velocity, dt)};
}

// Along the directions gravity is known well enough; along the others (never observed, as the
// axis of a featureless corridor) the constant-velocity model stands: there a gravity guessed
// from the first second's mean force, 0.5 m/s^2 off, ran the handheld-endless walk to 1.8 km.
void Odometry::PredictWithAccel(Frame& frame, double dt) const {
  const VelocityIncrement& increment = *frame.accel_interval;
  const Eigen::Matrix3d& R = T_world_last_.linear();
  const auto [change, trusted] = VelocityChangeByAccel(frame, dt);
  if (trusted.isZero(0.0)) return;
  const Eigen::Vector3d bias = gravity_->bias();
  // The bias acts on the displacement as on the velocity, over half the interval on average.
  const Eigen::Vector3d displacement = R * (increment.displacement -
                                            0.5 * dt * increment.bias_to_velocity * bias) +
                                       0.5 * dt * dt * gravity_->gravity();
  const Eigen::Matrix3d untrusted = Eigen::Matrix3d::Identity() - trusted;
  frame.T_pred.translation() =
      untrusted * frame.T_pred.translation() +
      trusted * (T_world_last_.translation() + dt * world_velocity_ + displacement);
  frame.accel_velocity = untrusted * WorldVelocity(dt) + trusted * (world_velocity_ + change);
  frame.accel_trusted = trusted;
}

void Odometry::LearnGravity(const Frame& frame, const RegistrationResult& reg,
                            const Eigen::Vector3d& velocity_before, double dt) {
  if (!frame.accel_interval || !gravity_ || !Consecutive(dt)) return;
  const Eigen::Matrix3d& R = velocity_frame_;  // the previous scan's orientation
  // A velocity change is two positions over dt apart, each known as well as the scan's own
  // position information says; along a direction the scans hardly see it is the prediction's.
  const Eigen::Matrix3d I_tt = reg.PositionInformation();
  constexpr double kUnobservedInformation = 1e-6;  // 1/m^2: a kilometre
  const Eigen::Matrix3d position_covariance =
      (I_tt + kUnobservedInformation * Eigen::Matrix3d::Identity()).ldlt().solve(Eigen::Matrix3d::Identity());
  gravity_->Add(world_velocity_ - velocity_before, R * frame.accel_interval->velocity,
                R * frame.accel_interval->bias_to_velocity, dt, 2.0 * position_covariance / (dt * dt));
}

}  // namespace dammloam
