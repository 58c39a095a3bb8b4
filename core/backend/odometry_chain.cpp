#include "core/backend/odometry_chain.hpp"

namespace dammloam::backend {

OdometryChain ComposeOdometryChain(const std::vector<Keyframe>& keyframes, std::uint32_t from,
                                   std::uint32_t to, const ChainNoise& noise) {
  OdometryChain chain;
  const Eigen::Isometry3d T_world_from_inv = keyframes[from].T_world_sensor_odom.inverse();
  Eigen::Isometry3d T_from_prev = Eigen::Isometry3d::Identity();
  Vector6d heading_bias_jacobian = Vector6d::Zero();  // end error per rad/m of heading bias
  for (std::uint32_t k = from + 1; k <= to; ++k) {
    const Eigen::Isometry3d T_prev_k =
        keyframes[k - 1].T_world_sensor_odom.inverse() * keyframes[k].T_world_sensor_odom;
    Matrix6d edge = keyframes[k].edge_covariance;
    edge.diagonal().head<3>().array() += noise.translation_sigma * noise.translation_sigma;
    edge.diagonal().tail<3>().array() += noise.rotation_sigma * noise.rotation_sigma;
    // T_from_k = T_from_prev * T_prev_k: a right rotation error a of T_from_prev moves the
    // end by -R [t_prev_k]x a and turns it by R_prev_k^T a; the edge's own error enters
    // rotated into `from`'s frame.
    Matrix6d J_chain = Matrix6d::Zero();
    J_chain.topLeftCorner<3, 3>().setIdentity();
    J_chain.topRightCorner<3, 3>() = -T_from_prev.rotation() * Hat(T_prev_k.translation());
    J_chain.bottomRightCorner<3, 3>() = T_prev_k.rotation().transpose();
    Matrix6d J_edge = Matrix6d::Identity();
    J_edge.topLeftCorner<3, 3>() = T_from_prev.rotation();
    chain.covariance = J_chain * chain.covariance * J_chain.transpose() +
                       J_edge * edge * J_edge.transpose();
    // The bias turns this edge by its length about the vertical, seen in the edge's end frame.
    const Eigen::Vector3d vertical =
        keyframes[k].T_world_sensor_odom.rotation().transpose() * Eigen::Vector3d::UnitZ();
    heading_bias_jacobian = J_chain * heading_bias_jacobian;
    heading_bias_jacobian.tail<3>() += T_prev_k.translation().norm() * vertical;
    T_from_prev = T_from_prev * T_prev_k;
  }
  chain.covariance += noise.heading_drift_per_metre * noise.heading_drift_per_metre *
                      heading_bias_jacobian * heading_bias_jacobian.transpose();
  chain.T_from_to = T_world_from_inv * keyframes[to].T_world_sensor_odom;
  return chain;
}

double ConsistencyChi2(const OdometryChain& odometry, const Eigen::Isometry3d& T_measured,
                       const Matrix6d& measured_covariance) {
  const Eigen::Vector3d e = T_measured.translation() - odometry.T_from_to.translation();
  const Eigen::Matrix3d S = (odometry.covariance + measured_covariance).topLeftCorner<3, 3>();
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(0.5 * (S + S.transpose()));
  return e.dot(ldlt.solve(e));
}

}  // namespace dammloam::backend
