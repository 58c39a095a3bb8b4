#include "core/preprocess/deskew.hpp"

#include <gtest/gtest.h>

#include <random>

#include "core/geometry/se3.hpp"

namespace dammloam {
namespace {

constexpr double kPeriod = 0.1;

struct MovingScan {
  ClassifiedScan scan;
  std::vector<Eigen::Vector3d> start_points;  // ground truth in the scan-start frame
  std::vector<Eigen::Vector3f> start_normals;
};

// A static scene of random points (given in the scan-start frame) sampled by a sensor moving at
// constant velocity: a point fired at time t is seen from pose ScaleMotion(T_start_end, t/T).
MovingScan SampleWhileMoving(const Eigen::Isometry3d& T_start_end, bool with_times) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coord(-20.0, 20.0);
  MovingScan out;
  const int n = 5000;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d q(coord(rng), coord(rng), coord(rng) * 0.2);
    const Eigen::Vector3f normal =
        Eigen::Vector3f(float(coord(rng)), float(coord(rng)), 5.0f).normalized();
    // Firing times in blocks of 16 (one column of a 16-beam sensor shares a time).
    const float t = static_cast<float>((i / 16) * 16) / n * static_cast<float>(kPeriod);
    const Eigen::Isometry3d T_start_t = ScaleMotion(T_start_end, t / kPeriod);
    out.start_points.push_back(q);
    out.start_normals.push_back(normal);
    out.scan.scan.points.push_back(T_start_t.inverse() * q);
    out.scan.normals.push_back(
        (T_start_t.linear().transpose() * normal.cast<double>()).cast<float>());
    if (with_times) out.scan.scan.times.push_back(t);
  }
  out.scan.labels.assign(n, PointClass::Wall);
  return out;
}

Eigen::Isometry3d Motion() {
  Vector6d xi;
  xi << 1.2, -0.3, 0.05, 0.01, -0.02, 0.15;  // 12 m/s forward, 1.5 rad/s yaw
  return ExpSE3(xi);
}

TEST(Deskew, RestoresTheStartFrameGivenTheTrueMotion) {
  MovingScan moving = SampleWhileMoving(Motion(), true);
  // Without compensation the points are off by up to the scan's motion.
  double worst_before = 0.0;
  for (std::size_t i = 0; i < moving.start_points.size(); ++i) {
    worst_before =
        std::max(worst_before, (moving.scan.scan.points[i] - moving.start_points[i]).norm());
  }
  EXPECT_GT(worst_before, 0.5);
  DeskewScan(moving.scan, Motion(), kPeriod);
  for (std::size_t i = 0; i < moving.start_points.size(); ++i) {
    ASSERT_LT((moving.scan.scan.points[i] - moving.start_points[i]).norm(), 1e-9) << "point " << i;
    ASSERT_LT((moving.scan.normals[i] - moving.start_normals[i]).norm(), 1e-6) << "normal " << i;
  }
}

TEST(Deskew, ExpressesThePointsInTheRequestedFrame) {
  MovingScan moving = SampleWhileMoving(Motion(), true);
  const Eigen::Isometry3d T_out_start =
      Eigen::Translation3d(0.4, -1.0, 0.2) * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ());
  DeskewScan(moving.scan, Motion(), kPeriod, T_out_start);
  for (std::size_t i = 0; i < moving.start_points.size(); ++i) {
    ASSERT_LT((moving.scan.scan.points[i] - T_out_start * moving.start_points[i]).norm(), 1e-9)
        << "point " << i;
    ASSERT_LT((moving.scan.normals[i] - (T_out_start.linear().cast<float>() *
                                         moving.start_normals[i])).norm(), 1e-6)
        << "normal " << i;
  }
}

TEST(Deskew, WrongMotionDoesNotRestore) {
  MovingScan moving = SampleWhileMoving(Motion(), true);
  DeskewScan(moving.scan, Eigen::Isometry3d::Identity(), kPeriod);
  double worst = 0.0;
  for (std::size_t i = 0; i < moving.start_points.size(); ++i) {
    worst = std::max(worst, (moving.scan.scan.points[i] - moving.start_points[i]).norm());
  }
  EXPECT_GT(worst, 0.5);
}

TEST(Deskew, ScansWithoutTimesAreUnchanged) {
  MovingScan moving = SampleWhileMoving(Motion(), false);
  const std::vector<Eigen::Vector3d> before = moving.scan.scan.points;
  const std::vector<Eigen::Vector3f> normals_before = moving.scan.normals;
  DeskewScan(moving.scan, Motion(), kPeriod);
  EXPECT_EQ(moving.scan.scan.points, before);
  EXPECT_EQ(moving.scan.normals, normals_before);
}

