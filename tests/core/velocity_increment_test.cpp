// The accelerometer between two scans (issues 52, 55): a known motion's specific force, sampled
// at 100 Hz by an IMU mounted off the sensor's origin and turned against it, integrates to the
// sensor's own velocity change and displacement (gravity left in); clipped and NaN readings are
// refused; and gravity and the bias are recovered from registered velocity changes.
#include "core/inertial/velocity_increment.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "core/geometry/se3.hpp"
#include "core/inertial/gravity_estimate.hpp"

namespace dammloam {
namespace {

constexpr double kRate = 100.0;
const Eigen::Vector3d kGravity(0.0, 0.0, -9.80665);

// The sensor turns at a constant body rate while its origin follows p(t); world z is up.
struct Motion {
  Eigen::Vector3d w{0.4, -0.3, 1.2};  // rad/s, sensor frame
  Eigen::Matrix3d R0 = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 0).normalized()).toRotationMatrix();
  Eigen::Matrix3d R(double t) const { return R0 * ExpSO3(w * t); }
  Eigen::Vector3d p(double t) const { return {0.5 * t * t + t, std::sin(2.0 * t), 0.1 * std::cos(3.0 * t)}; }
  Eigen::Vector3d v(double t) const { return {t + 1.0, 2.0 * std::cos(2.0 * t), -0.3 * std::sin(3.0 * t)}; }
  Eigen::Vector3d a(double t) const { return {1.0, -4.0 * std::sin(2.0 * t), -0.9 * std::cos(3.0 * t)}; }
};

Eigen::Isometry3d Mounting() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.05, -0.08, 0.03);  // IMU origin in the sensor frame
  return T;
}

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

// What the IMU reads: the specific force at its own origin (p + R t_si) in its own frame.
std::vector<ImuSample> Readings(const Motion& m, const Eigen::Isometry3d& T_si, double t_end,
                                const Eigen::Vector3d& bias = Eigen::Vector3d::Zero()) {
  const Eigen::Matrix3d W = Skew(m.w);
  std::vector<ImuSample> samples;
  for (int k = 0; k / kRate <= t_end + 1e-12; ++k) {
    const double t = k / kRate;
    const Eigen::Vector3d a_imu = m.a(t) + m.R(t) * W * W * T_si.translation();
    ImuSample s;
    s.t = t;
    s.angular_velocity = T_si.linear().transpose() * m.w;
    s.linear_acceleration = T_si.linear().transpose() * (m.R(t).transpose() * (a_imu - kGravity)) + bias;
    samples.push_back(s);
  }
  return samples;
}

VelocityIncrement Integrate(const std::vector<ImuSample>& samples, const Eigen::Isometry3d& T_si,
                            double t0, double t1) {
  GyroCalibration calibration;
  calibration.R_sensor_imu = T_si.linear();
  const GyroTrack track = IntegrateGyro(samples, t0, t1, calibration, GyroIntegrationConfig{});
  return IntegrateSpecificForce(samples, track, T_si, 15.5 * 9.80665);
}

TEST(VelocityIncrement, AKnownMotionIntegratesToTheSensorsVelocityChangeAndDisplacement) {
  const Motion m;
  const Eigen::Isometry3d T_si = Mounting();
  const auto samples = Readings(m, T_si, 2.0);
  const double t0 = 0.537, t1 = 0.637;  // a scan interval, ends between samples
  const VelocityIncrement inc = Integrate(samples, T_si, t0, t1);
  ASSERT_TRUE(inc.covered());
  EXPECT_NEAR(inc.duration, 0.1, 1e-12);
  const double dt = t1 - t0;
  const Eigen::Matrix3d Rt0 = m.R(t0).transpose();
  const Eigen::Vector3d dv = Rt0 * (m.v(t1) - m.v(t0) - kGravity * dt);
  const Eigen::Vector3d dp = Rt0 * (m.p(t1) - m.p(t0) - m.v(t0) * dt - 0.5 * kGravity * dt * dt);
  // 100 Hz trapezoid on a force that varies at a few Hz: well under a mm/s over a scan.
  EXPECT_LT((inc.velocity - dv).norm(), 5e-4) << inc.velocity.transpose() << " vs " << dv.transpose();
  EXPECT_LT((inc.displacement - dp).norm(), 5e-5);
  // Without the lever arm the IMU's own centripetal acceleration (|w|^2 r ~ 0.17 m/s^2 here)
  // would be taken for the sensor's: 17 mm/s over the scan.
  Eigen::Isometry3d no_lever = T_si;
  no_lever.translation().setZero();
  const VelocityIncrement naive = Integrate(samples, no_lever, t0, t1);
  EXPECT_GT((naive.velocity - dv).norm(), 5e-3);
}

