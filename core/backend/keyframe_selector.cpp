#include "core/backend/keyframe_selector.hpp"

#include "core/geometry/se3.hpp"

namespace dammloam::backend {

bool KeyframeSelector::Consider(const Eigen::Isometry3d& T_world_sensor) {
  if (last_keyframe_) {
    const Eigen::Isometry3d delta = last_keyframe_->inverse() * T_world_sensor;
    const double distance = delta.translation().norm();
    const double rotation = LogSO3(delta.rotation()).norm();
    if (distance < config_.min_distance && rotation < config_.min_rotation_rad) return false;
  }
  last_keyframe_ = T_world_sensor;
  return true;
}

}  // namespace dammloam::backend
