#include "core/odometry/ros_covariance.hpp"

namespace dammloam {

Matrix6d PoseCovarianceToRos(const Matrix6d& covariance, const Eigen::Isometry3d& T_world_sensor) {
  Matrix6d J = Matrix6d::Identity();
  J.topRightCorner<3, 3>() = -Hat(T_world_sensor.translation());
  return J * covariance * J.transpose();
}

Matrix6d TwistCovarianceToRos(const Matrix6d& motion_covariance,
                              const Eigen::Isometry3d& T_world_sensor, double dt) {
  const Eigen::Matrix3d Rt = T_world_sensor.linear().transpose();
  Matrix6d ad_inverse = Matrix6d::Zero();  // Ad(T^-1) for the [rho; phi] order
  ad_inverse.topLeftCorner<3, 3>() = Rt;
  ad_inverse.topRightCorner<3, 3>() = -Rt * Hat(T_world_sensor.translation());
  ad_inverse.bottomRightCorner<3, 3>() = Rt;
  return ad_inverse * motion_covariance * ad_inverse.transpose() / (dt * dt);
}

}  // namespace dammloam
