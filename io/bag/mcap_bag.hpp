#pragma once
#include <memory>
#include <vector>

#include "io/bag/bag_reader.hpp"
#include "io/bag/mcap_reader.hpp"

namespace dammloam::io {

// BagReader over one or more MCAP files read one after the other (a single .mcap, or the
// split files of a rosbag2 directory with storage mcap). Topic types come from the channels'
// schema names, serialization from their message_encoding.
class McapBag : public BagReader {
 public:
  McapBag(const std::vector<std::filesystem::path>& files, const McapReadOptions& options);
  const std::vector<BagTopic>& topics() const override { return topics_; }
  void Select(const std::string& topic) override;
  bool Next(BagMessage& out) override;

 private:
  std::vector<std::filesystem::path> files_;
  McapReadOptions options_;
  std::vector<BagTopic> topics_;
  std::string topic_;
  std::size_t file_index_ = 0;
  std::unique_ptr<McapReader> reader_;
  std::size_t reader_file_ = 0;  // the file reader_ reads
  McapMessage message_;
};

}  // namespace dammloam::io
