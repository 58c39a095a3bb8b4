#pragma once
#include <filesystem>
#include <memory>
#include <string>

#include "io/bag/scan_source.hpp"

namespace dammloam::tools {

// A bag of raw Ouster packets as ouster-ros records them (`ouster_sensor_msgs/msg/PacketMsg`,
// or the older `ouster_ros/msg/PacketMsg`: one UDP payload per message, topic
// /ouster/lidar_packets), decoded with the sensor's metadata JSON as dammloam-driver decodes
// the UDP stream. `topic` empty: the only PacketMsg topic, or the one named *lidar_packets.
// ROS 2 (CDR) and ROS 1 bags.
std::unique_ptr<io::ScanSource> OpenOusterBag(const std::filesystem::path& path,
                                              const std::string& topic,
                                              const std::filesystem::path& metadata);

// Whether the bag holds a PacketMsg topic (and no PointCloud2 is asked for): the caller then
// needs the metadata JSON.
bool HasOusterPackets(const std::filesystem::path& path);

}  // namespace dammloam::tools
