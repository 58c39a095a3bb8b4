#include "io/bag/mcap_writer.hpp"

#include <algorithm>
#include <bit>
#include <cstring>

#include "io/bag/decompress.hpp"
#include "io/bag/mcap_format.hpp"
#include "io/io_error.hpp"

namespace dammloam::io {
namespace {

static_assert(std::endian::native == std::endian::little, "MCAP and CDR output assume a little-endian host");

// One record's content, little-endian as MCAP wants it.
class Content {
 public:
  template <typename T>
  Content& Put(T v) {
    const std::size_t at = bytes.size();
    bytes.resize(at + sizeof(T));
    std::memcpy(bytes.data() + at, &v, sizeof(T));
    return *this;
  }
  Content& String(const std::string& s) {
    Put(static_cast<std::uint32_t>(s.size()));
    bytes.insert(bytes.end(), s.begin(), s.end());
    return *this;
  }
  Content& Raw(const std::vector<std::uint8_t>& data) {
    bytes.insert(bytes.end(), data.begin(), data.end());
    return *this;
  }
  // opcode, length, content
  std::vector<std::uint8_t> Record(std::uint8_t opcode) const {
    Content r;
    r.Put(opcode).Put(static_cast<std::uint64_t>(bytes.size()));
    r.bytes.insert(r.bytes.end(), bytes.begin(), bytes.end());
    return r.bytes;
  }
  std::vector<std::uint8_t> bytes;
};

}  // namespace

McapWriter::McapWriter(const std::filesystem::path& file, const McapWriteOptions& options)
    : file_(file), options_(options) {
  if (options_.compression != "" && options_.compression != "zstd") {
    throw IoError(file.string() + ": MCAP compression '" + options_.compression +
                  "' is not written (zstd or none)");
  }
  out_.open(file, std::ios::binary | std::ios::trunc);
  if (!out_) throw IoError(file.string() + ": cannot open for writing");
  Emit(std::vector<std::uint8_t>(mcap::kMagic, mcap::kMagic + 8));
  Emit(Content().String(options_.profile).String("dammloam").Record(mcap::kHeader));
}

McapWriter::~McapWriter() {
  try {
    Close();
  } catch (...) {  // a destructor must not throw; Close() reports errors when called itself
  }
}

void McapWriter::Emit(const std::vector<std::uint8_t>& bytes) {
  out_.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out_) throw IoError(file_.string() + ": write failed at byte " + std::to_string(position_));
  data_crc_ = Crc32(data_crc_, bytes.data(), bytes.size());
  position_ += bytes.size();
}

std::uint16_t McapWriter::AddSchema(const std::string& name, const std::string& encoding,
                                    const std::string& data) {
  const auto id = static_cast<std::uint16_t>(schemas_.size() + 1);
  Content c;
  c.Put(id).String(name).String(encoding).Put(static_cast<std::uint32_t>(data.size()));
  c.bytes.insert(c.bytes.end(), data.begin(), data.end());
  schemas_.push_back(c.Record(mcap::kSchema));
  Emit(schemas_.back());
  return id;
}

std::uint16_t McapWriter::AddChannel(std::uint16_t schema_id, const std::string& topic,
                                     const std::string& message_encoding,
                                     const std::map<std::string, std::string>& metadata) {
  const auto id = static_cast<std::uint16_t>(channels_.size());
  Content map;
  for (const auto& [key, value] : metadata) map.String(key).String(value);
  Content c;
  c.Put(id).Put(schema_id).String(topic).String(message_encoding)
      .Put(static_cast<std::uint32_t>(map.bytes.size())).Raw(map.bytes);
  channels_.push_back(c.Record(mcap::kChannel));
  Emit(channels_.back());
  return id;
}

void McapWriter::Write(std::uint16_t channel_id, std::uint64_t log_time,
                       std::uint64_t publish_time, const std::vector<std::uint8_t>& data) {
  if (closed_) throw IoError(file_.string() + ": write after Close()");
  if (chunk_.empty()) chunk_start_ = chunk_end_ = log_time;
  chunk_start_ = std::min(chunk_start_, log_time);
  chunk_end_ = std::max(chunk_end_, log_time);
  chunk_index_[channel_id].emplace_back(log_time, chunk_.size());
  Content c;
  c.Put(channel_id).Put(static_cast<std::uint32_t>(message_count_)).Put(log_time).Put(publish_time).Raw(data);
  const auto record = c.Record(mcap::kMessage);
  chunk_.insert(chunk_.end(), record.begin(), record.end());
  if (message_count_ == 0) first_time_ = last_time_ = log_time;
  first_time_ = std::min(first_time_, log_time);
  last_time_ = std::max(last_time_, log_time);
  ++message_count_;
  ++message_counts_[channel_id];
  if (chunk_.size() >= options_.chunk_bytes) FlushChunk();
}

