// The simulated IMU and wheel odometry (issue 55): the IMU's signal is the exact derivative of
// the trajectory (integrating it reproduces the true pose), its noise has the stated densities,
// the wheel odometry's scale and slip errors are what was drawn, and everything is per seed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "tools/simulate/imu_model.hpp"
#include "tools/simulate/inertial_streams.hpp"
#include "tools/simulate/presets.hpp"
#include "tools/simulate/simulator.hpp"
#include "tools/simulate/wheel_model.hpp"

namespace dammloam::sim {
namespace {

constexpr double kRadToDeg = 180.0 / std::numbers::pi;

Eigen::Matrix3d Exp(const Eigen::Vector3d& phi) {
  const double angle = phi.norm();
  if (angle < 1e-15) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, phi / angle).toRotationMatrix();
}

// Strapdown integration of noiseless samples (trapezoidal in rate and acceleration) from the
// IMU's true state at the first sample; returns the pose at the last one.
Eigen::Isometry3d Integrate(const std::vector<ImuSample>& samples, const RigidMotion& start) {
  Eigen::Matrix3d R = start.T_world_body.linear();
  Eigen::Vector3d p = start.T_world_body.translation(), v = start.velocity_world;
  for (std::size_t k = 0; k + 1 < samples.size(); ++k) {
    const ImuSample &a = samples[k], &b = samples[k + 1];
    const double dt = b.t - a.t;
    const Eigen::Matrix3d R_next = R * Exp(0.5 * dt * (a.angular_velocity + b.angular_velocity));
    const Eigen::Vector3d acc_a = R * a.linear_acceleration + kGravity;
    const Eigen::Vector3d acc_b = R_next * b.linear_acceleration + kGravity;
    p += v * dt + dt * dt / 6.0 * (2.0 * acc_a + acc_b);
    v += 0.5 * dt * (acc_a + acc_b);
    R = R_next;
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R;
  T.translation() = p;
  return T;
}

ImuSimOptions Noiseless(double rate_hz) {
  ImuSimOptions options;
  options.rate_hz = rate_hz;
  options.noiseless = true;
  return options;
}

// Integrates one second of the noiseless IMU at 2 kHz from the true state at t and compares
// with the true pose of the IMU one second later.
void ExpectIntegrationReproducesTruth(const Trajectory& trajectory, double t, const std::string& what) {
  const PoseOfTime pose = [&](double u) { return trajectory.Pose(u); };
  const ImuSimOptions options = Noiseless(2000.0);
  const std::vector<ImuSample> samples = SimulateImu(pose, 0.0, t, t + 1.0, options, 1);
  ASSERT_EQ(samples.size(), 2001u);
  const RigidMotion start = TrueImuAt(pose, options.description.T_sensor_imu, t).imu_motion;
  const Eigen::Isometry3d integrated = Integrate(samples, start);
  const Eigen::Isometry3d truth = pose(t + 1.0) * options.description.T_sensor_imu;
  const double position_error = (integrated.translation() - truth.translation()).norm();
  const double angle_error =
      Eigen::AngleAxisd(Eigen::Matrix3d(integrated.linear().transpose() * truth.linear())).angle() * kRadToDeg;
  std::printf("%s, 1 s from t = %.2f s: %.3f mm, %.5f deg\n", what.c_str(), t, position_error * 1e3, angle_error);
  EXPECT_LT(position_error, 1e-3) << what << " at t = " << t;
  EXPECT_LT(angle_error, 0.01) << what << " at t = " << t;
}

TEST(Imu, LevelAtRestReadsGravityUpAndNoRate) {
  const PoseOfTime still = [](double) { return Eigen::Isometry3d::Identity(); };
  const ImuTruth truth = TrueImuAt(still, OusterOs1ImuToSensor(), 3.0);
  EXPECT_TRUE(truth.angular_velocity.isZero(1e-12));
  EXPECT_NEAR((truth.specific_force - Eigen::Vector3d(0, 0, 9.81)).norm(), 0.0, 1e-9);
}

// Spinning about the sensor's z axis: the IMU, off the axis by the OS1's lever arm, feels the
// centripetal acceleration -w^2 r towards the axis, in its own (rotating) frame.
TEST(Imu, LeverArmAddsTheCentripetalAcceleration) {
  const double w = 2.0;
  const PoseOfTime spin = [w](double t) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(w * t, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return T;
  };
  const Eigen::Vector3d r = OusterOs1ImuToSensor().translation();
  for (const double t : {0.0, 0.7, 5.0}) {
    const ImuTruth truth = TrueImuAt(spin, OusterOs1ImuToSensor(), t);
    EXPECT_NEAR((truth.angular_velocity - Eigen::Vector3d(0, 0, w)).norm(), 0.0, 1e-7);
    const Eigen::Vector3d expected(-w * w * r.x(), -w * w * r.y(), 9.81);
    EXPECT_NEAR((truth.specific_force - expected).norm(), 0.0, 1e-5) << t;
  }
}

TEST(Imu, IntegratingTheNoiselessSignalReproducesTheTruePose) {
  const Simulator walk(*FindPreset("handheld-corridor"), Vlp16(), 1, 1);
  ExpectIntegrationReproducesTruth(walk.trajectory(), 20.0, "handheld-corridor (hand shake)");
  const Simulator robot(*FindPreset("wheeled-zigzag"), Vlp16(), 2, 1);
  ExpectIntegrationReproducesTruth(robot.trajectory(), 30.0, "wheeled-zigzag (vibration)");

  // The aggressive run at its fastest turn and through its drop (found from the signal).
  const Preset preset = *FindPreset("handheld-aggressive");
  const Simulator run(preset, Vlp16(), 1, 1);
  const PoseOfTime pose = [&](double u) { return run.trajectory().Pose(u); };
  const std::vector<ImuSample> coarse =
      SimulateImu(pose, 0.0, 0.0, preset.scans * 0.1, Noiseless(100.0), 1);
  const auto fastest = std::max_element(coarse.begin(), coarse.end(), [](const ImuSample& a, const ImuSample& b) {
    return a.angular_velocity.norm() < b.angular_velocity.norm();
  });
  const auto lightest = std::min_element(coarse.begin(), coarse.end(), [](const ImuSample& a, const ImuSample& b) {
    return a.linear_acceleration.norm() < b.linear_acceleration.norm();
  });
  double top_speed = 0.0;
  for (double t = 1.0; t < preset.scans * 0.1; t += 0.5) {
    top_speed = std::max(top_speed, TrueImuAt(pose, Eigen::Isometry3d::Identity(), t).imu_motion.velocity_world.norm());
  }
  std::printf("handheld-aggressive: fastest turn %.2f rad/s at %.2f s, lowest |f| %.2f m/s^2 at %.2f s, "
              "top speed %.2f m/s\n",
              fastest->angular_velocity.norm(), fastest->t, lightest->linear_acceleration.norm(), lightest->t,
              top_speed);
  EXPECT_GT(fastest->angular_velocity.norm(), 2.7);  // turns up to 3 rad/s, shake included
  EXPECT_LT(fastest->angular_velocity.norm(), 3.3);
  EXPECT_LT(lightest->linear_acceleration.norm(), 2.0);  // free fall: the accelerometer reads ~0
  EXPECT_GT(top_speed, 2.8);                             // running
  ExpectIntegrationReproducesTruth(run.trajectory(), fastest->t - 0.5, "handheld-aggressive (fastest turn)");
  ExpectIntegrationReproducesTruth(run.trajectory(), lightest->t - 0.3, "handheld-aggressive (drop)");
}

// White noise at the stated density (first differences remove the slow bias), the turn-on bias
// as drawn, the clock offset on every stamp, and the same samples for the same seed.
TEST(Imu, NoiseHasTheStatedDensityAndIsDeterministicPerSeed) {
  const PoseOfTime still = [](double) { return Eigen::Isometry3d::Identity(); };
  const ImuSimOptions options;  // 100 Hz, ICM-20948 noise, 3 ms clock offset
  ImuBiases bias;
  const std::vector<ImuSample> samples = SimulateImu(still, 100.0, 0.0, 300.0, options, 7, &bias);
  ASSERT_EQ(samples.size(), 30001u);
  EXPECT_DOUBLE_EQ(samples.front().t, 100.0 + options.description.time_offset);
  EXPECT_DOUBLE_EQ(samples.back().t, 400.0 + options.description.time_offset);
  Eigen::Array3d gyro_sq = Eigen::Array3d::Zero(), accel_sq = Eigen::Array3d::Zero();
  for (std::size_t k = 1; k < samples.size(); ++k) {
    gyro_sq += (samples[k].angular_velocity - samples[k - 1].angular_velocity).array().square();
    accel_sq += (samples[k].linear_acceleration - samples[k - 1].linear_acceleration).array().square();
  }
  const double n = static_cast<double>(samples.size() - 1);
  const Eigen::Array3d gyro_sigma = (gyro_sq / (2.0 * n)).sqrt(), accel_sigma = (accel_sq / (2.0 * n)).sqrt();
  const double gyro_expected = options.description.noise.gyro_noise_density * 10.0;  // * sqrt(100 Hz)
  const double accel_expected = options.description.noise.accel_noise_density * 10.0;
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(gyro_sigma[i] / gyro_expected, 1.0, 0.03) << i;
    EXPECT_NEAR(accel_sigma[i] / accel_expected, 1.0, 0.03) << i;
  }
  // The first second's mean is the turn-on bias (plus gravity) to within the white noise.
  Eigen::Vector3d gyro_mean = Eigen::Vector3d::Zero(), accel_mean = Eigen::Vector3d::Zero();
  for (int k = 0; k < 100; ++k) {
    gyro_mean += samples[k].angular_velocity / 100.0;
    accel_mean += samples[k].linear_acceleration / 100.0;
  }
  EXPECT_GT(bias.gyro.norm(), 1e-4);
  EXPECT_LT((gyro_mean - bias.gyro).norm(), 4.0 * gyro_expected / 10.0);
  EXPECT_LT((accel_mean - Eigen::Vector3d(0, 0, 9.81) - bias.accel).norm(), 4.0 * accel_expected / 10.0);

  const std::vector<ImuSample> again = SimulateImu(still, 100.0, 0.0, 2.0, options, 7);
  const std::vector<ImuSample> other = SimulateImu(still, 100.0, 0.0, 2.0, options, 8);
  for (std::size_t k = 0; k < again.size(); ++k) {
    ASSERT_EQ(again[k].angular_velocity, samples[k].angular_velocity);
    ASSERT_EQ(again[k].linear_acceleration, samples[k].linear_acceleration);
  }
  EXPECT_NE(other[5].angular_velocity, again[5].angular_velocity);
}

// The wheeled robot of the endless corridor: the fitted speed and yaw-rate scales are the drawn
// 1-2 % errors, the slip in its U-turn is the stated 0.03 rad/s per m/s^2, the noise is as
// stated, and the base frame moves only forwards (the vibration is the sensor's, not the
// wheels'). Its turn is taken at the lateral-acceleration limit, so yaw rate and lateral
// acceleration are collinear there: the scale is fitted on a run without slip, the slip on the
// residual of the drawn scale.
TEST(Wheel, ScaleSlipAndNoiseAreWhatWasDrawn) {
  const Preset preset = *FindPreset("wheeled-endless");
  const Simulator robot(preset, Vlp16(), 3, 1);
  InertialStreamOptions options;
  options.no_imu = true;
  const InertialStreams streams = SimulateInertialStreams(robot, preset.scans, options);
  ASSERT_TRUE(streams.wheel);
  EXPECT_FALSE(streams.imu);
  EXPECT_DOUBLE_EQ(streams.T_sensor_base.translation().z(), -0.8);  // on the floor under it
  const std::vector<WheelSample>& measured = *streams.wheel;
  ASSERT_EQ(measured.size(), static_cast<std::size_t>(preset.scans * 0.1 * 50.0) + 1);
  const WheelErrors drawn = streams.wheel_errors;
  for (const double scale : {drawn.speed_scale, drawn.yaw_rate_scale}) {
    EXPECT_GE(std::abs(scale - 1.0), 0.01);
    EXPECT_LE(std::abs(scale - 1.0), 0.02);
  }
  const PoseOfTime chassis = [&](double t) { return robot.trajectory().ChassisPose(t); };
  WheelSimOptions no_slip;
  no_slip.slip_yaw_per_lateral_accel = 0.0;
  const std::vector<WheelSample> without_slip =
      SimulateWheel(chassis, streams.T_sensor_base, robot.options().t0, 0.0, preset.scans * 0.1, no_slip,
                    robot.options().seed);
  ASSERT_EQ(without_slip.size(), measured.size());
  double vv = 0.0, vm = 0.0, ww = 0.0, wm = 0.0, aa = 0.0, ar = 0.0, speed_sq = 0.0;
  double max_side = 0.0, max_lateral_accel = 0.0;
  for (std::size_t k = 0; k < measured.size(); ++k) {
    const WheelSample& m = measured[k];
    const BaseTwist truth = TrueBaseTwistAt(chassis, streams.T_sensor_base, m.t - robot.options().t0);
    const double v = truth.linear.x(), w = truth.angular.z(), lateral = v * w;
    vv += v * v;
    vm += v * m.linear_velocity.x();
    speed_sq += std::pow(m.linear_velocity.x() - drawn.speed_scale * v, 2);
    ww += w * w;
    wm += w * without_slip[k].angular_velocity.z();
    aa += lateral * lateral;
    ar += lateral * (m.angular_velocity.z() - drawn.yaw_rate_scale * w);
    max_side = std::max({max_side, std::abs(truth.linear.y()), std::abs(truth.linear.z())});
    max_lateral_accel = std::max(max_lateral_accel, std::abs(lateral));
    ASSERT_EQ(m.linear_velocity.y(), 0.0);
    ASSERT_EQ(m.angular_velocity.x(), 0.0);
  }
  const double speed_noise = std::sqrt(speed_sq / static_cast<double>(measured.size()));
  std::printf("wheeled-endless s3: speed scale drawn %.4f fitted %.4f; yaw-rate scale drawn %.4f fitted %.4f, "
              "slip %.4f rad/s per m/s^2 (lateral accel up to %.2f m/s^2); speed noise %.4f m/s; base "
              "side speed <= %.1e m/s\n",
              drawn.speed_scale, vm / vv, drawn.yaw_rate_scale, wm / ww, ar / aa, max_lateral_accel, speed_noise,
              max_side);
  EXPECT_NEAR(vm / vv, drawn.speed_scale, 0.002);
  EXPECT_NEAR(wm / ww, drawn.yaw_rate_scale, 0.005);
  EXPECT_NEAR(ar / aa, WheelSimOptions{}.slip_yaw_per_lateral_accel, 0.006);
  EXPECT_NEAR(speed_noise / WheelSimOptions{}.speed_noise, 1.0, 0.05);
  EXPECT_GT(max_lateral_accel, 0.2);  // it does turn
  EXPECT_LT(max_side, 1e-3);          // the chassis moves along its own x axis only
}

TEST(InertialStreams, OnlyWheeledCarriersGetWheelOdometry) {
  const Simulator walk(*FindPreset("handheld-corridor"), Vlp16(), 1, 1);
  const InertialStreams streams = SimulateInertialStreams(walk, 20, {});
  ASSERT_TRUE(streams.imu);
  EXPECT_FALSE(streams.wheel);
  EXPECT_EQ(streams.imu->size(), 201u);  // 2 s at 100 Hz, both ends
  EXPECT_DOUBLE_EQ(streams.imu->front().t, walk.ScanStartTime(0) + 0.003);
}

}  // namespace
}  // namespace dammloam::sim