// Within a scan: where the sensor's origin went beyond its velocity at the scan start, at every
// moment, with gravity and the bias taken out. A bounce of 10 m/s^2 bends a 0.1 s scan by
// about a centimetre (what a constant velocity misses); the track finds it to 0.2 mm, and a
// gravity estimate 0.5 m/s^2 off moves its middle by 0.6 mm.
TEST(VelocityIncrement, TheAccelerationTrackFollowsABounceWithinAScan) {
  Motion m;
  m.w = Eigen::Vector3d(0.3, -0.2, 2.0);
  const Eigen::Isometry3d T_si = Mounting();
  const Eigen::Vector3d bias(0.08, -0.05, 0.12);
  // The readings of a running bounce: a(t) = (0, 0, -9.72 sin(18 t)).
  const Eigen::Matrix3d W = Skew(m.w);
  std::vector<ImuSample> samples;
  for (int k = 0; k <= 100; ++k) {
    const double t = k / kRate;
    const Eigen::Vector3d a(0.0, 0.0, -0.03 * 324.0 * std::sin(18.0 * t));
    const Eigen::Vector3d a_imu = a + m.R(t) * W * W * T_si.translation();
    ImuSample s;
    s.t = t;
    s.angular_velocity = T_si.linear().transpose() * m.w;
    s.linear_acceleration =
        T_si.linear().transpose() * (m.R(t).transpose() * (a_imu - kGravity)) + bias;
    samples.push_back(s);
  }
  const auto position = [](double t) {
    return Eigen::Vector3d(3.0 * t, 0.0, 0.03 * std::sin(18.0 * t));
  };
  const auto velocity = [](double t) { return Eigen::Vector3d(3.0, 0.0, 0.54 * std::cos(18.0 * t)); };
  const double t0 = 0.213, t1 = 0.313;
  GyroCalibration calibration;
  calibration.R_sensor_imu = T_si.linear();
  const GyroTrack rotation = IntegrateGyro(samples, t0, t1, calibration, GyroIntegrationConfig{});
  const Eigen::Matrix3d Rt0 = m.R(t0).transpose();
  const auto track = [&](const Eigen::Vector3d& gravity) {
    return TrackAcceleration(samples, rotation, T_si, 15.5 * 9.80665, bias, Rt0 * gravity);
  };
  const std::optional<AccelerationTrack> exact = track(kGravity);
  ASSERT_TRUE(exact.has_value());
  double worst = 0.0, worst_velocity = 0.0, bend = 0.0;
  for (double t = t0; t <= t1 + 1e-9; t += 0.0037) {
    const double tau = t - t0;
    const Eigen::Vector3d truth = Rt0 * (position(t) - position(t0) - tau * velocity(t0));
    worst = std::max(worst, (exact->At(t) - truth).norm());
    const Eigen::Vector3d gained = Rt0 * (velocity(t) - velocity(t0));
    worst_velocity = std::max(worst_velocity, (exact->VelocityAt(t) - gained).norm());
    // What a constant velocity over the scan (the chord) misses.
    const Eigen::Vector3d chord = position(t0) + (tau / (t1 - t0)) * (position(t1) - position(t0));
    bend = std::max(bend, (position(t) - chord).norm());
  }
  EXPECT_GT(bend, 0.008);
  // 100 Hz samples of a force that turns at 2.9 Hz, linear between knots: 0.12 mm and 3.7 mm/s
  // measured, against the bend's 8+ mm.
  EXPECT_LT(worst, 2e-4);
  EXPECT_LT(worst_velocity, 5e-3);
  const std::optional<AccelerationTrack> tilted = track(kGravity + Eigen::Vector3d(0.5, 0.0, 0.0));
  const double t_mid = 0.5 * (t0 + t1);
  EXPECT_LT((tilted->At(t_mid) - exact->At(t_mid)).norm(), 0.7e-3);
  // A NaN reading in the scan leaves no track.
  samples[25].linear_acceleration.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(track(kGravity).has_value());
}

