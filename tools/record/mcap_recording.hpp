#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>

#include "dammloam.h"
#include "io/bag/mcap_writer.hpp"

namespace dammloam::tools {

// dammloam-record --mcap: what dammloamd publishes, as ROS 2 messages with ros2msg schemas, on
// the names dammloam-odometry --mcap uses, so Foxglove, Lichtblick and `ros2 bag play` open
// either: /dammloam/odometry (nav_msgs/Odometry: the daemon's frames, pose covariance in ROS
// order, twist in the sensor frame with unknown (zero) covariance), /tf (map frame -> sensor),
// /dammloam/labelled_cloud (PointCloud2 x y z normal label, sensor frame), /dammloam/loop_closures
// (a MarkerArray line per accepted loop, between the poses recorded at its two stamps) and
// /dammloam/status (std_msgs/String: the JSON line --events writes).
class McapRecording {
 public:
  explicit McapRecording(const std::filesystem::path& file);
  void AddOdometry(const dammloam_msg_Odometry& m);
  // False (with the reason in *error) when the cloud does not decode.
  bool AddLabelledCloud(const dammloam_msg_LabelledCloud& m, std::string* error);
  void AddLoop(const dammloam_msg_LoopClosure& m);
  void AddStatus(const dammloam_msg_Time& stamp, const std::string& json);
  void Close() { writer_.Close(); }

 private:
  const Eigen::Vector3d* PositionAt(std::uint64_t t) const;

  io::McapWriter writer_;
  std::uint16_t odometry_, tf_, cloud_, loops_, status_;
  std::map<std::uint64_t, Eigen::Vector3d> positions_;  // by stamp (ns), for loop lines
  std::string map_frame_ = "map";
  std::int32_t loop_count_ = 0;
};

}  // namespace dammloam::tools
