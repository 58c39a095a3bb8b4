#include "io/bag/ros1_bag.hpp"

#include <algorithm>
#include <cstring>

#include "io/bag/byte_cursor.hpp"
#include "io/bag/decompress.hpp"
#include "io/io_error.hpp"

namespace dammloam::io {
namespace {

constexpr char kRos1Magic[] = "#ROSBAG V2.0\n";
constexpr std::size_t kRos1MagicSize = sizeof(kRos1Magic) - 1;

enum Ros1Op : std::uint8_t {
  kOpMessageData = 0x02,
  kOpBagHeader = 0x03,
  kOpIndexData = 0x04,
  kOpChunk = 0x05,
  kOpChunkInfo = 0x06,
  kOpConnection = 0x07,
};

std::string OpName(std::uint8_t op) {
  switch (op) {
    case kOpMessageData: return "Message data record";
    case kOpBagHeader: return "Bag header record";
    case kOpIndexData: return "Index data record";
    case kOpChunk: return "Chunk record";
    case kOpChunkInfo: return "Chunk info record";
    case kOpConnection: return "Connection record";
    default: return "record (op " + std::to_string(op) + ")";
  }
}

// "sensor_msgs/PointCloud2" -> "sensor_msgs/msg/PointCloud2".
std::string Ros2Spelling(const std::string& ros1_type) {
  const auto slash = ros1_type.find('/');
  if (slash == std::string::npos || ros1_type.find('/', slash + 1) != std::string::npos) {
    return ros1_type;
  }
  return ros1_type.substr(0, slash) + "/msg/" + ros1_type.substr(slash + 1);
}

}  // namespace

Ros1Bag::Ros1Bag(const std::filesystem::path& file, const BagReadOptions& options)
    : file_(file), options_(options) {
  std::error_code ec;
  file_size_ = std::filesystem::file_size(file, ec);
  if (ec) throw IoError(file.string() + ": cannot read (" + ec.message() + ")");
  in_.open(file, std::ios::binary);
  if (!in_) throw IoError(file.string() + ": cannot open");
  char magic[kRos1MagicSize] = {};
  in_.read(magic, kRos1MagicSize);
  if (in_.gcount() != static_cast<std::streamsize>(kRos1MagicSize) ||
      std::memcmp(magic, kRos1Magic, kRos1MagicSize) != 0) {
    const bool other_version = in_.gcount() >= 9 && std::memcmp(magic, "#ROSBAG V", 9) == 0;
    throw IoError(file.string() + ": not a ROS 1 bag of format 2.0 (" +
                  (other_version ? "version " + std::string(magic + 9, 3) : "no '#ROSBAG V2.0' line") +
                  " at byte 0)");
  }
  pos_ = kRos1MagicSize;
  if (!ReadFileRecord(false) || file_record_.op != kOpBagHeader) {
    throw IoError(Where("first record", kRos1MagicSize, false) + ": not a bag header record");
  }
  const auto it = file_record_.fields.find("index_pos");
  if (it == file_record_.fields.end() || it->second.size() != 8) {
    throw IoError(Where("Bag header record", kRos1MagicSize, false) + ": no 8-byte index_pos field");
  }
  std::memcpy(&index_pos_, it->second.data(), 8);
  first_record_ = pos_;
  if (index_pos_ != 0 && index_pos_ < first_record_) {
    throw IoError(Where("Bag header record", kRos1MagicSize, false) + ": index_pos " +
                  std::to_string(index_pos_) + " lies inside the header");
  }
  // An index past the end: the file was cut. Scanning it names the record that was cut short.
  if (index_pos_ > file_size_) index_pos_ = 0;
  if (index_pos_ != 0) {
    ReadIndex();
  } else {
    ScanConnections();
  }
  Rewind();
}

std::string Ros1Bag::Where(const char* what, std::uint64_t offset, bool in_chunk) const {
  if (in_chunk) {
    return file_.string() + ": " + what + " at byte " + std::to_string(offset) +
           " of the chunk at byte " + std::to_string(chunk_offset_) + " (decompressed)";
  }
  return file_.string() + ": " + what + " at byte " + std::to_string(offset);
}

void Ros1Bag::Rewind() {
  pos_ = first_record_;
  in_chunk_ = false;
  chunk_.clear();
  chunk_pos_ = 0;
}

void Ros1Bag::ParseHeader(const std::uint8_t* header, std::uint32_t size, std::uint64_t offset,
                          const std::string& where, Record& record) const {
  ByteCursor cursor(header, size, offset, where);
  record.fields.clear();
  while (cursor.remaining() > 0) {
    const std::uint32_t n = cursor.Read<std::uint32_t>("header field length");
    const std::uint8_t* p = cursor.Bytes(n, "header field");
    const auto* eq = static_cast<const std::uint8_t*>(std::memchr(p, '=', n));
    if (eq == nullptr) cursor.Fail("header field without '='");
    record.fields[std::string(p, eq)] = std::string(eq + 1, p + n);
  }
  const auto op = record.fields.find("op");
  if (op == record.fields.end() || op->second.size() != 1) {
    throw IoError(where + " at byte " + std::to_string(offset) + ": header has no 1-byte op field");
  }
  record.op = static_cast<std::uint8_t>(op->second[0]);
}

bool Ros1Bag::ReadFileRecord(bool stop_at_index) {
  if (pos_ >= file_size_ || (stop_at_index && index_pos_ != 0 && pos_ >= index_pos_)) return false;
  const std::uint64_t offset = pos_;
  const std::string where = Where("record", offset, false);
  auto read = [&](std::uint64_t at, std::uint64_t n, std::vector<std::uint8_t>& buf, const char* what) {
    if (n > options_.max_record_bytes) {
      throw IoError(where + ": " + what + " of " + std::to_string(n) + " bytes exceeds the limit (" +
                    std::to_string(options_.max_record_bytes) + "): corrupt length");
    }
    if (at > file_size_ || n > file_size_ - at) {
      throw IoError(where + ": truncated: " + what + " needs " + std::to_string(n) + " bytes at byte " +
                    std::to_string(at) + ", the file ends at " + std::to_string(file_size_));
    }
    buf.resize(static_cast<std::size_t>(n));
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(at));
    in_.read(reinterpret_cast<char*>(buf.data()), static_cast<std::streamsize>(n));
    if (in_.gcount() != static_cast<std::streamsize>(n)) throw IoError(where + ": read error");
  };
  std::uint32_t header_len = 0, data_len = 0;
  read(offset, 4, header_buf_, "header length");
  std::memcpy(&header_len, header_buf_.data(), 4);
  read(offset + 4, header_len, header_buf_, "header");
  ParseHeader(header_buf_.data(), header_len, offset + 4, where, file_record_);
  const std::string named = Where(OpName(file_record_.op).c_str(), offset, false);
  std::vector<std::uint8_t> length(4);
  try {
    read(offset + 4 + header_len, 4, length, "data length");
    std::memcpy(&data_len, length.data(), 4);
    read(offset + 8 + header_len, data_len, data_buf_, "data");
  } catch (const IoError& e) {
    throw IoError(named + std::string(e.what()).substr(where.size()));
  }
  file_record_.offset = offset;
  file_record_.data = data_buf_.data();
  file_record_.data_at = offset + 8 + header_len;
  file_record_.data_size = data_len;
  pos_ = offset + 8 + header_len + data_len;
  return true;
}

