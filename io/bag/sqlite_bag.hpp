#pragma once
#include <memory>
#include <vector>

#include "io/bag/bag_reader.hpp"
#include "io/bag/rosbag2_metadata.hpp"

struct sqlite3;
struct sqlite3_stmt;

namespace dammloam::io {

// BagReader over the .db3 files of a rosbag2 directory with storage sqlite3 (tables
// topics(id, name, type, serialization_format, ...) and messages(id, topic_id, timestamp,
// data)), read through libsqlite3 one row at a time.
class SqliteBag : public BagReader {
 public:
  SqliteBag(const Rosbag2Metadata& metadata, const BagReadOptions& options);
  ~SqliteBag() override;
  const std::vector<BagTopic>& topics() const override { return topics_; }
  void Select(const std::string& topic) override;
  bool Next(BagMessage& out) override;

 private:
  void OpenFile(std::size_t index);
  void Close();

  Rosbag2Metadata metadata_;
  BagReadOptions options_;
  std::vector<BagTopic> topics_;
  std::string topic_;
  std::size_t file_index_ = 0;
  sqlite3* db_ = nullptr;
  sqlite3_stmt* query_ = nullptr;
  std::vector<std::uint8_t> decompressed_;  // compression_mode MESSAGE
};

}  // namespace dammloam::io
