#include "tools/simulate/rigid_motion.hpp"

namespace dammloam::sim {

RigidMotion Differentiate(const PoseOfTime& pose, double t, double h) {
  const Eigen::Isometry3d before = pose(t - h), now = pose(t), after = pose(t + h);
  RigidMotion m;
  m.T_world_body = now;
  // R(t-h)^T R(t+h) = Exp(2h w) to second order: the body rate at t.
  const Eigen::AngleAxisd turn(Eigen::Matrix3d(before.linear().transpose() * after.linear()));
  m.angular_velocity_body = turn.angle() * turn.axis() / (2.0 * h);
  m.velocity_world = (after.translation() - before.translation()) / (2.0 * h);
  m.acceleration_world =
      (after.translation() - 2.0 * now.translation() + before.translation()) / (h * h);
  return m;
}

}  // namespace dammloam::sim