TEST(Deskew, NonPositivePeriodIsIgnored) {
  MovingScan moving = SampleWhileMoving(Motion(), true);
  const std::vector<Eigen::Vector3d> before = moving.scan.scan.points;
  DeskewScan(moving.scan, Motion(), 0.0);
  EXPECT_EQ(moving.scan.scan.points, before);
}

// A floor 1.4 m below the sensor scanned while a hand's shake turned the sensor with a constant
// angular acceleration (a scan's ends tilted against its middle): the far floor is off by
// centimetres. Turning each point back by its firing time's share must lay it flat again.
TEST(Deskew, AngularAccelerationTurnsTheBentFloorFlat) {
  const Eigen::Vector3d acceleration(3.0, -5.0, 1.0);  // rad/s^2, sensor frame
  ClassifiedScan scan;
  std::vector<double> taus;
  for (int i = 0; i < 3600; ++i) {
    const float t = static_cast<float>(i / 4) / 900.0f * static_cast<float>(kPeriod);
    const double azimuth = 2.0 * M_PI * t / kPeriod - M_PI;
    const double range = 2.0 + 0.005 * i;  // up to 20 m away
    scan.scan.points.emplace_back(range * std::cos(azimuth), range * std::sin(azimuth), -1.4);
    scan.scan.times.push_back(t);
    scan.normals.emplace_back(0.0f, 0.0f, 1.0f);
    taus.push_back(double{t} - 0.5 * kPeriod);
  }
  scan.labels.assign(scan.scan.points.size(), PointClass::Ground);
  double mean_tau_sq = 0.0;
  for (double tau : taus) mean_tau_sq += tau * tau / static_cast<double>(taus.size());
  double worst_bend = 0.0;
  for (std::size_t i = 0; i < taus.size(); ++i) {  // measured through the turned sensor
    const double curve = 0.5 * (taus[i] * taus[i] - mean_tau_sq);
    const Eigen::Matrix3d R = ExpSO3(curve * acceleration);
    scan.scan.points[i] = R.transpose() * scan.scan.points[i];
    scan.normals[i] = (R.transpose() * scan.normals[i].cast<double>()).cast<float>();
    worst_bend = std::max(worst_bend, std::abs(scan.scan.points[i].z() + 1.4));
  }
  EXPECT_GT(worst_bend, 0.02);
  TurnByAngularAcceleration(scan, acceleration, kPeriod, mean_tau_sq);
  for (std::size_t i = 0; i < taus.size(); ++i) {
    ASSERT_NEAR(scan.scan.points[i].z(), -1.4, 1e-6) << "point " << i;
    ASSERT_NEAR(scan.normals[i].z(), 1.0f, 1e-6f) << "normal " << i;
  }
}

// The fused pass must give exactly what the two passes give, point by point and normal by
// normal, to the bit: the odometry's poses are compared byte for byte between builds.
TEST(Deskew, DeskewAndTurnEqualsBothPassesToTheBit) {
  const Eigen::Vector3d acceleration(3.0, -5.0, 1.0);
  Eigen::Isometry3d T_out_start = Eigen::Isometry3d::Identity();
  T_out_start.translation() << 0.01, -0.02, 0.003;
  MovingScan moving = SampleWhileMoving(Motion(), true);
  moving.scan.normals.assign(moving.scan.scan.points.size(), Eigen::Vector3f(0.6f, 0.0f, 0.8f));
  ClassifiedScan two_passes = moving.scan;
  DeskewScan(two_passes, Motion(), kPeriod, T_out_start);
  TurnByAngularAcceleration(two_passes, acceleration, kPeriod, 0.0009);
  ClassifiedScan one_pass = moving.scan;
  DeskewAndTurn(one_pass, Motion(), kPeriod, T_out_start, acceleration, 0.0009);
  ASSERT_EQ(one_pass.scan.points.size(), two_passes.scan.points.size());
  for (std::size_t i = 0; i < one_pass.scan.points.size(); ++i) {
    ASSERT_EQ(one_pass.scan.points[i], two_passes.scan.points[i]) << "point " << i;
    ASSERT_EQ(one_pass.normals[i], two_passes.normals[i]) << "normal " << i;
  }
  EXPECT_FALSE(one_pass.scan.points[0].isApprox(moving.scan.scan.points[0], 1e-9)) << "moved";
}

}  // namespace
}  // namespace dammloam
