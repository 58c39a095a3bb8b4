#pragma once
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "io/bag/bag_reader.hpp"

namespace dammloam::io {

// ROS 1 message types are named "pkg/Name"; topics() reports them as "pkg/msg/Name" (the ROS 2
// spelling the rest of io/bag matches on) with serialization_format "ros1".
inline constexpr const char* kRos1Serialization = "ros1";

// A ROS 1 bag, format 2.0 (wiki.ros.org/Bags/Format/2.0): the bag header record, chunks stored,
// bz2 or lz4 (LZ4 frame, as roslz4 writes), connection, message-data, index-data and chunk-info
// records. Streamed: one chunk is in memory at a time. The topics and per-topic message counts
// come from the index section (connection and chunk-info records at the header's index_pos);
// a bag without one (index_pos 0: recording was interrupted; or an index_pos past the end: the file
// was cut) is scanned once for its connections.
// Messages come in file order; their data is the ROS 1 serialisation (little-endian, no
// alignment). Every problem is an IoError "<file>: <record> at byte N: ...".
class Ros1Bag : public BagReader {
 public:
  explicit Ros1Bag(const std::filesystem::path& file, const BagReadOptions& options = {});

  const std::vector<BagTopic>& topics() const override { return topics_; }
  void Select(const std::string& topic) override;
  bool Next(BagMessage& out) override;

  // The connection's ROS 1 type ("sensor_msgs/PointCloud2") by topic, for messages.
  const std::string& Ros1Type(const std::string& topic) const;

 private:
  struct Record {
    std::uint64_t offset = 0;  // of the record's header length, in the file or the chunk
    std::uint8_t op = 0;
    std::map<std::string, std::string> fields;  // header fields, values raw bytes
    const std::uint8_t* data = nullptr;
    std::uint32_t data_size = 0;
    std::uint64_t data_at = 0;  // offset of data[0], in the file or the chunk
  };
  struct Connection {
    std::string topic, type;
  };

  // Reads the record at the file position into file_record_; false at the end of the file
  // (or at index_pos when stop_at_index).
  bool ReadFileRecord(bool stop_at_index);
  // Parses "len name=value" header fields of a record (in the file or a chunk).
  void ParseHeader(const std::uint8_t* header, std::uint32_t size, std::uint64_t offset,
                   const std::string& where, Record& record) const;
  // The next record of the current chunk; false when it is exhausted.
  bool NextChunkRecord(Record& record);
  void LoadChunk(const Record& chunk);
  void AddConnection(const Record& record, const std::string& where);
  void ReadIndex();
  void ScanConnections();
  std::string Where(const char* what, std::uint64_t offset, bool in_chunk) const;
  void Rewind();

  std::filesystem::path file_;
  BagReadOptions options_;
  std::ifstream in_;
  std::uint64_t file_size_ = 0;
  std::uint64_t index_pos_ = 0;
  std::uint64_t first_record_ = 0;  // after the bag header record
  std::uint64_t pos_ = 0;           // next record in the file

  std::vector<std::uint8_t> header_buf_, data_buf_, compressed_, chunk_;
  Record file_record_;
  std::uint64_t chunk_offset_ = 0;  // file offset of the chunk record being read
  std::size_t chunk_pos_ = 0;
  bool in_chunk_ = false;

  std::map<std::uint32_t, Connection> connections_;
  std::vector<BagTopic> topics_;
  std::string selected_;
  std::string where_;
};

}  // namespace dammloam::io
