// Wheel odometry's motion of the sensor over an interval (issue 55): a constant twist against
// its analytic arc, carried to a sensor mounted off the axle; gaps and missing samples; the
// covariance's size along and across the drive, straight and in a turn.
#include "core/inertial/wheel_integration.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "core/geometry/se3.hpp"

namespace dammloam {
namespace {

constexpr double kRate = 50.0;  // Hz

std::vector<WheelSample> Constant(double speed, double yaw_rate, double t_first, double t_end) {
  std::vector<WheelSample> samples;
  for (int k = 0; t_first + k / kRate <= t_end + 1e-12; ++k) {
    WheelSample s;
    s.t = t_first + k / kRate;
    s.linear_velocity = Eigen::Vector3d(speed, 0.0, 0.0);
    s.angular_velocity = Eigen::Vector3d(0.0, 0.0, yaw_rate);
    samples.push_back(s);
  }
  return samples;
}

// The base after driving a circular arc from the origin along x.
Eigen::Isometry3d Arc(double speed, double yaw_rate, double T) {
  const double theta = yaw_rate * T;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const double r = speed / yaw_rate;
  pose.translation() = Eigen::Vector3d(r * std::sin(theta), r * (1.0 - std::cos(theta)), 0.0);
  return pose;
}

// A sensor 0.5 m above the base and 0.3 m ahead of the axle, turned 90 deg (its x to the
// robot's left): it swings out in the turn, and its own frame sees the drive along -y.
Eigen::Isometry3d OffAxleMount() {
  Eigen::Isometry3d T_base_sensor = Eigen::Isometry3d::Identity();
  T_base_sensor.linear() = Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T_base_sensor.translation() = Eigen::Vector3d(0.3, 0.0, 0.5);
  return T_base_sensor.inverse();  // T_sensor_base
}

TEST(WheelIntegration, AConstantTwistDrivesItsArcAtTheSensor) {
  const double v = 1.2, w = 0.6, T = 1.5;
  const std::vector<WheelSample> samples = Constant(v, w, -0.1, T + 0.1);
  const Eigen::Isometry3d T_sensor_base = OffAxleMount();
  const WheelTrack track = IntegrateWheel(samples, 0.0, T, T_sensor_base, WheelIntegrationConfig{});
  ASSERT_TRUE(track.covered());
  const Eigen::Isometry3d expected = T_sensor_base * Arc(v, w, T) * T_sensor_base.inverse();
  EXPECT_LT((track.motion.translation() - expected.translation()).norm(), 1e-9);
  EXPECT_LT(Eigen::AngleAxisd(track.motion.linear().transpose() * expected.linear()).angle(), 1e-9);
  EXPECT_NEAR(track.distance, v * T, 1e-9);
  // The lever arm: the sensor 0.3 m ahead of the axle sweeps a wider circle than the base.
  EXPECT_GT(track.motion.translation().norm(), Arc(v, w, T).translation().norm() + 0.01);
}

TEST(WheelIntegration, AnIntervalBetweenSamplesInterpolatesTheirTwist) {
  // Speed ramps 1 -> 2 m/s over 1 s: the distance over [0.31, 0.77] is the ramp's integral.
  std::vector<WheelSample> samples;
  for (int k = -2; k <= 52; ++k) {
    WheelSample s;
    s.t = k / kRate;
    s.linear_velocity.x() = 1.0 + s.t;
    samples.push_back(s);
  }
  const WheelTrack track = IntegrateWheel(samples, 0.31, 0.77, Eigen::Isometry3d::Identity(), {});
  ASSERT_TRUE(track.covered());
  const auto distance = [](double t) { return t + 0.5 * t * t; };
  EXPECT_NEAR(track.motion.translation().x(), distance(0.77) - distance(0.31), 1e-9);
  EXPECT_NEAR(track.motion.translation().y(), 0.0, 1e-9);
}

TEST(WheelIntegration, GapsAndMissingSamplesAreNotBridged) {
  std::vector<WheelSample> samples = Constant(1.0, 0.0, 0.0, 2.0);
  const WheelIntegrationConfig config;
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  EXPECT_EQ(IntegrateWheel({}, 0.5, 0.6, I, config).coverage, WheelCoverage::kNoSamples);
  // The stream stopped before the interval ends, or starts after it begins.
  EXPECT_EQ(IntegrateWheel(samples, 1.9, 2.2, I, config).coverage, WheelCoverage::kNoSamples);
  EXPECT_EQ(IntegrateWheel(samples, -0.3, 0.1, I, config).coverage, WheelCoverage::kNoSamples);
  // A gap of 0.1 s (5 samples lost) inside the interval; one lost sample (0.04 s) is bridged.
  std::vector<WheelSample> gapped;
  for (const WheelSample& s : samples) {
    if (s.t > 1.0 && s.t < 1.1) continue;
    gapped.push_back(s);
  }
  EXPECT_EQ(IntegrateWheel(gapped, 0.95, 1.05, I, config).coverage, WheelCoverage::kGap);
  EXPECT_EQ(IntegrateWheel(gapped, 1.2, 1.4, I, config).coverage, WheelCoverage::kCovered);
  std::vector<WheelSample> one_lost = samples;
  one_lost.erase(one_lost.begin() + 60);
  const WheelTrack bridged = IntegrateWheel(one_lost, 1.1, 1.3, I, config);
  ASSERT_TRUE(bridged.covered());
  EXPECT_NEAR(bridged.motion.translation().x(), 0.2, 1e-9);
}

TEST(WheelIntegration, TheCovarianceIsTheScaleErrorAlongAndGrowsAcrossInTurns) {
  const WheelIntegrationConfig config;
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  // 1 m straight ahead in 1 s: 2 % of the distance along the drive; across it the vibration
  // and the turn's noise only.
  const WheelTrack straight = IntegrateWheel(Constant(1.0, 0.0, -0.1, 1.1), 0.0, 1.0, I, config);
  ASSERT_TRUE(straight.covered());
  const Eigen::Matrix3d& C = straight.translation_covariance;
  EXPECT_NEAR(std::sqrt(C(0, 0)), 0.02, 0.001);
  EXPECT_LT(std::sqrt(C(1, 1)), 0.005);
  EXPECT_NEAR(std::sqrt(C(2, 2)), config.noise.vibration, 1e-12);
  // The same metre on a 1 rad/s turn: the heading's scale error and the slip bend the path.
  const WheelTrack turn = IntegrateWheel(Constant(1.0, 1.0, -0.1, 1.1), 0.0, 1.0, I, config);
  ASSERT_TRUE(turn.covered());
  const Eigen::Vector3d chord = turn.motion.translation().normalized();
  const Eigen::Vector3d across = Eigen::Vector3d::UnitZ().cross(chord);
  const double sigma_across = std::sqrt(across.dot(turn.translation_covariance * across));
  EXPECT_GT(sigma_across, 4.0 * std::sqrt(C(1, 1)));
  EXPECT_GT(turn.yaw_variance, 4.0 * straight.yaw_variance);
  // Standing still: only the model's floor, never a singular covariance.
  const WheelTrack still = IntegrateWheel(Constant(0.0, 0.0, -0.1, 1.1), 0.0, 0.1, I, config);
  ASSERT_TRUE(still.covered());
  EXPECT_GT(still.translation_covariance.determinant(), 0.0);
}

}  // namespace
}  // namespace dammloam