bool Ros1Bag::NextChunkRecord(Record& record) {
  if (chunk_pos_ >= chunk_.size()) return false;
  const std::uint64_t offset = chunk_pos_;
  // Offsets count from the chunk's start (decompressed); `where` names the chunk.
  ByteCursor c(chunk_.data(), chunk_.size(), 0,
               file_.string() + ": in the chunk at byte " + std::to_string(chunk_offset_) +
                   " (decompressed), record");
  c.SetPosition(chunk_pos_, "record");
  const std::uint32_t header_len = c.Read<std::uint32_t>("header length");
  const std::uint8_t* header = c.Bytes(header_len, "header");
  ParseHeader(header, header_len, offset + 4, Where("record", offset, true), record);
  const std::uint32_t data_len = c.Read<std::uint32_t>("data length");
  record.data_at = c.position();
  record.data = c.Bytes(data_len, "data");
  record.data_size = data_len;
  record.offset = offset;
  chunk_pos_ = c.position();
  return true;
}

void Ros1Bag::LoadChunk(const Record& chunk) {
  const std::string where = Where("Chunk record", chunk.offset, false);
  const auto compression = chunk.fields.find("compression");
  const auto size = chunk.fields.find("size");
  if (compression == chunk.fields.end() || size == chunk.fields.end() || size->second.size() != 4) {
    throw IoError(where + ": no compression or 4-byte size field");
  }
  std::uint32_t uncompressed = 0;
  std::memcpy(&uncompressed, size->second.data(), 4);
  if (uncompressed > options_.max_record_bytes) {
    throw IoError(where + ": chunk of " + std::to_string(uncompressed) +
                  " bytes exceeds the limit: corrupt size");
  }
  const std::string& kind = compression->second;
  if (kind == "none") {
    if (chunk.data_size != uncompressed) {
      throw IoError(where + ": stored chunk of " + std::to_string(chunk.data_size) +
                    " bytes but its size field says " + std::to_string(uncompressed));
    }
    chunk_.assign(chunk.data, chunk.data + chunk.data_size);
  } else if (kind == "bz2") {
    DecompressBz2(chunk.data, chunk.data_size, uncompressed, chunk_, where);
  } else if (kind == "lz4") {
    Decompress("lz4", chunk.data, chunk.data_size, uncompressed, chunk_, where);
  } else {
    throw IoError(where + ": unknown compression '" + kind + "' (supported: none, bz2, lz4)");
  }
  chunk_offset_ = chunk.offset;
  chunk_pos_ = 0;
  in_chunk_ = true;
}

