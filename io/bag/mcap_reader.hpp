#pragma once
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "io/io_error.hpp"

namespace dammloam::io {

struct McapSchema {
  std::uint16_t id = 0;
  std::string name;      // e.g. sensor_msgs/msg/PointCloud2
  std::string encoding;  // e.g. ros2msg
  std::vector<std::uint8_t> data;
};

struct McapChannel {
  std::uint16_t id = 0;
  std::uint16_t schema_id = 0;  // 0: no schema
  std::string topic;
  std::string message_encoding;  // e.g. cdr
  std::map<std::string, std::string> metadata;
};

// One message; data points into the reader's buffer and is valid until the next Next().
struct McapMessage {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::uint64_t log_time = 0;      // ns
  std::uint64_t publish_time = 0;  // ns
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
  // Where the message is, for error messages: "<file>: Message record at byte N" (in the
  // file, or "... at byte N of the Chunk record at byte M (decompressed)").
  std::string where;
  std::uint64_t data_offset = 0;  // byte of data[0] in the file (or in the decompressed chunk)
};

struct McapReadOptions {
  // Larger records (decompressed chunks, summary section, unchunked messages) are refused as
  // corrupt rather than allocated: a flipped length byte must not ask for terabytes.
  std::uint64_t max_record_bytes = 1ull << 30;
};

// Streams an MCAP file (https://mcap.dev/spec) record by record: one chunk is in memory at a
// time, so files larger than memory are read with bounded memory. Checks the magic at both
// ends, every chunk's CRC and the summary and data-section CRCs where the writer set them.
// Every problem is an IoError naming the file, the record and its byte offset.
class McapReader {
 public:
  // Reads the header and, when the footer points to one, the summary section (schemas,
  // channels, statistics). A file without summary is scanned once to learn its channels.
  explicit McapReader(const std::filesystem::path& file, const McapReadOptions& options = {});

  const std::filesystem::path& file() const { return file_; }
  const std::map<std::uint16_t, McapChannel>& channels() const { return channels_; }
  const std::map<std::uint16_t, McapSchema>& schemas() const { return schemas_; }
  // Messages per channel from the Statistics record, when the file has one.
  std::optional<std::uint64_t> MessageCount(std::uint16_t channel_id) const;

  // The next message of the data section, in file order; false after the last one.
  bool Next(McapMessage& out);
  // Back to the first record after the header.
  void Rewind();

 private:
  void ReadHeader();
  void ReadSummary();
  void ScanChannels();
  // The next record of the data section into record_ (content only); false at its end.
  bool NextRecord();
  void ReadExactly(std::uint8_t* out, std::uint64_t n, std::uint64_t at, const std::string& what);
  bool NextInChunk(McapMessage& out);
  void OpenChunk();
  void ReadMessage(const std::uint8_t* data, std::size_t size, std::uint64_t offset,
                   const std::string& where, McapMessage& out) const;
  void AddSchema(const std::uint8_t* data, std::size_t size, std::uint64_t offset,
                 const std::string& where);
  void AddChannel(const std::uint8_t* data, std::size_t size, std::uint64_t offset,
                  const std::string& where);
  std::string RecordName(std::uint8_t opcode, std::uint64_t offset) const;

  std::filesystem::path file_;
  McapReadOptions options_;
  std::ifstream in_;
  std::uint64_t file_size_ = 0;
  std::uint64_t data_start_ = 0;  // first record after the header
  std::uint64_t pos_ = 0;         // next record in the data section
  bool data_ended_ = false;
  bool have_statistics_ = false;
  bool closed_ = false;  // the file ends with the closing magic
  std::uint32_t header_crc_ = 0;   // CRC of the magic and the Header record
  std::uint32_t data_crc_ = 0;     // running CRC of the data section so far

  std::uint8_t opcode_ = 0;        // current record
  std::uint64_t record_offset_ = 0;
  std::vector<std::uint8_t> record_;

  std::vector<std::uint8_t> chunk_;  // decompressed records of the current chunk
  const std::uint8_t* chunk_data_ = nullptr;  // the records: in chunk_, or in record_ if stored
  std::size_t chunk_size_ = 0;
  std::size_t chunk_pos_ = 0;
  std::uint64_t chunk_offset_ = 0;
  bool in_chunk_ = false;

  std::map<std::uint16_t, McapChannel> channels_;
  std::map<std::uint16_t, McapSchema> schemas_;
  std::map<std::uint16_t, std::uint64_t> message_counts_;
};

}  // namespace dammloam::io
