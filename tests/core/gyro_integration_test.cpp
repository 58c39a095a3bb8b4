// The gyroscope's rotation over an interval (issue 55): known rates against their analytic
// rotation, the extrinsic and the bias, gaps, clipped and NaN readings, the covariance; and the
// bias filter recovering a bias from rotation departures.
#include "core/inertial/gyro_integration.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>
#include <vector>

#include "core/geometry/se3.hpp"
#include "core/inertial/gyro_bias_filter.hpp"

namespace dammloam {
namespace {

constexpr double kRate = 100.0;  // Hz, the OS1's IMU

std::vector<ImuSample> Sampled(const std::function<Eigen::Vector3d(double)>& rate, double t_end,
                               double t_first = 0.0) {
  std::vector<ImuSample> samples;
  for (int k = 0; t_first + k / kRate <= t_end + 1e-12; ++k) {
    ImuSample s;
    s.t = t_first + k / kRate;
    s.angular_velocity = rate(s.t);
    samples.push_back(s);
  }
  return samples;
}

double AngleBetween(const Eigen::Matrix3d& A, const Eigen::Matrix3d& B) {
  return Eigen::AngleAxisd(A.transpose() * B).angle();
}

GyroTrack Integrate(const std::vector<ImuSample>& samples, double t0, double t1,
                    const GyroCalibration& calibration = {}) {
  return IntegrateGyro(samples, t0, t1, calibration, GyroIntegrationConfig{});
}

TEST(GyroIntegration, ConstantRateGivesItsExponentialAtAnyTimeWithin) {
  const Eigen::Vector3d w(0.3, -0.2, 1.0);
  const auto samples = Sampled([&](double) { return w; }, 2.0);
  // Ends between samples: interpolated there.
  const GyroTrack track = Integrate(samples, 0.123, 0.987);
  ASSERT_TRUE(track.covered());
  EXPECT_LT(AngleBetween(track.Rotation(), ExpSO3(w * (0.987 - 0.123))), 1e-12);
  EXPECT_LT(AngleBetween(track.At(0.5), ExpSO3(w * (0.5 - 0.123))), 1e-12);
  EXPECT_LT(AngleBetween(track.At(0.2345), ExpSO3(w * (0.2345 - 0.123))), 1e-12);
  EXPECT_LT(AngleBetween(track.At(0.0), Eigen::Matrix3d::Identity()), 1e-15);  // clamped
}

TEST(GyroIntegration, ExtrinsicRotatesAndBiasIsRemoved) {
  const Eigen::Vector3d w_imu(0.5, 0.1, -0.4), bias(0.01, -0.02, 0.005);
  const auto samples = Sampled([&](double) { return Eigen::Vector3d(w_imu + bias); }, 1.0);
  GyroCalibration calibration;
  calibration.R_sensor_imu = Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  calibration.bias = bias;
  const GyroTrack track = Integrate(samples, 0.05, 0.55, calibration);
  ASSERT_TRUE(track.covered());
  EXPECT_LT(AngleBetween(track.Rotation(), ExpSO3(calibration.R_sensor_imu * w_imu * 0.5)), 1e-12);
}

// R(t) = Rz(a sin(2 pi f t)) Rx(b t): the body rate R^T dR/dt = Rx(b t)^T (0, 0, a 2 pi f
// cos(2 pi f t)) + (b, 0, 0) turns about two axes that do not commute.
TEST(GyroIntegration, SwingAboutTwoAxesMatchesTheAnalyticRotation) {
  const double a = 0.6, f = 2.0, b = 1.5;  // a 2 Hz swing of 34 deg while rolling at 1.5 rad/s
  const double omega = 2.0 * std::numbers::pi * f;
  const auto R_of = [&](double t) {
    return Eigen::Matrix3d(Eigen::AngleAxisd(a * std::sin(omega * t), Eigen::Vector3d::UnitZ()) *
                           Eigen::AngleAxisd(b * t, Eigen::Vector3d::UnitX()));
  };
  const auto rate = [&](double t) {
    const Eigen::Matrix3d Rx = Eigen::AngleAxisd(b * t, Eigen::Vector3d::UnitX()).toRotationMatrix();
    return Eigen::Vector3d(Rx.transpose() * Eigen::Vector3d(0, 0, a * omega * std::cos(omega * t)) +
                           Eigen::Vector3d(b, 0, 0));
  };
  const auto samples = Sampled(rate, 2.0);
  for (const auto& [t0, t1] : {std::pair{0.0, 0.1}, std::pair{0.3171, 0.4171}, std::pair{0.05, 0.55},
                               std::pair{0.2, 1.2}}) {
    const GyroTrack track = Integrate(samples, t0, t1);
    ASSERT_TRUE(track.covered());
    const Eigen::Matrix3d truth = R_of(t0).transpose() * R_of(t1);
    // Trapezoid on 100 Hz samples of a 2 Hz swing: ~(h w)^2 / 12 = 1.3e-3 of its 0.6 rad.
    EXPECT_LT(AngleBetween(track.Rotation(), truth), 1e-3) << t0 << " .. " << t1;
    const double tm = 0.5 * (t0 + t1);
    EXPECT_LT(AngleBetween(track.At(tm), R_of(t0).transpose() * R_of(tm)), 1e-3) << tm;
  }
}

TEST(GyroIntegration, AGapLongerThanThreeSamplePeriodsIsNotCovered) {
  auto samples = Sampled([](double) { return Eigen::Vector3d(0.1, 0.0, 0.2); }, 2.0);
  // Samples at 0.41 .. 0.45 lost: 0.40 -> 0.46, six periods.
  std::erase_if(samples, [](const ImuSample& s) { return s.t > 0.405 && s.t < 0.455; });
  EXPECT_EQ(Integrate(samples, 0.35, 0.45).coverage(), GyroCoverage::kGap);
  EXPECT_EQ(Integrate(samples, 0.42, 0.43).coverage(), GyroCoverage::kGap);
  EXPECT_TRUE(Integrate(samples, 0.46, 0.56).covered());
  EXPECT_TRUE(Integrate(samples, 0.30, 0.40).covered());
  // Two samples lost (three periods) is still bridged.
  auto two_lost = Sampled([](double) { return Eigen::Vector3d(0.1, 0.0, 0.2); }, 2.0);
  std::erase_if(two_lost, [](const ImuSample& s) { return s.t > 0.405 && s.t < 0.425; });
  EXPECT_TRUE(Integrate(two_lost, 0.35, 0.45).covered());
}

TEST(GyroIntegration, BeyondTheStreamIsNoSamples) {
  const auto samples = Sampled([](double) { return Eigen::Vector3d::Zero(); }, 1.0, 0.5);
  EXPECT_EQ(Integrate(samples, 0.9, 1.1).coverage(), GyroCoverage::kNoSamples);
  EXPECT_EQ(Integrate(samples, 0.3, 0.6).coverage(), GyroCoverage::kNoSamples);
  EXPECT_EQ(Integrate({}, 0.6, 0.7).coverage(), GyroCoverage::kNoSamples);
  // Held by less than max_gap beyond the last sample: covered.
  EXPECT_TRUE(Integrate(samples, 0.9, 1.02).covered());
}

TEST(GyroIntegration, ClippedOrNaNReadingsAreNotCovered) {
  auto samples = Sampled([](double) { return Eigen::Vector3d(0.1, 0.0, 0.2); }, 1.0);
  samples[50].angular_velocity.z() = 2000.0 * std::numbers::pi / 180.0;  // full scale
  EXPECT_EQ(Integrate(samples, 0.45, 0.55).coverage(), GyroCoverage::kSaturated);
  EXPECT_TRUE(Integrate(samples, 0.55, 0.65).covered());
  samples[80].angular_velocity.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(Integrate(samples, 0.75, 0.85).coverage(), GyroCoverage::kNonFinite);
}

TEST(GyroIntegration, CovarianceIsNoiseTimesIntervalPlusBiasTimesIntervalSquared) {
  const auto samples = Sampled([](double) { return Eigen::Vector3d::Zero(); }, 2.0);
  GyroCalibration calibration;
  calibration.noise_density = 2.6e-4;
  calibration.bias_covariance = Eigen::Vector3d(1e-6, 4e-6, 9e-6).asDiagonal();
  const GyroTrack track = Integrate(samples, 0.2, 0.7, calibration);
  ASSERT_TRUE(track.covered());
  const double T = 0.5;
  for (int i = 0; i < 3; ++i) {
    const double expected = 2.6e-4 * 2.6e-4 * T + T * T * calibration.bias_covariance(i, i);
    EXPECT_NEAR(track.covariance()(i, i), expected, 1e-15);
  }
}

// Departures of the LiDAR's rotation from the gyro's over 0.1 s intervals, with 2e-4 rad of
// registration noise: the filter finds a 0.3 deg/s bias to within 0.02 deg/s in 300 scans
// (its uncertainty is held at 0.02 deg/s or more, so that it keeps following).
TEST(GyroBiasFilter, RecoversABiasFromRotationDepartures) {
  const Eigen::Vector3d true_bias = Eigen::Vector3d(0.3, -0.2, 0.25) * std::numbers::pi / 180.0;
  const Eigen::Matrix3d R_si = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  GyroBiasFilter filter{ImuNoise{}, GyroBiasConfig{}};
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 2e-4);
  const double dt = 0.1;
  const Eigen::Matrix3d measurement = 2e-4 * 2e-4 * Eigen::Matrix3d::Identity();
  int accepted = 0;
  for (int k = 0; k < 300; ++k) {
    filter.Propagate(dt);
    const Eigen::Vector3d error = true_bias - filter.bias();
    const Eigen::Vector3d departure =
        -dt * R_si * error + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    accepted += filter.Update(departure, measurement, dt, R_si) ? 1 : 0;
  }
  EXPECT_GT(accepted, 290);
  const double tolerance = 0.02 * std::numbers::pi / 180.0;
  EXPECT_LT((filter.bias() - true_bias).cwiseAbs().maxCoeff(), tolerance)
      << (filter.bias() * 180.0 / std::numbers::pi).transpose();
  EXPECT_LT(std::sqrt(filter.covariance().diagonal().maxCoeff()), 1.01 * tolerance);
}

TEST(GyroBiasFilter, AnOutlierMovesTheBiasLittle) {
  GyroBiasFilter filter{ImuNoise{}, GyroBiasConfig{}};
  const Eigen::Matrix3d measurement = 2e-4 * 2e-4 * Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  for (int k = 0; k < 300; ++k) filter.Update(0.1 * filter.bias(), measurement, 0.1, I);  // truth 0
  // A 2 deg slip in 0.1 s would be a 20 deg/s bias: it counts as a 4-sigma departure.
  EXPECT_FALSE(filter.Update(Eigen::Vector3d(0.035, 0, 0), measurement, 0.1, I));
  EXPECT_LT(filter.bias().norm() * 180.0 / std::numbers::pi, 0.05);
}

// Confident in a wrong bias (1 deg/s off), the filter still follows departures that say so:
// a hard gate would refuse every one of them.
TEST(GyroBiasFilter, AConfidentWrongBiasIsCorrected) {
  const double deg = std::numbers::pi / 180.0;
  GyroBiasFilter filter{ImuNoise{}, GyroBiasConfig{}};
  const Eigen::Matrix3d measurement = 2e-4 * 2e-4 * Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  for (int k = 0; k < 300; ++k) {  // learns 1 deg/s on y
    filter.Update(-0.1 * (Eigen::Vector3d(0, 1.0 * deg, 0) - filter.bias()), measurement, 0.1, I);
  }
  ASSERT_NEAR(filter.bias().y(), 1.0 * deg, 0.01 * deg);
  for (int k = 0; k < 600; ++k) {  // the truth is 0
    filter.Propagate(0.1);
    filter.Update(-0.1 * (Eigen::Vector3d::Zero() - filter.bias()), measurement, 0.1, I);
  }
  EXPECT_LT(std::abs(filter.bias().y()), 0.05 * deg);
}

}  // namespace
}  // namespace dammloam
