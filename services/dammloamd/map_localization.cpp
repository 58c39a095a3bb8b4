#include "services/dammloamd/map_localization.hpp"

#include <spdlog/spdlog.h>

#include "core/geometry/se3.hpp"
#include "io/mapstore/map_store.hpp"

namespace dammloam::daemon {

CommandOutcome MapLocalization::Load(const std::filesystem::path& dir) {
  if (dir.empty()) return {false, "no map directory given"};
  std::unique_ptr<backend::Localizer> localizer;
  std::size_t keyframes = 0;
  try {
    const backend::MapData map = mapstore::LoadMap(dir);  // io::IoError names file and problem
    if (map.keyframes.empty() || map.global_points.empty()) {
      return {false, dir.string() + ": the map has no keyframes or no points"};
    }
    keyframes = map.keyframes.size();
    localizer = std::make_unique<backend::Localizer>(map, config_);
  } catch (const std::exception& e) {
    return {false, std::string("cannot load the map: ") + e.what()};
  }
  const std::size_t points = localizer->NumMapPoints();
  {
    std::lock_guard lock(pending_mutex_);
    pending_ = std::move(localizer);
    pending_dir_ = dir.string();
  }
  loaded_ = true;
  return {true, "loaded " + dir.string() + " (" + std::to_string(keyframes) + " keyframes, " +
                    std::to_string(points) + " points): localization mode, the next scans are "
                    "located in this map"};
}

void MapLocalization::TakePending() {
  std::lock_guard lock(pending_mutex_);
  if (!pending_) return;
  localizer_ = std::move(pending_);
  map_dir_ = std::move(pending_dir_);
  // A new map is a new frame: nothing known so far carries over.
  T_map_odom_ = Eigen::Isometry3d::Identity();
  fixed_ = false;
}

std::optional<MapPose> MapLocalization::Locate(const OdometryResult& r) {
  TakePending();
  if (!localizer_) return std::nullopt;
  std::optional<backend::LocalizationResult> found;
  if (Registered(r.status) && !r.deskewed_points.empty()) {
    found = localizer_->Localize(r.deskewed_points);
  }
  if (!found) {
    if (fixed_) {
      spdlog::warn("scan {} not located in map {}: odometry carries the pose until relocalized",
                   r.scan_index, map_dir_);
    }
    fixed_ = false;
    return MapPose{Normalized(T_map_odom_ * r.T_world_sensor), false};
  }
  if (!fixed_) {
    spdlog::info("scan {} located in map {} (inlier ratio {:.2f}, rmse {:.3f} m)", r.scan_index,
                 map_dir_, found->inlier_ratio, found->rmse);
  }
  fixed_ = true;
  T_map_odom_ = Normalized(found->T_map_sensor * r.T_world_sensor.inverse());
  return MapPose{found->T_map_sensor, true};
}

}  // namespace dammloam::daemon
