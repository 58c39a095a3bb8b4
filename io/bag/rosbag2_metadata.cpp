#include "io/bag/rosbag2_metadata.hpp"

#include <yaml-cpp/yaml.h>

#include "io/io_error.hpp"

namespace dammloam::io {
namespace {

template <typename T>
T Get(const YAML::Node& node, const char* key, const std::string& where, T fallback,
      bool required) {
  const YAML::Node value = node[key];
  if (!value) {
    if (required) throw IoError(where + ": missing key '" + key + "'");
    return fallback;
  }
  try {
    return value.as<T>();
  } catch (const YAML::Exception&) {
    throw IoError(where + ": key '" + key + "' has the wrong type");
  }
}

}  // namespace

Rosbag2Metadata ReadRosbag2Metadata(const std::filesystem::path& dir) {
  const std::filesystem::path file = dir / "metadata.yaml";
  const std::string where = file.string();
  YAML::Node root;
  try {
    root = YAML::LoadFile(file.string());
  } catch (const YAML::Exception& e) {
    throw IoError(where + ": " + e.what());
  }
  const YAML::Node info = root["rosbag2_bagfile_information"];
  if (!info || !info.IsMap()) {
    throw IoError(where + ": no 'rosbag2_bagfile_information' map (not rosbag2 metadata)");
  }
  Rosbag2Metadata meta;
  meta.version = Get<int>(info, "version", where, 0, false);
  meta.storage_identifier = Get<std::string>(info, "storage_identifier", where, "", true);
  meta.compression_format = Get<std::string>(info, "compression_format", where, "", false);
  meta.compression_mode = Get<std::string>(info, "compression_mode", where, "", false);
  const YAML::Node files = info["relative_file_paths"];
  if (!files || !files.IsSequence() || files.size() == 0) {
    throw IoError(where + ": 'relative_file_paths' must list the bag's files");
  }
  for (const auto& f : files) {
    if (!f.IsScalar()) throw IoError(where + ": 'relative_file_paths' holds a non-string entry");
    // rosbag2 before Foxy wrote paths that include the bag directory's name.
    std::filesystem::path path = dir / f.as<std::string>();
    if (!std::filesystem::exists(path)) path = dir / std::filesystem::path(f.as<std::string>()).filename();
    meta.files.push_back(path);
  }
  const YAML::Node topics = info["topics_with_message_count"];
  if (topics && !topics.IsSequence()) {
    throw IoError(where + ": 'topics_with_message_count' is not a list");
  }
  for (std::size_t i = 0; topics && i < topics.size(); ++i) {
    const std::string entry = where + ": topics_with_message_count[" + std::to_string(i) + "]";
    const YAML::Node topic = topics[i]["topic_metadata"];
    if (!topic || !topic.IsMap()) throw IoError(entry + ": missing 'topic_metadata'");
    BagTopic t;
    t.name = Get<std::string>(topic, "name", entry, "", true);
    t.type = Get<std::string>(topic, "type", entry, "", true);
    t.serialization_format = Get<std::string>(topic, "serialization_format", entry, "", false);
    if (topics[i]["message_count"]) {
      t.message_count = Get<std::uint64_t>(topics[i], "message_count", entry, 0, true);
    }
    meta.topics.push_back(std::move(t));
  }
  return meta;
}

}  // namespace dammloam::io
