#pragma once
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "io/io_error.hpp"

namespace dammloam::io {

struct BagTopic {
  std::string name;                  // e.g. /points
  std::string type;                  // e.g. sensor_msgs/msg/PointCloud2
  std::string serialization_format;  // e.g. cdr
  std::optional<std::uint64_t> message_count;
};

// One recorded message; data is valid until the next Next().
struct BagMessage {
  std::uint64_t log_time = 0;  // ns, when it was recorded
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
  std::uint64_t data_offset = 0;  // where data[0] lies (file, or decompressed chunk)
  std::string where;              // "<file>: Message record at byte N" / "<db3>: message id N"
};

// The recordings users have: a rosbag2 directory (metadata.yaml; storage sqlite3 or mcap), a
// single .mcap file or a ROS 1 .bag (format 2.0). Messages of one topic come in recorded order, streamed.
class BagReader {
 public:
  virtual ~BagReader() = default;
  virtual const std::vector<BagTopic>& topics() const = 0;
  // Restricts Next() to `topic` (must be one of topics()) and starts from the first message.
  virtual void Select(const std::string& topic) = 0;
  virtual bool Next(BagMessage& out) = 0;
};

struct BagReadOptions {
  std::uint64_t max_record_bytes = 1ull << 30;  // MCAP records and SQLite blobs larger: corrupt
};

// A rosbag2 directory (holds metadata.yaml), an .mcap file or a ROS 1 .bag file.
bool IsBagPath(const std::filesystem::path& path);
// Throws IoError naming the file when it is neither or cannot be read.
std::unique_ptr<BagReader> OpenBag(const std::filesystem::path& path,
                                   const BagReadOptions& options = {});

// "/a (sensor_msgs/msg/PointCloud2, 10 messages), /b (std_msgs/msg/String)"
std::string TopicList(const std::vector<BagTopic>& topics);

}  // namespace dammloam::io
