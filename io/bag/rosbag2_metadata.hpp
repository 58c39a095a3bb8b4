#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "io/bag/bag_reader.hpp"

namespace dammloam::io {

// What metadata.yaml (rosbag2_bagfile_information) says about a rosbag2 directory.
struct Rosbag2Metadata {
  int version = 0;
  std::string storage_identifier;            // sqlite3 or mcap
  std::vector<std::filesystem::path> files;  // relative_file_paths, resolved against the dir
  std::vector<BagTopic> topics;              // topics_with_message_count
  std::string compression_format;            // "" or zstd
  std::string compression_mode;              // "", FILE or MESSAGE
};

// Throws IoError naming metadata.yaml and the key for a missing or malformed entry.
Rosbag2Metadata ReadRosbag2Metadata(const std::filesystem::path& dir);

}  // namespace dammloam::io
