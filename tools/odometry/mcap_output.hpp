#pragma once
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/backend/loop_event.hpp"
#include "core/odometry/odometry_result.hpp"
#include "io/bag/mcap_writer.hpp"

namespace dammloam::tools {

// dammloam-odometry --mcap: the run's outputs as ROS 2 messages, on the daemon's topic names
// (docs/topics.md): /dammloam/odometry (nav_msgs/Odometry with covariance), /tf (odom ->
// sensor, and map -> odom from loop closure), /dammloam/labelled_cloud (PointCloud2 with a label per point) and
// /dammloam/loop_closures (a MarkerArray line between the keyframes of each accepted loop).
class McapOutput {
 public:
  // compression: "zstd" or "" (uncompressed chunks).
  McapOutput(const std::filesystem::path& file, double scan_period, const std::string& compression);
  // T_map_odom: the loop closure's correction when the scan came out (identity without).
  void AddScan(const OdometryResult& result, const Eigen::Isometry3d& T_map_odom);
  void AddLoops(const std::vector<backend::LoopEvent>& events);
  void Close() { writer_.Close(); }

  static constexpr const char* kMapFrame = "map";
  static constexpr const char* kOdomFrame = "odom";
  static constexpr const char* kSensorFrame = "lidar";

 private:
  io::McapWriter writer_;
  double scan_period_;
  std::uint16_t odometry_, tf_, cloud_, loops_;
  std::map<double, Eigen::Vector3d> positions_;  // by stamp, for loop lines
  std::int32_t loop_count_ = 0;
};

}  // namespace dammloam::tools
