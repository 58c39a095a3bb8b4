#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>

// Minimal Lie-group helpers (Sophus is not packaged in Debian 12).
// Tangent vectors are ordered [translation (3); rotation (3)] everywhere in this project,
// matching the Jacobian parameter order of the registration (see registration/).
namespace dammloam {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

Eigen::Matrix3d Hat(const Eigen::Vector3d& w);
Eigen::Matrix3d ExpSO3(const Eigen::Vector3d& w);
Eigen::Vector3d LogSO3(const Eigen::Matrix3d& R);
// exp of a twist [rho; w]: rotation ExpSO3(w), translation V(w) * rho.
Eigen::Isometry3d ExpSE3(const Vector6d& xi);
Vector6d LogSE3(const Eigen::Isometry3d& T);
// Pose at fraction s in [0,1] of the relative motion delta, s * log(delta) mapped back.
Eigen::Isometry3d ScaleMotion(const Eigen::Isometry3d& delta, double s);
// Re-orthonormalises the rotation part (numerical hygiene after long products).
Eigen::Isometry3d Normalized(const Eigen::Isometry3d& T);

}  // namespace dammloam