TEST(VelocityIncrement, ABiasEntersThroughBiasToVelocity) {
  const Motion m;
  const Eigen::Isometry3d T_si = Mounting();
  const Eigen::Vector3d bias(0.08, -0.05, 0.12);
  const VelocityIncrement clean = Integrate(Readings(m, T_si, 1.0), T_si, 0.2, 0.3);
  const VelocityIncrement biased = Integrate(Readings(m, T_si, 1.0, bias), T_si, 0.2, 0.3);
  EXPECT_LT((biased.velocity - biased.bias_to_velocity * bias - clean.velocity).norm(), 1e-9);
}

TEST(VelocityIncrement, ClippedAndNonFiniteReadingsAreRefused) {
  const Motion m;
  const Eigen::Isometry3d T_si = Mounting();
  auto samples = Readings(m, T_si, 1.0);
  samples[25].linear_acceleration.x() = 16.0 * 9.80665;
  EXPECT_EQ(Integrate(samples, T_si, 0.2, 0.3).coverage, AccelCoverage::kSaturated);
  EXPECT_TRUE(Integrate(samples, T_si, 0.4, 0.5).covered());  // elsewhere still usable
  samples[45].linear_acceleration.z() = std::nan("");
  EXPECT_EQ(Integrate(samples, T_si, 0.4, 0.5).coverage, AccelCoverage::kNonFinite);
  // No gyro track over the interval: the force's direction through it is unknown.
  EXPECT_EQ(Integrate(samples, T_si, 1.5, 1.6).coverage, AccelCoverage::kNoRotation);
}

