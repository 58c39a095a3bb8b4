#pragma once
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

#include "io/io_error.hpp"

namespace dammloam::io {

// Bounds-checked reading of a record or message held in memory. Every overrun throws IoError
// naming `where` (file and record) and the byte offset in the file, so a truncated or lying
// length field is an error message, never a read past the buffer.
class ByteCursor {
 public:
  // `file_offset`: where data[0] sits in the file (for messages); `where`: "file: Chunk record".
  ByteCursor(const std::uint8_t* data, std::size_t size, std::uint64_t file_offset,
             std::string where, bool big_endian = false)
      : data_(data), size_(size), file_offset_(file_offset), where_(std::move(where)),
        big_endian_(big_endian) {}

  std::size_t position() const { return pos_; }
  std::size_t remaining() const { return size_ - pos_; }
  std::uint64_t file_offset() const { return file_offset_ + pos_; }
  const std::string& where() const { return where_; }
  void set_big_endian(bool big) { big_endian_ = big; }

  template <typename T>
  T Read(std::string_view what) {
    Need(sizeof(T), what);
    T value;
    std::memcpy(&value, data_ + pos_, sizeof(T));
    if (big_endian_ != (std::endian::native == std::endian::big)) value = Swap(value);
    pos_ += sizeof(T);
    return value;
  }

  // n bytes, not copied: valid while the buffer lives.
  const std::uint8_t* Bytes(std::uint64_t n, std::string_view what) {
    Need(n, what);
    const std::uint8_t* p = data_ + pos_;
    pos_ += static_cast<std::size_t>(n);
    return p;
  }
  void Skip(std::uint64_t n, std::string_view what) { Bytes(n, what); }
  void SetPosition(std::size_t pos, std::string_view what) {
    if (pos > size_) Fail(std::string(what) + " lies beyond the end");
    pos_ = pos;
  }

  [[noreturn]] void Fail(const std::string& problem) const {
    throw IoError(where_ + " at byte " + std::to_string(file_offset()) + ": " + problem);
  }

 private:
  void Need(std::uint64_t n, std::string_view what) const {
    if (n > size_ - pos_) {
      Fail("truncated: " + std::string(what) + " needs " + std::to_string(n) + " bytes, " +
           std::to_string(size_ - pos_) + " left");
    }
  }
  template <typename T>
  static T Swap(T value) {
    std::uint8_t bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
    std::memcpy(&value, bytes, sizeof(T));
    return value;
  }

  const std::uint8_t* data_;
  std::size_t size_;
  std::uint64_t file_offset_;
  std::string where_;
  bool big_endian_;
  std::size_t pos_ = 0;
};

}  // namespace dammloam::io
