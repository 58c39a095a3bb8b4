#include "core/inertial/gyro_bias_filter.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

namespace dammloam {

GyroBiasFilter::GyroBiasFilter(const ImuNoise& noise, const GyroBiasConfig& config)
    : noise_(noise),
      config_(config),
      bias_(config.initial_bias),
      covariance_(config.initial_sigma * config.initial_sigma * Eigen::Matrix3d::Identity()) {}

void GyroBiasFilter::Propagate(double dt) {
  if (!(dt > 0.0)) return;
  const double q = noise_.gyro_bias_random_walk;
  covariance_ += q * q * dt * Eigen::Matrix3d::Identity();
}

bool GyroBiasFilter::Update(const Eigen::Vector3d& departure,
                            const Eigen::Matrix3d& measurement_covariance, double interval,
                            const Eigen::Matrix3d& R_sensor_imu) {
  if (!config_.estimate || !(interval > 0.0) || !departure.allFinite() ||
      !measurement_covariance.allFinite()) {
    return false;
  }
  const double n = noise_.gyro_noise_density;
  const Eigen::Matrix3d H = -interval * R_sensor_imu;
  const Eigen::Matrix3d S = H * covariance_ * H.transpose() + measurement_covariance +
                            n * n * interval * Eigen::Matrix3d::Identity();
  const Eigen::LDLT<Eigen::Matrix3d> S_ldlt(S);
  if (S_ldlt.info() != Eigen::Success || !S_ldlt.isPositive()) return false;
  const double chi2 = departure.dot(S_ldlt.solve(departure));
  const bool inside = chi2 <= config_.gate_chi2;
  // Beyond the gate the departure is shortened to it (Huber).
  const double scale = inside ? 1.0 : std::sqrt(config_.gate_chi2 / chi2);
  const Eigen::Matrix3d K = S_ldlt.solve(H * covariance_).transpose();  // P H^T S^-1 (S, P symmetric)
  bias_ += K * (scale * departure);
  covariance_ = (Eigen::Matrix3d::Identity() - K * H) * covariance_;
  covariance_ = 0.5 * (covariance_ + covariance_.transpose()).eval();
  const double floor = config_.min_sigma * config_.min_sigma;
  for (int i = 0; i < 3; ++i) covariance_(i, i) = std::max(covariance_(i, i), floor);
  return inside;
}

}  // namespace dammloam
