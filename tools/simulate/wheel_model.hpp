#pragma once
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "core/inertial/wheel_sample.hpp"
#include "tools/simulate/rigid_motion.hpp"

// Wheel odometry of a differential-drive (or car-like) carrier, read from the chassis' exact
// motion (Trajectory::ChassisPose: no shake or vibration, which the wheels do not see). It
// reports what such odometry can: the forward speed and the yaw rate of the base frame; vy,
// vz, wx, wy are 0. Errors: a wrong wheel radius (speed scale), a wrong track width (yaw-rate
// scale), slip in turns (the wheels slide outwards, so they report more turn than the body
// makes, in proportion to the lateral acceleration) and white noise.
namespace dammloam::sim {

struct WheelSimOptions {
  double rate_hz = 50.0;
  // |scale error| of speed and of yaw rate, each drawn per seed in [min, max] with a random sign.
  double scale_error_min = 0.01, scale_error_max = 0.02;
  // Yaw rate reported beyond the true one per m/s^2 of lateral acceleration (v * yaw rate),
  // in the direction of the turn: 0.03 rad/s at 1 m/s^2 (a skid-steer robot's tyres, lightly).
  double slip_yaw_per_lateral_accel = 0.03;
  double speed_noise = 0.01;     // m/s, per sample
  double yaw_rate_noise = 0.005;  // rad/s, per sample
  bool noiseless = false;         // exact twist: no scale, slip or noise
};

// What a run drew (for tests and for checking an estimator).
struct WheelErrors {
  double speed_scale = 1.0, yaw_rate_scale = 1.0;
};

// The exact twist of the base frame at drive time t: T_world_base = chassis(t) * T_chassis_base.
struct BaseTwist {
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();   // m/s, base frame
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();  // rad/s, base frame
};
BaseTwist TrueBaseTwistAt(const PoseOfTime& chassis, const Eigen::Isometry3d& T_chassis_base, double t);

// Samples at drive times t_begin, t_begin + 1/rate, ... <= t_end, stamped clock_zero + t.
std::vector<WheelSample> SimulateWheel(const PoseOfTime& chassis, const Eigen::Isometry3d& T_chassis_base,
                                       double clock_zero, double t_begin, double t_end,
                                       const WheelSimOptions& options, std::uint64_t seed,
                                       WheelErrors* drawn = nullptr);

}  // namespace dammloam::sim