void Ros1Bag::AddConnection(const Record& record, const std::string& where) {
  const auto conn = record.fields.find("conn");
  const auto topic = record.fields.find("topic");
  if (conn == record.fields.end() || conn->second.size() != 4 || topic == record.fields.end()) {
    throw IoError(where + ": no 4-byte conn or topic field");
  }
  std::uint32_t id = 0;
  std::memcpy(&id, conn->second.data(), 4);
  Record definition;
  definition.fields.clear();
  // The data is a header of its own (topic, type, md5sum, message_definition, ...), without op.
  ByteCursor cursor(record.data, record.data_size, 0, where + ", connection header");
  while (cursor.remaining() > 0) {
    const std::uint32_t n = cursor.Read<std::uint32_t>("field length");
    const std::uint8_t* p = cursor.Bytes(n, "field");
    const auto* eq = static_cast<const std::uint8_t*>(std::memchr(p, '=', n));
    if (eq == nullptr) cursor.Fail("field without '='");
    definition.fields[std::string(p, eq)] = std::string(eq + 1, p + n);
  }
  const auto type = definition.fields.find("type");
  if (type == definition.fields.end()) throw IoError(where + ": connection without a type");
  connections_[id] = {topic->second, type->second};
}

void Ros1Bag::ReadIndex() {
  pos_ = index_pos_;
  std::map<std::uint32_t, std::uint64_t> counts;
  while (ReadFileRecord(false)) {
    const Record& r = file_record_;
    const std::string where = Where(OpName(r.op).c_str(), r.offset, false);
    if (r.op == kOpConnection) {
      AddConnection(r, where);
    } else if (r.op == kOpChunkInfo) {
      ByteCursor cursor(r.data, r.data_size, r.offset, where + ", data");
      while (cursor.remaining() > 0) {
        const auto conn = cursor.Read<std::uint32_t>("conn");
        counts[conn] += cursor.Read<std::uint32_t>("count");
      }
    } else {
      throw IoError(where + ": unexpected in the index section (connection and chunk info records)");
    }
  }
  std::map<std::string, std::size_t> topic_index;
  for (const auto& [id, c] : connections_) {
    auto [it, added] = topic_index.try_emplace(c.topic, topics_.size());
    if (added) topics_.push_back({c.topic, Ros2Spelling(c.type), kRos1Serialization, 0});
    BagTopic& t = topics_[it->second];
    if (t.type != Ros2Spelling(c.type)) {
      throw IoError(file_.string() + ": topic " + c.topic + " has connections of two types (" +
                    t.type + ", " + c.type + ")");
    }
    *t.message_count += counts[id];
  }
}

