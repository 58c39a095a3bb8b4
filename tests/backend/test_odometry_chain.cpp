// The odometry chain's covariance against sampled chains, and the consistency test on it.
#include <gtest/gtest.h>

#include <random>

#include "core/backend/odometry_chain.hpp"

namespace dammloam::backend {
namespace {

// A quarter circle of radius 20 m in 40 keyframes, each edge with the same covariance.
std::vector<Keyframe> QuarterCircle(const Matrix6d& edge_covariance) {
  std::vector<Keyframe> keyframes(41);
  for (int k = 0; k <= 40; ++k) {
    const double a = 0.5 * 3.14159265358979 * k / 40.0;
    Keyframe& kf = keyframes[static_cast<std::size_t>(k)];
    kf.id = static_cast<std::uint32_t>(k);
    kf.T_world_sensor_odom.linear() = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    kf.T_world_sensor_odom.translation() = Eigen::Vector3d(20.0 * std::sin(a), 20.0 - 20.0 * std::cos(a), 0.0);
    kf.edge_covariance = edge_covariance;
  }
  return keyframes;
}

// Composing sampled edges (translation added in the edge's frame, rotation right-multiplied,
// as the pose graph's edge error reads) and a heading-rate bias shared by all of them spreads the
// end pose as the first-order covariance says.
TEST(OdometryChain, CovarianceMatchesSampledChains) {
  Vector6d sigma;
  sigma << 0.01, 0.01, 0.02, 0.0005, 0.0005, 0.002;
  const Matrix6d edge = sigma.cwiseAbs2().asDiagonal();
  const std::vector<Keyframe> keyframes = QuarterCircle(edge);
  const double heading_drift = 2e-4;  // rad/m
  const OdometryChain chain = ComposeOdometryChain(keyframes, 0, 40, {0.0, 0.0, heading_drift});

  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  const int samples = 4000;
  std::vector<Vector6d> errors;
  Vector6d mean = Vector6d::Zero();
  for (int s = 0; s < samples; ++s) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    const double bias = heading_drift * normal(rng);  // one per chain: every edge turns alike
    for (int k = 1; k <= 40; ++k) {
      Eigen::Isometry3d step = keyframes[k - 1].T_world_sensor_odom.inverse() *
                               keyframes[k].T_world_sensor_odom;
      Vector6d n;
      for (int i = 0; i < 6; ++i) n(i) = sigma(i) * normal(rng);
      const double length = step.translation().norm();
      step.translation() += n.head<3>();
      step.linear() = step.linear() * ExpSO3(n.tail<3>() + bias * length * Eigen::Vector3d::UnitZ());
      T = T * step;
    }
    Vector6d e;
    e.head<3>() = T.translation() - chain.T_from_to.translation();
    e.tail<3>() = LogSO3(chain.T_from_to.rotation().transpose() * T.rotation());
    errors.push_back(e);
    mean += e / samples;
  }
  Matrix6d sampled = Matrix6d::Zero();
  for (const Vector6d& e : errors) sampled += (e - mean) * (e - mean).transpose() / (samples - 1);

  // The heading's uncertainty reaches the end as position: far more than the edges' own 1-2 cm.
  EXPECT_GT(std::sqrt(chain.covariance(0, 0)), 2.0 * std::sqrt(40.0) * 0.01);
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(std::sqrt(sampled(i, i)), std::sqrt(chain.covariance(i, i)),
                0.06 * std::sqrt(chain.covariance(i, i)))
        << "component " << i;
  }
  // x and y are correlated through the heading: the sign and size of that agree too.
  const double rho_chain = chain.covariance(0, 1) / std::sqrt(chain.covariance(0, 0) * chain.covariance(1, 1));
  const double rho_sampled = sampled(0, 1) / std::sqrt(sampled(0, 0) * sampled(1, 1));
  EXPECT_NEAR(rho_sampled, rho_chain, 0.05);
}

TEST(OdometryChain, FloorsAddToEveryEdge) {
  const std::vector<Keyframe> keyframes = QuarterCircle(Matrix6d::Zero());
  const OdometryChain unfloored = ComposeOdometryChain(keyframes, 0, 40, {});
  EXPECT_NEAR(unfloored.covariance.norm(), 0.0, 1e-15);
  const OdometryChain floored = ComposeOdometryChain(keyframes, 10, 20, {0.01, 0.0, 0.0});
  // Ten edges of 1 cm each: 10 * 1e-4 per axis, no rotation.
  EXPECT_NEAR(floored.covariance(2, 2), 10 * 1e-4, 1e-12);
  EXPECT_NEAR((floored.covariance.bottomRightCorner<3, 3>().norm()), 0.0, 1e-15);
}

// A look-alike place one storey below what odometry says is far outside both uncertainties; the
// same place with the chain's typical drift is not.
TEST(OdometryChain, ConsistencyChi2SeparatesAStoreyFromDrift) {
  OdometryChain odometry;
  odometry.T_from_to.translation() = Eigen::Vector3d(0.3, -0.2, 2.1);
  odometry.covariance = Matrix6d::Identity() * 1e-6;
  odometry.covariance.diagonal().head<3>() = Eigen::Vector3d(0.1, 0.1, 0.4).cwiseAbs2();
  Matrix6d loop = Matrix6d::Identity() * 1e-4;
  loop(0, 0) = 1e4;  // a corridor loop: free along its axis

  EXPECT_NEAR(ConsistencyChi2(odometry, odometry.T_from_to, loop), 0.0, 1e-12);
  Eigen::Isometry3d same_floor = odometry.T_from_to;
  same_floor.translation().z() -= 0.4;  // one sigma of vertical drift
  EXPECT_NEAR(ConsistencyChi2(odometry, same_floor, loop), 0.4 * 0.4 / (0.16 + 1e-4), 1e-6);
  Eigen::Isometry3d floor_below = odometry.T_from_to;
  floor_below.translation().z() = 0.0;
  floor_below.translation().x() += 50.0;  // along the free axis: costs almost nothing
  const double chi2 = ConsistencyChi2(odometry, floor_below, loop);
  EXPECT_GT(chi2, 16.3);  // the default bound
  EXPECT_LT(chi2, 2.1 * 2.1 / 0.16 + 1.0);
}

}  // namespace
}  // namespace dammloam::backend
