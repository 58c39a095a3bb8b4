#pragma once
// Localization mode (after a `relocalize` command): every registered scan is located in a
// loaded map with backend::Localizer (Scan Context + ICP until found, then tracking), exactly as
// dammloam-odometry --localize does; the odometry keeps running underneath only to deskew.
//
// Threading: Load() runs on the command thread (reading the map and building the ICP target
// take far longer than a scan); it hands the finished Localizer over through a mutex-guarded
// slot that the publish thread picks up before its next scan, so neither waits for the other.
#include <Eigen/Geometry>
#include <atomic>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "core/backend/localizer.hpp"
#include "core/odometry/odometry_result.hpp"
#include "services/dammloamd/command_stage.hpp"

namespace dammloam::daemon {

// Where a scan is in the loaded map.
struct MapPose {
  Eigen::Isometry3d T_map_sensor = Eigen::Isometry3d::Identity();
  bool localized = false;  // false: not found; the pose is odometry carried on from the last fix
};

class MapLocalization {
 public:
  explicit MapLocalization(const backend::LocalizerConfig& config = {}) : config_(config) {}

  // Command thread. Loads and checks the map; on failure the current mode is left untouched.
  CommandOutcome Load(const std::filesystem::path& dir);

  // Publish thread. nullopt while no map was loaded (mapping mode).
  std::optional<MapPose> Locate(const OdometryResult& result);

  // Any thread: a map has been loaded (the next scan is located in it).
  bool Active() const { return loaded_; }

 private:
  void TakePending();

  backend::LocalizerConfig config_;
  std::atomic<bool> loaded_{false};
  std::mutex pending_mutex_;
  std::unique_ptr<backend::Localizer> pending_;
  std::string pending_dir_;

  // Publish thread only.
  std::unique_ptr<backend::Localizer> localizer_;
  std::string map_dir_;
  // Map pose of the odometry frame at the last fix: carries the pose over scans the localizer
  // could not place, so every scan still gets one pose in the map frame.
  Eigen::Isometry3d T_map_odom_ = Eigen::Isometry3d::Identity();
  bool fixed_ = false;  // the last scan was located
};

}  // namespace dammloam::daemon
