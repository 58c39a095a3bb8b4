#pragma once
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

namespace dammloam::io {

struct McapWriteOptions {
  std::string compression = "zstd";    // "zstd" (level 1: the run, not the file, is the cost) or ""
  std::size_t chunk_bytes = 4u << 20;  // a chunk is closed once its records pass this size
  std::string profile = "ros2";
};

// Writes an indexed MCAP file (https://mcap.dev/spec): schemas and channels in the data
// section, messages in chunks with message indexes, then a summary section (schemas,
// channels, statistics, chunk indexes) with summary offsets, and every CRC set; what Foxglove
// and Lichtblick seek in and `ros2 bag play` reads. Close() finishes the file; a writer
// destroyed without it leaves a file with no summary (still readable front to back).
class McapWriter {
 public:
  McapWriter(const std::filesystem::path& file, const McapWriteOptions& options = {});
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  std::uint16_t AddSchema(const std::string& name, const std::string& encoding,
                          const std::string& data);
  std::uint16_t AddChannel(std::uint16_t schema_id, const std::string& topic,
                           const std::string& message_encoding,
                           const std::map<std::string, std::string>& metadata);
  // log_time and publish_time in ns.
  void Write(std::uint16_t channel_id, std::uint64_t log_time, std::uint64_t publish_time,
             const std::vector<std::uint8_t>& data);
  void Close();

 private:
  struct ChunkIndex {
    std::uint64_t start_time, end_time, offset, length;
    std::map<std::uint16_t, std::uint64_t> index_offsets;
    std::uint64_t index_length, compressed_size, uncompressed_size;
  };

  void Emit(const std::vector<std::uint8_t>& bytes);  // to the file, CRC and position counted
  void FlushChunk();
  void WriteSummary();

  std::filesystem::path file_;
  McapWriteOptions options_;
  std::ofstream out_;
  std::uint64_t position_ = 0;
  std::uint32_t data_crc_ = 0;
  bool closed_ = false;

  std::vector<std::vector<std::uint8_t>> schemas_, channels_;  // records, for the summary
  std::vector<ChunkIndex> chunk_indexes_;
  std::map<std::uint16_t, std::uint64_t> message_counts_;
  std::uint64_t message_count_ = 0, first_time_ = 0, last_time_ = 0;

  std::vector<std::uint8_t> chunk_;  // uncompressed records of the open chunk
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> chunk_index_;
  std::uint64_t chunk_start_ = 0, chunk_end_ = 0;
};

}  // namespace dammloam::io
