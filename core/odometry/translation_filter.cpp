#include "core/odometry/translation_filter.hpp"

#include <algorithm>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

namespace dammloam {

TranslationFilter::TranslationFilter(const Config& config) : config_(config) { Reset(); }

void TranslationFilter::Reset() {
  P_.setZero();
  P_.bottomRightCorner<3, 3>() =
      config_.max_speed_sigma * config_.max_speed_sigma * Eigen::Matrix3d::Identity();
}

Eigen::Matrix3d TranslationFilter::Predict(double dt, double measured_acceleration_sigma,
                                           const Eigen::Matrix3d& measured) {
  Matrix6 F = Matrix6::Identity();
  F.topRightCorner<3, 3>() = dt * Eigen::Matrix3d::Identity();
  const double gait_dt = std::min(dt, config_.gait_time);
  const double position_sigma = config_.acceleration * gait_dt * gait_dt;
  const double speed_sigma = config_.speed_change * dt;
  Matrix6 Q = Matrix6::Zero();
  Q.topLeftCorner<3, 3>().diagonal().setConstant(position_sigma * position_sigma);
  Q.bottomRightCorner<3, 3>().diagonal().setConstant(speed_sigma * speed_sigma);
  if (measured_acceleration_sigma > 0.0) {
    const Eigen::Matrix3d unmeasured = Eigen::Matrix3d::Identity() - measured;
    const double a_position = 0.5 * measured_acceleration_sigma * dt * dt;
    const double a_speed = measured_acceleration_sigma * dt;
    Q.topLeftCorner<3, 3>() = unmeasured * Q.topLeftCorner<3, 3>() * unmeasured +
                              a_position * a_position * measured;
    Q.bottomRightCorner<3, 3>() = unmeasured * Q.bottomRightCorner<3, 3>() * unmeasured +
                                  a_speed * a_speed * measured;
  }
  P_ = F * P_ * F.transpose() + Q;
  // A blind stretch would let the velocity's uncertainty grow without end; a carrier's speed
  // does not.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> vv(P_.bottomRightCorner<3, 3>());
  const double cap = config_.max_speed_sigma * config_.max_speed_sigma;
  if (vv.eigenvalues().maxCoeff() > cap) {
    const Eigen::Vector3d clamped = vv.eigenvalues().cwiseMin(cap);
    const Eigen::Matrix3d Pvv = vv.eigenvectors() * clamped.asDiagonal() * vv.eigenvectors().transpose();
    // Keep the correlation coefficients: scale the cross terms with the velocity's sigma.
    const Eigen::Vector3d scale = (clamped.array() / vv.eigenvalues().array()).sqrt();
    const Eigen::Matrix3d S = vv.eigenvectors() * scale.asDiagonal() * vv.eigenvectors().transpose();
    P_.topRightCorner<3, 3>() = P_.topRightCorner<3, 3>() * S;
    P_.bottomLeftCorner<3, 3>() = P_.topRightCorner<3, 3>().transpose();
    P_.bottomRightCorner<3, 3>() = Pvv;
  }
  return P_.topLeftCorner<3, 3>();
}

// Kalman update with a measurement of the position only: the velocity moves by
// P_vp P_pp^-1 times the position's move, and the covariance by the information added.
Eigen::Vector3d TranslationFilter::Update(const Eigen::Vector3d& predicted_velocity,
                                          const Eigen::Vector3d& innovation,
                                          const Eigen::Matrix3d& data_information) {
  const Eigen::LDLT<Eigen::Matrix3d> Ppp(P_.topLeftCorner<3, 3>());
  const Eigen::Vector3d velocity =
      predicted_velocity + P_.bottomLeftCorner<3, 3>() * Ppp.solve(innovation);
  Matrix6 information = P_.ldlt().solve(Matrix6::Identity());
  information.topLeftCorner<3, 3>() += data_information;
  P_ = information.ldlt().solve(Matrix6::Identity());
  P_ = 0.5 * (P_ + P_.transpose()).eval();
  return velocity.allFinite() ? velocity : predicted_velocity;
}

}  // namespace dammloam
