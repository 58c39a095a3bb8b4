#pragma once
#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "core/cloud/point_cloud2.hpp"
#include "io/bag/bag_reader.hpp"

namespace dammloam::io {

inline constexpr const char* kPointCloud2Type = "sensor_msgs/msg/PointCloud2";

// Recorded clouds are checked like the daemon's ROS 2 input (same field layouts, stamps at
// the start or the end of the sweep) but without its per-message size limits.
CloudLimits RecordedCloudLimits();

struct BagScanOptions {
  std::string topic;  // empty: the bag's only PointCloud2 topic
  CloudLimits limits = RecordedCloudLimits();
};

// The sensor_msgs/msg/PointCloud2 messages of one topic of a bag, as scans, streamed.
class BagScans {
 public:
  // Throws IoError when the bag cannot be read, the topic is missing or not a PointCloud2, or
  // no topic was named and the bag has none or several PointCloud2 topics (the message lists
  // the topics).
  BagScans(const std::filesystem::path& path, const BagScanOptions& options);

  const BagTopic& topic() const { return topic_; }
  // The next scan; t_start is the stamp to the nanosecond (StampSeconds), moved to the first
  // point when the stamp ends the sweep. Clouds without a valid point are skipped and counted;
  // any other problem is an IoError naming the file, the message and its offset.
  std::optional<Scan> Next();
  std::size_t skipped_clouds() const { return skipped_; }
  // height x width of the last cloud read (before no-returns were dropped).
  std::uint64_t last_cloud_points() const { return last_cloud_points_; }
  std::uint32_t last_cloud_height() const { return last_cloud_height_; }

 private:
  std::filesystem::path path_;
  BagScanOptions options_;
  std::unique_ptr<BagReader> bag_;
  BagTopic topic_;
  BagMessage message_;
  bool ros1_ = false;  // a ROS 1 bag: the ROS 1 serialisation, not CDR
  std::size_t skipped_ = 0;
  std::uint64_t last_cloud_points_ = 0;
  std::uint32_t last_cloud_height_ = 0;
};

}  // namespace dammloam::io
