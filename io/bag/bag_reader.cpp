#include "io/bag/bag_reader.hpp"

#include "io/bag/mcap_bag.hpp"
#include "io/bag/ros1_bag.hpp"
#include "io/bag/rosbag2_metadata.hpp"
#include "io/bag/sqlite_bag.hpp"
#include "io/io_error.hpp"

namespace dammloam::io {

bool IsBagPath(const std::filesystem::path& path) {
  if (std::filesystem::is_directory(path)) return std::filesystem::exists(path / "metadata.yaml");
  return path.extension() == ".mcap" || path.extension() == ".bag";
}

std::unique_ptr<BagReader> OpenBag(const std::filesystem::path& path,
                                   const BagReadOptions& options) {
  const McapReadOptions mcap_options{options.max_record_bytes};
  if (!std::filesystem::is_directory(path)) {
    if (!std::filesystem::is_regular_file(path)) {
      throw IoError(path.string() + ": no such file");
    }
    if (path.extension() == ".bag") return std::make_unique<Ros1Bag>(path, options);
    return std::make_unique<McapBag>(std::vector<std::filesystem::path>{path}, mcap_options);
  }
  const Rosbag2Metadata metadata = ReadRosbag2Metadata(path);
  if (metadata.storage_identifier == "sqlite3") {
    return std::make_unique<SqliteBag>(metadata, options);
  }
  if (metadata.storage_identifier == "mcap") {
    if (!metadata.compression_format.empty()) {
      throw IoError((path / "metadata.yaml").string() + ": compressed rosbag2 (" +
                    metadata.compression_format + ", mode " + metadata.compression_mode +
                    ") with mcap storage is not supported; decompress it (ros2 bag decompress)");
    }
    return std::make_unique<McapBag>(metadata.files, mcap_options);
  }
  throw IoError((path / "metadata.yaml").string() + ": storage_identifier '" +
                metadata.storage_identifier + "' is not supported (sqlite3 or mcap)");
}

std::string TopicList(const std::vector<BagTopic>& topics) {
  std::string list;
  for (const BagTopic& t : topics) {
    if (!list.empty()) list += ", ";
    list += t.name + " (" + (t.type.empty() ? "no type" : t.type);
    if (t.message_count) list += ", " + std::to_string(*t.message_count) + " messages";
    list += ")";
  }
  return list.empty() ? "no topics" : list;
}

}  // namespace dammloam::io
