#include "io/bag/mcap_bag.hpp"

#include <algorithm>

#include "io/io_error.hpp"

namespace dammloam::io {

McapBag::McapBag(const std::vector<std::filesystem::path>& files, const McapReadOptions& options)
    : files_(files), options_(options) {
  for (std::size_t i = 0; i < files_.size(); ++i) {
    const std::filesystem::path& file = files_[i];
    auto opened = std::make_unique<McapReader>(file, options_);
    const McapReader& reader = *opened;
    for (const auto& entry : reader.channels()) {
      const McapChannel& channel = entry.second;  // a named reference: clang 14 cannot capture bindings
      const auto schema = reader.schemas().find(channel.schema_id);
      const std::string type = schema == reader.schemas().end() ? "" : schema->second.name;
      auto it = std::find_if(topics_.begin(), topics_.end(),
                             [&](const BagTopic& t) { return t.name == channel.topic; });
      if (it == topics_.end()) {
        topics_.push_back({channel.topic, type, channel.message_encoding, std::uint64_t{0}});
        it = topics_.end() - 1;
      } else if (it->type != type) {
        throw IoError(file.string() + ": topic " + channel.topic + " is recorded as both " +
                      it->type + " and " + type);
      }
      const auto count = reader.MessageCount(entry.first);
      if (count && it->message_count) {
        *it->message_count += *count;
      } else {
        it->message_count.reset();
      }
    }
    // Kept for the first Next(): a file without summary was already read once for its channels.
    if (i == 0) reader_ = std::move(opened);
  }
}

void McapBag::Select(const std::string& topic) {
  topic_ = topic;
  file_index_ = 0;
  if (reader_ && reader_file_ == 0) {
    reader_->Rewind();
  } else {
    reader_.reset();
  }
}

bool McapBag::Next(BagMessage& out) {
  while (file_index_ < files_.size()) {
    if (!reader_) {
      reader_ = std::make_unique<McapReader>(files_[file_index_], options_);
      reader_file_ = file_index_;
    }
    while (reader_->Next(message_)) {
      if (reader_->channels().at(message_.channel_id).topic != topic_) continue;
      out.log_time = message_.log_time;
      out.data = message_.data;
      out.size = message_.size;
      out.data_offset = message_.data_offset;
      out.where = message_.where;
      return true;
    }
    reader_.reset();
    ++file_index_;
  }
  return false;
}

}  // namespace dammloam::io
