#pragma once
// The core's covariances in the conventions of nav_msgs/Odometry, for every ROS 2 output (the
// daemon's DDS topics and dammloam-odometry --mcap).
#include <Eigen/Geometry>

#include "core/geometry/se3.hpp"

namespace dammloam {

// Pose covariance in ROS order [x y z roll pitch yaw] from the core's, whose tangent order is
// [translation; rotation] of a left (world-frame) SE(3) perturbation T = Exp(xi) * T_world_sensor.
// ROS means a perturbation of the position and small rotations about the parent's fixed X Y Z
// axes. The rotation parts agree (a left perturbation rotates about the world axes); the
// position moves by rho + phi x t, so the translation block picks up the rotation uncertainty
// lever-armed by the distance from the origin: Sigma_ros = J Sigma J^T, J = [I -[t]x; 0 I].
Matrix6d PoseCovarianceToRos(const Matrix6d& covariance, const Eigen::Isometry3d& T_world_sensor);

// Twist covariance in the sensor (child) frame: the scan-to-scan registration covariance (left
// perturbation, world frame) moved into the body frame with the inverse adjoint and divided by
// dt^2, as the velocity is that motion over dt. An estimate: the core does not filter velocity
// uncertainty.
Matrix6d TwistCovarianceToRos(const Matrix6d& motion_covariance,
                              const Eigen::Isometry3d& T_world_sensor, double dt);

}  // namespace dammloam
