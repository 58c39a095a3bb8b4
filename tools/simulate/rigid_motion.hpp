#pragma once
#include <Eigen/Geometry>
#include <functional>

// Velocities and accelerations of a pose given as a function of time, by central differences:
// the simulator's trajectories are exact functions of time but have no closed-form derivative.
namespace dammloam::sim {

// Drive time (seconds since the first scan, small numbers: an absolute stamp near 1.7e9 s has
// only 2.4e-7 s resolution, too coarse to difference) -> T_world_body.
using PoseOfTime = std::function<Eigen::Isometry3d(double)>;

struct RigidMotion {
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  Eigen::Vector3d angular_velocity_body = Eigen::Vector3d::Zero();  // rad/s, body frame
  Eigen::Vector3d velocity_world = Eigen::Vector3d::Zero();         // m/s
  Eigen::Vector3d acceleration_world = Eigen::Vector3d::Zero();     // m/s^2
};

// Step 1e-4 s: truncation error O(h^2) ~ 1e-8 of the motion's own scale, rounding error
// ~ 1e-5 m/s^2 on positions of a few hundred metres.
inline constexpr double kDifferenceStep = 1e-4;

RigidMotion Differentiate(const PoseOfTime& pose, double t, double h = kDifferenceStep);

}  // namespace dammloam::sim
