#pragma once
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "core/inertial/imu_sample.hpp"
#include "core/inertial/inertial_config.hpp"
#include "tools/simulate/rigid_motion.hpp"

// A strapdown IMU rigidly mounted on the LiDAR, read from the exact trajectory: angular
// velocity and specific force f = R_world_imu^T (a - g) in the IMU frame at the lever arm of
// T_sensor_imu, plus consumer-MEMS errors (white noise, turn-on bias, bias random walk), full
// scale saturation and a clock offset.
namespace dammloam::sim {

inline const Eigen::Vector3d kGravity(0.0, 0.0, -9.81);  // world frame, z up

struct ImuSimOptions {
  double rate_hz = 100.0;  // the Ouster OS1's IMU rate
  // Extrinsic (default: the OS1's imu_to_sensor_transform), noise densities (ICM-20948) and
  // clock offset: stamp = LiDAR-clock time of the measurement + time_offset.
  ImuDescription description{OusterOs1ImuToSensor(), ImuNoise{}, 0.003};
  // Turn-on bias, standard deviation per axis, drawn once per run. The datasheet bounds the
  // untrimmed part at +-5 deg/s and +-25 mg (component level); a turned-on, trimmed unit is
  // much closer: 0.3 deg/s and 10 mg.
  double gyro_turn_on_bias = 0.3 * 3.14159265358979323846 / 180.0;  // rad/s
  double accel_turn_on_bias = 0.010 * 9.80665;                        // m/s^2
  // Full scale as Ouster configures it (+-2000 deg/s is the part's widest; accelerometer +-16 g
  // likewise): readings are clipped there.
  double gyro_full_scale = 2000.0 * 3.14159265358979323846 / 180.0;  // rad/s
  double accel_full_scale = 16.0 * 9.80665;                           // m/s^2
  bool noiseless = false;  // no noise, no biases, no clock offset: the exact signal
};

// The exact reading at drive time t of an IMU at T_sensor_imu on a sensor moving as `pose`.
struct ImuTruth {
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  // rad/s, IMU frame
  Eigen::Vector3d specific_force = Eigen::Vector3d::Zero();    // m/s^2, IMU frame
  RigidMotion imu_motion;                                      // of the IMU's own frame
};
ImuTruth TrueImuAt(const PoseOfTime& pose, const Eigen::Isometry3d& T_sensor_imu, double t);

// The turn-on biases a run drew (for tests and for checking an estimator's bias estimate).
struct ImuBiases {
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero(), accel = Eigen::Vector3d::Zero();
};

// Samples measured at drive times t_begin, t_begin + 1/rate, ... <= t_end, stamped
// clock_zero + t + time_offset (clock_zero: the absolute stamp of drive time 0). Seeded by
// `seed` through the IMU's own stream. `turn_on`, if given, receives the drawn biases.
std::vector<ImuSample> SimulateImu(const PoseOfTime& pose, double clock_zero, double t_begin,
                                   double t_end, const ImuSimOptions& options, std::uint64_t seed,
                                   ImuBiases* turn_on = nullptr);

}  // namespace dammloam::sim