void Ros1Bag::ScanConnections() {
  // No index: one pass over every record (and chunk) to learn the connections and counts.
  std::map<std::uint32_t, std::uint64_t> counts;
  Rewind();
  Record record;
  for (;;) {
    if (in_chunk_) {
      if (!NextChunkRecord(record)) {
        in_chunk_ = false;
        continue;
      }
    } else {
      if (!ReadFileRecord(false)) break;
      if (file_record_.op == kOpChunk) {
        LoadChunk(file_record_);
        continue;
      }
      record = file_record_;
    }
    const std::string where = Where(OpName(record.op).c_str(), record.offset, in_chunk_);
    if (record.op == kOpConnection) AddConnection(record, where);
    if (record.op == kOpMessageData) {
      const auto conn = record.fields.find("conn");
      if (conn == record.fields.end() || conn->second.size() != 4) throw IoError(where + ": no conn field");
      std::uint32_t id = 0;
      std::memcpy(&id, conn->second.data(), 4);
      ++counts[id];
    }
  }
  for (const auto& [id, c] : connections_) {
    const std::string& topic = c.topic;  // clang 14 does not capture structured bindings
    auto it = std::find_if(topics_.begin(), topics_.end(), [&](const BagTopic& t) { return t.name == topic; });
    if (it == topics_.end()) {
      topics_.push_back({c.topic, Ros2Spelling(c.type), kRos1Serialization, 0});
      it = topics_.end() - 1;
    }
    *it->message_count += counts[id];
  }
}

const std::string& Ros1Bag::Ros1Type(const std::string& topic) const {
  for (const auto& [id, c] : connections_) {
    if (c.topic == topic) return c.type;
  }
  throw IoError(file_.string() + ": no topic " + topic);
}

void Ros1Bag::Select(const std::string& topic) {
  if (std::none_of(topics_.begin(), topics_.end(), [&](const BagTopic& t) { return t.name == topic; })) {
    throw IoError(file_.string() + ": no topic " + topic + " (topics: " + TopicList(topics_) + ")");
  }
  selected_ = topic;
  Rewind();
}

bool Ros1Bag::Next(BagMessage& out) {
  Record record;
  for (;;) {
    const Record* r = nullptr;
    if (in_chunk_) {
      if (!NextChunkRecord(record)) {
        in_chunk_ = false;
        continue;
      }
      r = &record;
    } else {
      if (!ReadFileRecord(true)) return false;
      if (file_record_.op == kOpChunk) {
        LoadChunk(file_record_);
        continue;
      }
      r = &file_record_;
    }
    const std::string where = Where(OpName(r->op).c_str(), r->offset, in_chunk_);
    switch (r->op) {
      case kOpConnection:
        AddConnection(*r, where);  // already known from the index: checked, same content
        continue;
      case kOpIndexData:
      case kOpChunkInfo:
      case kOpBagHeader:
        continue;
      case kOpMessageData:
        break;
      default:
        throw IoError(where + ": unknown op");
    }
    const auto conn = r->fields.find("conn");
    const auto time = r->fields.find("time");
    if (conn == r->fields.end() || conn->second.size() != 4 || time == r->fields.end() ||
        time->second.size() != 8) {
      throw IoError(where + ": no 4-byte conn or 8-byte time field");
    }
    std::uint32_t id = 0, sec = 0, nsec = 0;
    std::memcpy(&id, conn->second.data(), 4);
    std::memcpy(&sec, time->second.data(), 4);
    std::memcpy(&nsec, time->second.data() + 4, 4);
    const auto c = connections_.find(id);
    if (c == connections_.end()) throw IoError(where + ": message on unknown connection " + std::to_string(id));
    if (c->second.topic != selected_) continue;
    out.log_time = std::uint64_t{sec} * 1000000000ull + nsec;
    out.data = r->data;
    out.size = r->data_size;
    out.data_offset = r->data_at;
    out.where = in_chunk_ ? file_.string() + ": chunk at byte " + std::to_string(chunk_offset_) +
                                ", Message data record at chunk byte " + std::to_string(r->offset) +
                                "; message (offsets in the decompressed chunk)"
                          : file_.string() + ": Message data record at byte " + std::to_string(r->offset) +
                                "; message";
    return true;
  }
}

}  // namespace dammloam::io
