#pragma once
#include <cstdint>
#include <cstring>
#include <string>
#include <type_traits>
#include <vector>

#include "io/io_error.hpp"

namespace dammloam::mapstore {

// Little-endian (host order; the project targets x86-64/arm64) append-only byte buffer.
class ByteWriter {
 public:
  template <typename T>
  void Put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(&value);
    data_.insert(data_.end(), bytes, bytes + sizeof(T));
  }
  template <typename T>
  void PutArray(const T* values, std::size_t count) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(values);
    data_.insert(data_.end(), bytes, bytes + count * sizeof(T));
  }
  const std::vector<std::uint8_t>& data() const { return data_; }

 private:
  std::vector<std::uint8_t> data_;
};

// Bounds-checked reader: every short read throws IoError naming the file and byte offset.
class ByteReader {
 public:
  ByteReader(const std::vector<std::uint8_t>& data, std::string file)
      : data_(data), file_(std::move(file)) {}

  template <typename T>
  T Get(const char* what) {
    T value;
    GetArray(&value, 1, what);
    return value;
  }
  template <typename T>
  void GetArray(T* out, std::size_t count, const char* what) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (count > (data_.size() - offset_) / sizeof(T)) {
      throw io::IoError(file_ + ": truncated while reading " + what + " at byte " +
                        std::to_string(offset_));
    }
    if (count == 0) return;  // `out` may be null then (an empty Eigen matrix): no memcpy
    std::memcpy(out, data_.data() + offset_, count * sizeof(T));
    offset_ += count * sizeof(T);
  }
  std::size_t offset() const { return offset_; }
  std::size_t remaining() const { return data_.size() - offset_; }
  const std::string& file() const { return file_; }

 private:
  const std::vector<std::uint8_t>& data_;
  std::string file_;
  std::size_t offset_ = 0;
};

// FNV-1a 64-bit: detects corruption of keyframes.bin (not an integrity guarantee against intent).
std::uint64_t Fnv1a64(const std::vector<std::uint8_t>& data);

}  // namespace dammloam::mapstore
