#include "core/inertial/gravity_estimate.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>

namespace dammloam {
namespace {
constexpr double kStandardGravity = 9.80665;  // m/s^2
}

// Over a second the walk's accelerations average out to a few tenths of a m/s^2: the mean
// specific force points against gravity, whose magnitude is known.
void GravityEstimate::Initialise() {
  const Eigen::Vector3d mean = force_sum_ / force_time_;
  if (!(mean.norm() > 0.5 * kStandardGravity)) return;  // falling, or no reading: wait
  gravity_ = -kStandardGravity * mean.normalized();
  bias_.setZero();
  P_.setZero();
  P_.topLeftCorner<3, 3>().diagonal().setConstant(config_.initial_sigma * config_.initial_sigma);
  P_.bottomRightCorner<3, 3>().diagonal().setConstant(config_.bias_sigma * config_.bias_sigma);
  initialised_ = true;
}

void GravityEstimate::Add(const Eigen::Vector3d& registered_change, const Eigen::Vector3d& integrated,
                          const Eigen::Matrix3d& bias_to_velocity, double dt,
                          const Eigen::Matrix3d& change_covariance) {
  if (!(dt > 0.0) || !registered_change.allFinite() || !integrated.allFinite()) return;
  if (!initialised_) {
    force_sum_ += integrated;
    force_time_ += dt;
    if (force_time_ >= config_.warmup) Initialise();
    return;
  }
  P_.topLeftCorner<3, 3>().diagonal().array() += config_.gravity_walk * config_.gravity_walk * dt;
  P_.bottomRightCorner<3, 3>().diagonal().array() += config_.bias_walk * config_.bias_walk * dt;
  Eigen::Matrix<double, 3, 6> H;
  H << dt * Eigen::Matrix3d::Identity(), -bias_to_velocity;
  const Eigen::Vector3d innovation = registered_change - VelocityChange(integrated, bias_to_velocity, dt);
  const Eigen::Matrix3d S = H * P_ * H.transpose() + change_covariance +
                            config_.velocity_sigma * config_.velocity_sigma * Eigen::Matrix3d::Identity();
  const Eigen::Matrix<double, 6, 3> K = P_ * H.transpose() * S.ldlt().solve(Eigen::Matrix3d::Identity());
  const Vector6 correction = K * innovation;
  if (!correction.allFinite()) return;
  gravity_ += correction.head<3>();
  bias_ += correction.tail<3>();
  P_ = (Matrix6::Identity() - K * H) * P_;
  P_ = 0.5 * (P_ + P_.transpose()).eval();
}

Eigen::Matrix3d GravityEstimate::Trusted(const Eigen::Matrix3d& bias_to_velocity, double dt) const {
  if (!initialised_ || !(dt > 0.0)) return Eigen::Matrix3d::Zero();
  Eigen::Matrix<double, 3, 6> J;
  J << Eigen::Matrix3d::Identity(), -bias_to_velocity / dt;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> error(J * P_ * J.transpose());
  Eigen::Matrix3d trusted = Eigen::Matrix3d::Zero();
  const double limit = config_.trusted_sigma * config_.trusted_sigma;
  for (int i = 0; i < 3; ++i) {
    if (error.eigenvalues()(i) < limit) {
      trusted += error.eigenvectors().col(i) * error.eigenvectors().col(i).transpose();
    }
  }
  return trusted;
}

}  // namespace dammloam