// A sensor that walks a curve and turns, tilted 17 deg against the world, its accelerometer
// biased by 0.16 m/s^2: after 12 s of noisy registered velocity changes the estimate predicts the
// velocity change of a scan interval to a few mm/s, where taking the raw force with a levelled
// gravity would be off by the bias, 16 mm/s. (Turning about one fixed axis, the bias along it
// and gravity are one constant; only their sum is asked for.)
TEST(GravityEstimate, PredictsAScansVelocityChangeFromNoisyRegisteredChanges) {
  const Motion m;
  const Eigen::Isometry3d T_si = Mounting();
  const Eigen::Vector3d bias(0.09, -0.06, 0.11);
  const auto samples = Readings(m, T_si, 14.0, bias);
  GravityEstimate estimate({});
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.02);
  for (double t = 0.05; t + 0.1 <= 12.0; t += 0.1) {
    const VelocityIncrement inc = Integrate(samples, T_si, t, t + 0.1);
    ASSERT_TRUE(inc.covered());
    // Drawn in sequence: the order of a constructor's arguments is unspecified, and a release
    // and a sanitizer build gave the axes different draws.
    Eigen::Vector3d error;
    for (int i = 0; i < 3; ++i) error(i) = noise(rng);
    const Eigen::Vector3d measured = m.v(t + 0.1) - m.v(t) + error;
    estimate.Add(measured, m.R(t) * inc.velocity, m.R(t) * inc.bias_to_velocity, 0.1);
    if (t < 0.9) {
      EXPECT_FALSE(estimate.ready()) << t;
    }
  }
  ASSERT_TRUE(estimate.ready());
  double worst = 0.0, naive = 0.0;
  for (double t = 12.0; t + 0.1 <= 13.9; t += 0.1) {
    const VelocityIncrement inc = Integrate(samples, T_si, t, t + 0.1);
    const Eigen::Vector3d predicted =
        estimate.VelocityChange(m.R(t) * inc.velocity, m.R(t) * inc.bias_to_velocity, 0.1);
    const Eigen::Vector3d truth = m.v(t + 0.1) - m.v(t);
    worst = std::max(worst, (predicted - truth).norm());
    naive = std::max(naive, (m.R(t) * inc.velocity + kGravity * 0.1 - truth).norm());
  }
  std::printf("worst velocity change error: estimate %.5f m/s, true gravity without bias %.5f m/s\n",
              worst, naive);
  // 2 cm/s noise on each of 119 changes leaves gravity known to ~0.018 m/s^2 per axis, ~3 mm/s
  // over a scan interval; the worst of 19 intervals stays under 8 mm/s (4.0 and 6.1 were seen
  // with two noise draws), half of what the bias alone costs.
  EXPECT_LT(worst, 0.008);
  EXPECT_GT(naive, 0.012);
  const Eigen::Matrix3d B = m.R(12.0) * Integrate(samples, T_si, 12.0, 12.1).bias_to_velocity;
  EXPECT_TRUE(estimate.Trusted(B, 0.1).isApprox(Eigen::Matrix3d::Identity(), 1e-9));
}

// The axis of a featureless corridor: the registrations never observe x, so what they report
// there is the prediction's own. The estimate must not learn from it, and must not be trusted
// there; the observed directions are learned as before.
TEST(GravityEstimate, AnUnobservedDirectionIsNeitherLearnedNorTrusted) {
  const Motion m;
  const Eigen::Isometry3d T_si = Mounting();
  const auto samples = Readings(m, T_si, 8.0);
  GravityEstimate estimate({});
  // The scans measured y and z to 2 cm/s, x not at all.
  const Eigen::Matrix3d measured = Eigen::Vector3d(1e6, 4e-4, 4e-4).asDiagonal();
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  for (double t = 0.05; t + 0.1 <= 8.0; t += 0.1) {
    const VelocityIncrement inc = Integrate(samples, T_si, t, t + 0.1);
    // Along x the "registered" change is wildly wrong: 3 m/s^2 of made-up acceleration.
    const Eigen::Vector3d reported = m.v(t + 0.1) - m.v(t) + Eigen::Vector3d(0.3, 0.0, 0.0);
    const bool was_ready = estimate.ready();
    estimate.Add(reported, m.R(t) * inc.velocity, m.R(t) * inc.bias_to_velocity, 0.1, measured);
    if (!was_ready && estimate.ready()) first = estimate.gravity();
  }
  ASSERT_TRUE(estimate.ready());
  // x still holds the first guess (the mean force over the first second) to within what the
  // observed directions' correlations move it, far from the 3 m/s^2 made up there.
  EXPECT_LT(std::abs(estimate.gravity().x() - first.x()), 0.5) << estimate.gravity().transpose();
  const Eigen::Matrix3d B = m.R(7.9) * Integrate(samples, T_si, 7.9, 8.0).bias_to_velocity;
  const Eigen::Matrix3d trusted = estimate.Trusted(B, 0.1);
  EXPECT_LT((trusted * Eigen::Vector3d::UnitX()).norm(), 0.5) << trusted;
  EXPECT_GT((trusted * Eigen::Vector3d::UnitZ()).norm(), 0.5) << trusted;
}

}  // namespace
}  // namespace dammloam
