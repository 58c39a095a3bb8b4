#pragma once
#include <Eigen/Geometry>

// What a sequence or a deployment says about its IMU and wheel odometry (meta.json "imu",
// "imu_extrinsic", "base_extrinsic"; sequence.md). Plain values, no file format here.
namespace dammloam {

// Continuous-time noise of a MEMS IMU, the values a Kalibr/Allan-variance calibration gives.
// Defaults: the TDK InvenSense ICM-20948 of Ouster sensors. Datasheet DS-000189 rev 1.3: gyro
// rate noise 0.015 deg/s/sqrt(Hz), accel noise 230 ug/sqrt(Hz). The bias random walks are not
// in the datasheet; these are typical of consumer MEMS parts in published calibrations.
struct ImuNoise {
  double gyro_noise_density = 0.015 * 3.14159265358979323846 / 180.0;  // rad/s/sqrt(Hz)
  double accel_noise_density = 230e-6 * 9.80665;                       // m/s^2/sqrt(Hz)
  double gyro_bias_random_walk = 4.0e-5;                               // rad/s^2/sqrt(Hz)
  double accel_bias_random_walk = 4.0e-4;                              // m/s^3/sqrt(Hz)
};

// The Ouster OS1's imu_to_sensor_transform (metres, identity rotation): the IMU's origin in the
// LiDAR sensor frame, p_sensor = R p_imu + t.
inline Eigen::Isometry3d OusterOs1ImuToSensor() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.006253, -0.011775, 0.007645);
  return T;
}

struct ImuDescription {
  Eigen::Isometry3d T_sensor_imu = OusterOs1ImuToSensor();
  ImuNoise noise;
  // IMU stamp minus the LiDAR-clock time the sample was measured at, seconds: subtract it from
  // imu.csv's stamps to put them on the LiDAR clock. 0 when unknown.
  double time_offset = 0.0;
};

}  // namespace dammloam