void McapWriter::FlushChunk() {
  if (chunk_.empty()) return;
  const std::vector<std::uint8_t> compressed =
      options_.compression == "zstd" ? CompressZstd(chunk_.data(), chunk_.size(), 1) : chunk_;
  ChunkIndex index{};
  index.start_time = chunk_start_;
  index.end_time = chunk_end_;
  index.offset = position_;
  index.compressed_size = compressed.size();
  index.uncompressed_size = chunk_.size();
  Content c;
  c.Put(chunk_start_).Put(chunk_end_).Put(static_cast<std::uint64_t>(chunk_.size()))
      .Put(Crc32(0, chunk_.data(), chunk_.size())).String(options_.compression)
      .Put(static_cast<std::uint64_t>(compressed.size())).Raw(compressed);
  const auto record = c.Record(mcap::kChunk);
  Emit(record);
  index.length = record.size();
  const std::uint64_t indexes_start = position_;
  for (const auto& [channel, entries] : chunk_index_) {
    index.index_offsets[channel] = position_;
    Content m;
    m.Put(channel).Put(static_cast<std::uint32_t>(entries.size() * 16));
    for (const auto& [time, offset] : entries) m.Put(time).Put(offset);
    Emit(m.Record(mcap::kMessageIndex));
  }
  index.index_length = position_ - indexes_start;
  chunk_indexes_.push_back(std::move(index));
  chunk_.clear();
  chunk_index_.clear();
}

void McapWriter::WriteSummary() {
  std::vector<std::uint8_t> summary;
  struct Group { std::uint8_t opcode; std::uint64_t start, length; };
  std::vector<Group> groups;
  const std::uint64_t summary_start = position_;
  const auto add_group = [&](std::uint8_t opcode, const std::vector<std::vector<std::uint8_t>>& records) {
    if (records.empty()) return;
    const std::uint64_t start = summary_start + summary.size();
    for (const auto& r : records) summary.insert(summary.end(), r.begin(), r.end());
    groups.push_back({opcode, start, summary_start + summary.size() - start});
  };
  add_group(mcap::kSchema, schemas_);
  add_group(mcap::kChannel, channels_);
  Content stats;
  Content counts;
  for (const auto& [channel, n] : message_counts_) counts.Put(channel).Put(n);
  stats.Put(message_count_).Put(static_cast<std::uint16_t>(schemas_.size()))
      .Put(static_cast<std::uint32_t>(channels_.size())).Put(std::uint32_t{0}).Put(std::uint32_t{0})
      .Put(static_cast<std::uint32_t>(chunk_indexes_.size())).Put(first_time_).Put(last_time_)
      .Put(static_cast<std::uint32_t>(counts.bytes.size())).Raw(counts.bytes);
  add_group(mcap::kStatistics, {stats.Record(mcap::kStatistics)});
  std::vector<std::vector<std::uint8_t>> chunk_records;
  for (const ChunkIndex& ci : chunk_indexes_) {
    Content offsets;
    for (const auto& [channel, offset] : ci.index_offsets) offsets.Put(channel).Put(offset);
    Content c;
    c.Put(ci.start_time).Put(ci.end_time).Put(ci.offset).Put(ci.length)
        .Put(static_cast<std::uint32_t>(offsets.bytes.size())).Raw(offsets.bytes)
        .Put(ci.index_length).String(options_.compression).Put(ci.compressed_size)
        .Put(ci.uncompressed_size);
    chunk_records.push_back(c.Record(mcap::kChunkIndex));
  }
  add_group(mcap::kChunkIndex, chunk_records);
  const std::uint64_t summary_offset_start = summary_start + summary.size();
  for (const Group& g : groups) {
    const auto r = Content().Put(g.opcode).Put(g.start).Put(g.length).Record(mcap::kSummaryOffset);
    summary.insert(summary.end(), r.begin(), r.end());
  }
  // The footer's CRC covers the summary and the footer up to its own crc field.
  Content footer;
  footer.Put(mcap::kFooter).Put(static_cast<std::uint64_t>(mcap::kFooterContent))
      .Put(summary_start).Put(summary_offset_start);
  const std::uint32_t crc =
      Crc32(Crc32(0, summary.data(), summary.size()), footer.bytes.data(), footer.bytes.size());
  footer.Put(crc);
  const std::vector<std::uint8_t>& footer_record = footer.bytes;
  Emit(summary);
  Emit(footer_record);
  Emit(std::vector<std::uint8_t>(mcap::kMagic, mcap::kMagic + 8));
}

void McapWriter::Close() {
  if (closed_) return;
  closed_ = true;
  FlushChunk();
  Emit(Content().Put(data_crc_).Record(mcap::kDataEnd));
  WriteSummary();
  out_.close();
  if (!out_) throw IoError(file_.string() + ": closing failed");
}

}  // namespace dammloam::io
