#include "core/backend/localizer.hpp"

#include "core/geometry/se3.hpp"

namespace dammloam::backend {

Localizer::Localizer(const MapData& map, const LocalizerConfig& config)
    : config_(config),
      scan_context_(map.scan_context),
      database_(ScanContextDatabaseConfig{0, config.num_candidates, 1,
                                          config.max_scan_context_distance}),
      target_(map.global_points, config.normal_neighbours) {
  for (const Keyframe& kf : map.keyframes) {
    keyframe_poses_.push_back(kf.T_world_sensor);
    // Saved descriptors are used as they are; recompute when a keyframe carries none.
    database_.Add(kf.descriptor.empty() ? MakeScanContext(kf.points, scan_context_)
                                        : kf.descriptor);
  }
}

std::optional<LocalizationResult> Localizer::Relocalize(
    const std::vector<Eigen::Vector3d>& points) const {
  if (database_.size() == 0 || target_.size() == 0) return std::nullopt;
  const ScanContext descriptor = MakeScanContext(points, scan_context_);
  const std::vector<Eigen::Vector3d> source = VoxelDownsample(points, config_.scan_voxel_size);
  std::optional<LocalizationResult> best;
  int registrations = 0;
  for (const ScanContextCandidate& c :
       database_.Query(descriptor, 0, config_.max_scan_context_distance)) {
    if (registrations++ >= config_.max_registrations) break;
    Eigen::Isometry3d T_kf_sensor = Eigen::Isometry3d::Identity();
    T_kf_sensor.linear() =
        Eigen::AngleAxisd(c.match.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const IcpResult r = AlignPointToPlane(source, target_, keyframe_poses_[c.id] * T_kf_sensor,
                                          config_.relocalize_icp);
    const bool good = r.inlier_ratio >= config_.relocalize_min_inlier_ratio &&
                      r.rmse <= config_.relocalize_max_rmse;
    if (!good || (best && r.inlier_ratio <= best->inlier_ratio)) continue;
    best = LocalizationResult{r.T_target_source, r.inlier_ratio, r.rmse, c.id, c.match.distance};
  }
  return best;
}

std::optional<LocalizationResult> Localizer::Track(
    const std::vector<Eigen::Vector3d>& points,
    const Eigen::Isometry3d& T_map_sensor_predicted) const {
  if (target_.size() == 0) return std::nullopt;
  const std::vector<Eigen::Vector3d> source = VoxelDownsample(points, config_.scan_voxel_size);
  const IcpResult r = AlignPointToPlane(source, target_, T_map_sensor_predicted,
                                        config_.track_icp);
  if (r.inlier_ratio < config_.track_min_inlier_ratio || r.rmse > config_.track_max_rmse) {
    return std::nullopt;
  }
  return LocalizationResult{r.T_target_source, r.inlier_ratio, r.rmse, 0, 0.0};
}

std::optional<LocalizationResult> Localizer::Localize(const std::vector<Eigen::Vector3d>& points) {
  std::optional<LocalizationResult> result;
  if (last_) result = Track(points, *last_ * velocity_);
  const bool tracked = result.has_value();
  if (!result) result = Relocalize(points);
  if (!result) {
    Reset();
    return std::nullopt;
  }
  velocity_ = tracked ? Normalized(last_->inverse() * result->T_map_sensor)
                      : Eigen::Isometry3d::Identity();
  last_ = result->T_map_sensor;
  return result;
}

}  // namespace dammloam::backend
