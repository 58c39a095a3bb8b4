#include "core/inertial/gravity_estimate.hpp"

#include <Eigen/Cholesky>
#include <cmath>

namespace dammloam {

void GravityEstimate::Add(const Eigen::Vector3d& registered_change, const Eigen::Vector3d& integrated,
                          const Eigen::Matrix3d& bias_to_velocity, double dt) {
  if (!(dt > 0.0) || !registered_change.allFinite() || !integrated.allFinite()) return;
  Eigen::Matrix<double, 3, 6> A;
  A << dt * Eigen::Matrix3d::Identity(), -bias_to_velocity;
  const Eigen::Vector3d y = registered_change - integrated;
  const double keep = std::exp(-dt / config_.memory);
  const double w = 1.0 / (config_.velocity_sigma * config_.velocity_sigma);
  normal_ = keep * normal_ + w * A.transpose() * A;
  rhs_ = keep * rhs_ + w * A.transpose() * y;
  fitted_time_ += dt;
  Matrix6 regularised = normal_;
  regularised.bottomRightCorner<3, 3>().diagonal().array() += 1.0 / (config_.bias_sigma * config_.bias_sigma);
  // Gravity's own prior is only there to keep the system solvable on the first interval.
  regularised.topLeftCorner<3, 3>().diagonal().array() += 1e-6;
  const Vector6 x = regularised.ldlt().solve(rhs_);
  if (!x.allFinite()) return;
  gravity_ = x.head<3>();
  bias_ = x.tail<3>();
}

}  // namespace dammloam
