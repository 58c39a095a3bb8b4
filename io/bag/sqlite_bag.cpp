#include "io/bag/sqlite_bag.hpp"

#include <sqlite3.h>

#include <algorithm>

#include "io/bag/decompress.hpp"
#include "io/io_error.hpp"

namespace dammloam::io {
namespace {

std::string Column(sqlite3_stmt* statement, int column) {
  const unsigned char* text = sqlite3_column_text(statement, column);
  return text != nullptr ? reinterpret_cast<const char*>(text) : "";
}

}  // namespace

SqliteBag::SqliteBag(const Rosbag2Metadata& metadata, const BagReadOptions& options)
    : metadata_(metadata), options_(options) {
  if (!metadata_.compression_format.empty() && metadata_.compression_mode != "MESSAGE") {
    throw IoError(metadata_.files.front().string() + ": the bag is compressed per file (" +
                  metadata_.compression_format + ", mode " + metadata_.compression_mode +
                  "); decompress it first (ros2 bag decompress)");
  }
  if (!metadata_.compression_format.empty() && metadata_.compression_format != "zstd") {
    throw IoError(metadata_.files.front().string() + ": unknown compression '" +
                  metadata_.compression_format + "' (supported: zstd)");
  }
  // The topics tables are the truth (metadata.yaml of a recording that was killed is stale);
  // message counts come from metadata.yaml when it has them.
  for (std::size_t i = 0; i < metadata_.files.size(); ++i) {
    OpenFile(i);
    sqlite3_stmt* statement = nullptr;
    if (sqlite3_prepare_v2(db_, "SELECT name, type, serialization_format FROM topics", -1,
                           &statement, nullptr) != SQLITE_OK) {
      const std::string error = sqlite3_errmsg(db_);
      Close();
      throw IoError(metadata_.files[i].string() + ": no rosbag2 topics table (" + error + ")");
    }
    while (sqlite3_step(statement) == SQLITE_ROW) {
      const std::string name = Column(statement, 0);
      if (std::any_of(topics_.begin(), topics_.end(), [&](const BagTopic& t) { return t.name == name; })) {
        continue;
      }
      BagTopic topic{name, Column(statement, 1), Column(statement, 2), std::nullopt};
      for (const BagTopic& listed : metadata_.topics) {
        if (listed.name == name) topic.message_count = listed.message_count;
      }
      topics_.push_back(std::move(topic));
    }
    sqlite3_finalize(statement);
    Close();
  }
}

SqliteBag::~SqliteBag() { Close(); }

void SqliteBag::Close() {
  if (query_ != nullptr) sqlite3_finalize(query_);
  if (db_ != nullptr) sqlite3_close(db_);
  query_ = nullptr;
  db_ = nullptr;
}

void SqliteBag::OpenFile(std::size_t index) {
  Close();
  const std::filesystem::path& file = metadata_.files[index];
  if (!std::filesystem::is_regular_file(file)) {
    throw IoError(file.string() + ": listed in metadata.yaml but missing");
  }
  if (sqlite3_open_v2(file.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
    const std::string error = db_ != nullptr ? sqlite3_errmsg(db_) : "out of memory";
    Close();
    throw IoError(file.string() + ": cannot open as SQLite (" + error + ")");
  }
}

void SqliteBag::Select(const std::string& topic) {
  Close();
  topic_ = topic;
  file_index_ = 0;
}

bool SqliteBag::Next(BagMessage& out) {
  while (file_index_ < metadata_.files.size()) {
    const std::filesystem::path& file = metadata_.files[file_index_];
    if (query_ == nullptr) {
      OpenFile(file_index_);
      // Row order is recording order (the recorder inserts as messages arrive) and needs no
      // sort: ORDER BY timestamp would make SQLite sort the blobs of a bag larger than memory.
      const char* sql =
          "SELECT m.id, m.timestamp, m.data FROM messages m JOIN topics t ON m.topic_id = t.id "
          "WHERE t.name = ? ORDER BY m.id";
      if (sqlite3_prepare_v2(db_, sql, -1, &query_, nullptr) != SQLITE_OK) {
        const std::string error = sqlite3_errmsg(db_);
        Close();
        throw IoError(file.string() + ": not a rosbag2 database (" + error + ")");
      }
      sqlite3_bind_text(query_, 1, topic_.c_str(), -1, SQLITE_TRANSIENT);
    }
    const int step = sqlite3_step(query_);
    if (step == SQLITE_ROW) {
      const sqlite3_int64 id = sqlite3_column_int64(query_, 0);
      out.where = file.string() + ": message id " + std::to_string(id);
      out.log_time = static_cast<std::uint64_t>(sqlite3_column_int64(query_, 1));
      const void* blob = sqlite3_column_blob(query_, 2);
      const int size = sqlite3_column_bytes(query_, 2);
      out.data = static_cast<const std::uint8_t*>(blob);
      out.size = static_cast<std::size_t>(size);
      out.data_offset = 0;
      if (metadata_.compression_mode == "MESSAGE") {
        DecompressZstdFrame(out.data, out.size, options_.max_record_bytes, decompressed_,
                            out.where);
        out.data = decompressed_.data();
        out.size = decompressed_.size();
      }
      return true;
    }
    if (step != SQLITE_DONE) {
      const std::string error = sqlite3_errmsg(db_);
      Close();
      throw IoError(file.string() + ": reading messages failed (" + error + ")");
    }
    Close();
    ++file_index_;
  }
  return false;
}

}  // namespace dammloam::io
