#include "io/bag/mcap_reader.hpp"

#include <algorithm>
#include <cstring>

#include "io/bag/byte_cursor.hpp"
#include "io/bag/decompress.hpp"
#include "io/bag/mcap_format.hpp"

namespace dammloam::io {
namespace {

std::string ReadString(ByteCursor& c, std::string_view what) {
  const auto n = c.Read<std::uint32_t>(what);
  const auto* p = c.Bytes(n, what);
  return std::string(reinterpret_cast<const char*>(p), n);
}

std::uint64_t LoadU64(const std::uint8_t* p) {
  std::uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}

}  // namespace

McapReader::McapReader(const std::filesystem::path& file, const McapReadOptions& options)
    : file_(file), options_(options) {
  in_.open(file, std::ios::binary);
  std::error_code error;
  file_size_ = std::filesystem::file_size(file, error);
  if (!in_ || error) throw IoError(file.string() + ": cannot open MCAP file");
  ReadHeader();
  ReadSummary();
  if (channels_.empty()) ScanChannels();
}

std::string McapReader::RecordName(std::uint8_t opcode, std::uint64_t offset) const {
  return file_.string() + ": " + mcap::OpcodeName(opcode) + " record at byte " +
         std::to_string(offset);
}

void McapReader::ReadExactly(std::uint8_t* out, std::uint64_t n, std::uint64_t at,
                             const std::string& what) {
  if (at > file_size_ || n > file_size_ - at) {
    throw IoError(what + ": needs bytes " + std::to_string(at) + " to " + std::to_string(at + n) +
                  " but the file ends at byte " + std::to_string(file_size_) + " (truncated)");
  }
  in_.clear();
  in_.seekg(static_cast<std::streamoff>(at));
  in_.read(reinterpret_cast<char*>(out), static_cast<std::streamsize>(n));
  if (!in_) throw IoError(what + ": read error at byte " + std::to_string(at));
}

void McapReader::ReadHeader() {
  std::uint8_t start[8 + mcap::kRecordPrefix];
  if (file_size_ < sizeof(start)) {
    throw IoError(file_.string() + ": " + std::to_string(file_size_) +
                  " bytes, too short for an MCAP file (truncated or not MCAP)");
  }
  ReadExactly(start, sizeof(start), 0, file_.string() + ": magic");
  if (std::memcmp(start, mcap::kMagic, 8) != 0) {
    throw IoError(file_.string() + ": not an MCAP file (no MCAP magic at byte 0)");
  }
  if (start[8] != mcap::kHeader) {
    throw IoError(RecordName(start[8], 8) + ": the first record must be a Header");
  }
  const std::uint64_t length = LoadU64(start + 9);
  if (length > options_.max_record_bytes) {
    throw IoError(RecordName(mcap::kHeader, 8) + ": length " + std::to_string(length) +
                  " is implausible");
  }
  record_.resize(static_cast<std::size_t>(length));
  ReadExactly(record_.data(), length, sizeof(start), RecordName(mcap::kHeader, 8));
  ByteCursor c(record_.data(), record_.size(), sizeof(start), RecordName(mcap::kHeader, 8));
  ReadString(c, "profile");
  ReadString(c, "library");
  data_start_ = sizeof(start) + length;
  header_crc_ = Crc32(Crc32(0, start, sizeof(start)), record_.data(), record_.size());
  Rewind();
}

void McapReader::ReadSummary() {
  constexpr std::uint64_t kFooterRecord = mcap::kRecordPrefix + mcap::kFooterContent;
  if (file_size_ < data_start_ + kFooterRecord + 8) return;  // no room: scanned instead
  std::uint8_t tail[kFooterRecord + 8];
  const std::uint64_t footer_offset = file_size_ - sizeof(tail);
  ReadExactly(tail, sizeof(tail), footer_offset, file_.string() + ": footer");
  if (std::memcmp(tail + kFooterRecord, mcap::kMagic, 8) != 0) return;  // truncated: scanned
  closed_ = true;
  if (tail[0] != mcap::kFooter || LoadU64(tail + 1) != mcap::kFooterContent) {
    throw IoError(RecordName(tail[0], footer_offset) +
                  ": expected the Footer record before the closing magic");
  }
  const std::uint64_t summary_start = LoadU64(tail + 9);
  const std::uint32_t summary_crc = static_cast<std::uint32_t>(LoadU64(tail + 25 - 4) >> 32);
  if (summary_start == 0) return;
  if (summary_start < data_start_ || summary_start > footer_offset) {
    throw IoError(RecordName(mcap::kFooter, footer_offset) + ": summary_start " +
                  std::to_string(summary_start) + " lies outside the file's records");
  }
  const std::uint64_t length = footer_offset - summary_start;
  if (length > options_.max_record_bytes) {
    throw IoError(RecordName(mcap::kFooter, footer_offset) + ": summary section of " +
                  std::to_string(length) + " bytes is implausible");
  }
  std::vector<std::uint8_t> summary(static_cast<std::size_t>(length));
  ReadExactly(summary.data(), length, summary_start, file_.string() + ": summary section");
  if (summary_crc != 0) {
    // Covers the summary and the footer up to (not including) its summary_crc field.
    const std::uint32_t crc = Crc32(Crc32(0, summary.data(), summary.size()), tail, 25);
    if (crc != summary_crc) {
      throw IoError(RecordName(mcap::kFooter, footer_offset) + ": summary CRC is " +
                    std::to_string(crc) + ", the footer says " + std::to_string(summary_crc) +
                    " (corrupt summary section at byte " + std::to_string(summary_start) + ")");
    }
  }
  ByteCursor c(summary.data(), summary.size(), summary_start, file_.string() + ": summary section");
  while (c.remaining() > 0) {
    const std::uint64_t offset = c.file_offset();
    const auto opcode = c.Read<std::uint8_t>("record opcode");
    const auto n = c.Read<std::uint64_t>("record length");
    const std::string where = RecordName(opcode, offset);
    if (n > c.remaining()) {
      throw IoError(where + ": length " + std::to_string(n) + " runs past the summary section");
    }
    const std::uint64_t content_offset = c.file_offset();
    const std::uint8_t* content = c.Bytes(n, "record");
    if (opcode == mcap::kSchema) {
      AddSchema(content, n, content_offset, where);
    } else if (opcode == mcap::kChannel) {
      AddChannel(content, n, content_offset, where);
    } else if (opcode == mcap::kStatistics) {
      ByteCursor s(content, n, content_offset, where);
      s.Skip(8 + 2 + 4 + 4 + 4 + 4 + 8 + 8, "statistics counts and times");
      const auto map_bytes = s.Read<std::uint32_t>("channel_message_counts length");
      const std::uint64_t map_offset = s.file_offset();
      ByteCursor m(s.Bytes(map_bytes, "channel_message_counts"), map_bytes, map_offset, where);
      while (m.remaining() > 0) {
        const auto channel = m.Read<std::uint16_t>("channel id");
        message_counts_[channel] = m.Read<std::uint64_t>("message count");
      }
      have_statistics_ = true;
    }
  }
}

void McapReader::ScanChannels() {
  McapMessage message;
  std::map<std::uint16_t, std::uint64_t> counts;
  while (Next(message)) ++counts[message.channel_id];
  message_counts_ = std::move(counts);
  have_statistics_ = true;
  Rewind();
}

std::optional<std::uint64_t> McapReader::MessageCount(std::uint16_t channel_id) const {
  if (!have_statistics_) return std::nullopt;
  const auto it = message_counts_.find(channel_id);
  return it == message_counts_.end() ? 0 : it->second;
}

void McapReader::Rewind() {
  pos_ = data_start_;
  data_ended_ = false;
  in_chunk_ = false;
  data_crc_ = header_crc_;
}

bool McapReader::NextRecord() {
  while (!data_ended_) {
    std::uint8_t prefix[mcap::kRecordPrefix];
    if (pos_ + mcap::kRecordPrefix > file_size_) {
      throw IoError(file_.string() + ": ends at byte " + std::to_string(file_size_) +
                    " inside the data section, before a DataEnd record (truncated)");
    }
    ReadExactly(prefix, sizeof(prefix), pos_, file_.string() + ": record at byte " +
                std::to_string(pos_));
    opcode_ = prefix[0];
    record_offset_ = pos_;
    const std::uint64_t length = LoadU64(prefix + 1);
    const std::string where = RecordName(opcode_, pos_);
    if (length > file_size_ - pos_ - mcap::kRecordPrefix) {
      throw IoError(where + ": length " + std::to_string(length) + " runs past the end of the " +
                    "file at byte " + std::to_string(file_size_) + " (truncated)");
    }
    const std::uint64_t content_offset = pos_ + mcap::kRecordPrefix;
    pos_ = content_offset + length;
    if (opcode_ == mcap::kFooter) {  // a writer that left out DataEnd
      data_ended_ = true;
      return false;
    }
    const bool wanted = opcode_ == mcap::kSchema || opcode_ == mcap::kChannel ||
                        opcode_ == mcap::kMessage || opcode_ == mcap::kChunk ||
                        opcode_ == mcap::kDataEnd;
    if (wanted && length > options_.max_record_bytes) {
      throw IoError(where + ": length " + std::to_string(length) + " exceeds the limit of " +
                    std::to_string(options_.max_record_bytes) + " bytes (corrupt?)");
    }
    if (opcode_ != mcap::kDataEnd) data_crc_ = Crc32(data_crc_, prefix, sizeof(prefix));
    if (!wanted) {
      // Attachments, metadata, message indexes: not needed, but part of the data CRC.
      std::vector<std::uint8_t> piece;
      for (std::uint64_t done = 0; done < length;) {
        const std::uint64_t n = std::min<std::uint64_t>(length - done, 1u << 20);
        piece.resize(static_cast<std::size_t>(n));
        ReadExactly(piece.data(), n, content_offset + done, where);
        data_crc_ = Crc32(data_crc_, piece.data(), piece.size());
        done += n;
      }
      continue;
    }
    record_.resize(static_cast<std::size_t>(length));
    ReadExactly(record_.data(), length, content_offset, where);
    if (opcode_ == mcap::kDataEnd) {
      ByteCursor c(record_.data(), record_.size(), content_offset, where);
      const auto crc = c.Read<std::uint32_t>("data_section_crc");
      if (crc != 0 && crc != data_crc_) {
        throw IoError(where + ": data section CRC is " + std::to_string(data_crc_) +
                      ", the record says " + std::to_string(crc) + " (corrupt data section)");
      }
      if (!closed_) {
        throw IoError(file_.string() + ": ends at byte " + std::to_string(file_size_) +
                      " without the footer and closing magic after the DataEnd record at byte " +
                      std::to_string(record_offset_) + " (truncated)");
      }
      data_ended_ = true;
      return false;
    }
    data_crc_ = Crc32(data_crc_, record_.data(), record_.size());
    return true;
  }
  return false;
}

void McapReader::OpenChunk() {
  const std::string where = RecordName(mcap::kChunk, record_offset_);
  ByteCursor c(record_.data(), record_.size(), record_offset_ + mcap::kRecordPrefix, where);
  c.Skip(16, "message_start_time, message_end_time");
  const auto uncompressed_size = c.Read<std::uint64_t>("uncompressed_size");
  const auto crc = c.Read<std::uint32_t>("uncompressed_crc");
  const std::string compression = ReadString(c, "compression");
  const auto records_size = c.Read<std::uint64_t>("records length");
  if (records_size != c.remaining()) {
    c.Fail("records length " + std::to_string(records_size) + " but the record holds " +
           std::to_string(c.remaining()) + " bytes");
  }
  if (uncompressed_size > options_.max_record_bytes) {
    c.Fail("uncompressed_size " + std::to_string(uncompressed_size) + " exceeds the limit of " +
           std::to_string(options_.max_record_bytes) + " bytes (corrupt?)");
  }
  const std::uint8_t* records = c.Bytes(records_size, "records");
  if (compression.empty() && records_size == uncompressed_size) {
    chunk_data_ = records;  // stored: read in place, no copy
    chunk_size_ = static_cast<std::size_t>(records_size);
  } else {
    Decompress(compression, records, records_size, uncompressed_size, chunk_, where);
    chunk_data_ = chunk_.data();
    chunk_size_ = chunk_.size();
  }
  if (crc != 0) {
    const std::uint32_t actual = Crc32(0, chunk_data_, chunk_size_);
    if (actual != crc) {
      throw IoError(where + ": CRC of the decompressed records is " + std::to_string(actual) +
                    ", the chunk says " + std::to_string(crc) + " (corrupt chunk)");
    }
  }
  chunk_pos_ = 0;
  chunk_offset_ = record_offset_;
  in_chunk_ = true;
}

bool McapReader::NextInChunk(McapMessage& out) {
  const std::string chunk_name = RecordName(mcap::kChunk, chunk_offset_);
  while (chunk_pos_ < chunk_size_) {
    ByteCursor c(chunk_data_, chunk_size_, 0, chunk_name + " (decompressed)");
    c.SetPosition(chunk_pos_, "record");
    const std::uint64_t offset = chunk_pos_;
    const auto opcode = c.Read<std::uint8_t>("record opcode");
    const auto length = c.Read<std::uint64_t>("record length");
    const std::string where = file_.string() + ": " + mcap::OpcodeName(opcode) +
                              " record at byte " + std::to_string(offset) + " of the Chunk " +
                              "record at byte " + std::to_string(chunk_offset_) +
                              " (decompressed)";
    if (length > c.remaining()) {
      throw IoError(where + ": length " + std::to_string(length) + " runs past the chunk's " +
                    std::to_string(chunk_size_) + " bytes");
    }
    const std::uint64_t content = c.position();
    chunk_pos_ = static_cast<std::size_t>(content + length);
    const std::uint8_t* data = chunk_data_ + content;
    if (opcode == mcap::kSchema) {
      AddSchema(data, length, content, where);
    } else if (opcode == mcap::kChannel) {
      AddChannel(data, length, content, where);
    } else if (opcode == mcap::kMessage) {
      ReadMessage(data, length, content, where, out);
      return true;
    }
  }
  in_chunk_ = false;
  return false;
}

bool McapReader::Next(McapMessage& out) {
  for (;;) {
    if (in_chunk_ && NextInChunk(out)) return true;
    if (!NextRecord()) return false;
    const std::string where = RecordName(opcode_, record_offset_);
    const std::uint64_t content = record_offset_ + mcap::kRecordPrefix;
    if (opcode_ == mcap::kSchema) {
      AddSchema(record_.data(), record_.size(), content, where);
    } else if (opcode_ == mcap::kChannel) {
      AddChannel(record_.data(), record_.size(), content, where);
    } else if (opcode_ == mcap::kChunk) {
      OpenChunk();
    } else if (opcode_ == mcap::kMessage) {
      ReadMessage(record_.data(), record_.size(), content, where, out);
      return true;
    }
  }
}

// A Message record's fields; its channel must have come before it.
void McapReader::ReadMessage(const std::uint8_t* data, std::size_t size, std::uint64_t offset,
                             const std::string& where, McapMessage& out) const {
  ByteCursor m(data, size, offset, where);
  out.channel_id = m.Read<std::uint16_t>("channel_id");
  out.sequence = m.Read<std::uint32_t>("sequence");
  out.log_time = m.Read<std::uint64_t>("log_time");
  out.publish_time = m.Read<std::uint64_t>("publish_time");
  out.data_offset = m.file_offset();
  out.size = m.remaining();
  out.data = m.Bytes(out.size, "data");
  out.where = where;
  if (!channels_.count(out.channel_id)) {
    throw IoError(where + ": channel " + std::to_string(out.channel_id) + " has no Channel record");
  }
}

void McapReader::AddSchema(const std::uint8_t* data, std::size_t size, std::uint64_t offset,
                           const std::string& where) {
  ByteCursor c(data, size, offset, where);
  McapSchema schema;
  schema.id = c.Read<std::uint16_t>("id");
  if (schema.id == 0) c.Fail("schema id 0 is reserved");
  schema.name = ReadString(c, "name");
  schema.encoding = ReadString(c, "encoding");
  const auto n = c.Read<std::uint32_t>("data length");
  const auto* bytes = c.Bytes(n, "data");
  schema.data.assign(bytes, bytes + n);
  schemas_.try_emplace(schema.id, std::move(schema));
}

void McapReader::AddChannel(const std::uint8_t* data, std::size_t size, std::uint64_t offset,
                            const std::string& where) {
  ByteCursor c(data, size, offset, where);
  McapChannel channel;
  channel.id = c.Read<std::uint16_t>("id");
  channel.schema_id = c.Read<std::uint16_t>("schema_id");
  channel.topic = ReadString(c, "topic");
  channel.message_encoding = ReadString(c, "message_encoding");
  const auto map_bytes = c.Read<std::uint32_t>("metadata length");
  const std::uint64_t map_offset = c.file_offset();
  ByteCursor m(c.Bytes(map_bytes, "metadata"), map_bytes, map_offset, where);
  while (m.remaining() > 0) {
    std::string key = ReadString(m, "metadata key");
    channel.metadata[std::move(key)] = ReadString(m, "metadata value");
  }
  if (channel.schema_id != 0 && !schemas_.count(channel.schema_id)) {
    c.Fail("channel " + std::to_string(channel.id) + " (" + channel.topic + ") refers to schema " +
           std::to_string(channel.schema_id) + ", which no Schema record before it defines");
  }
  channels_.try_emplace(channel.id, std::move(channel));
}

}  // namespace dammloam::io
