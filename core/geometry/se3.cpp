#include "core/geometry/se3.hpp"

#include <cmath>

namespace dammloam {

Eigen::Matrix3d Hat(const Eigen::Vector3d& w) {
  Eigen::Matrix3d W;
  W << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
  return W;
}

Eigen::Matrix3d ExpSO3(const Eigen::Vector3d& w) {
  const double theta = w.norm();
  if (theta < 1e-12) return Eigen::Matrix3d::Identity() + Hat(w);
  return Eigen::AngleAxisd(theta, w / theta).toRotationMatrix();
}

Eigen::Vector3d LogSO3(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

namespace {
// Left Jacobian of SO(3): maps the twist's rho to the translation.
Eigen::Matrix3d LeftJacobianSO3(const Eigen::Vector3d& w) {
  const double theta = w.norm();
  const Eigen::Matrix3d W = Hat(w);
  if (theta < 1e-8) return Eigen::Matrix3d::Identity() + 0.5 * W;
  const double t2 = theta * theta;
  return Eigen::Matrix3d::Identity() + (1.0 - std::cos(theta)) / t2 * W +
         (theta - std::sin(theta)) / (t2 * theta) * W * W;
}
}  // namespace

Eigen::Isometry3d ExpSE3(const Vector6d& xi) {
  const Eigen::Vector3d rho = xi.head<3>();
  const Eigen::Vector3d w = xi.tail<3>();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = ExpSO3(w);
  T.translation() = LeftJacobianSO3(w) * rho;
  return T;
}

Vector6d LogSE3(const Eigen::Isometry3d& T) {
  const Eigen::Vector3d w = LogSO3(T.linear());
  Vector6d xi;
  xi.head<3>() = LeftJacobianSO3(w).inverse() * T.translation();
  xi.tail<3>() = w;
  return xi;
}

Eigen::Isometry3d ScaleMotion(const Eigen::Isometry3d& delta, double s) {
  return ExpSE3(s * LogSE3(delta));
}

Eigen::Isometry3d Normalized(const Eigen::Isometry3d& T) {
  Eigen::Isometry3d out = T;
  out.linear() = Eigen::Quaterniond(T.linear()).normalized().toRotationMatrix();
  return out;
}

}  // namespace dammloam
