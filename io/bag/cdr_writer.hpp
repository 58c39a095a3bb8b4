#pragma once
#include <cstdint>
#include <cstring>
#include <string_view>
#include <vector>

namespace dammloam::io {

// Plain little-endian CDR (XCDR1) as rmw writes ROS 2 messages: encapsulation 00 01 00 00,
// members aligned to their size from the end of that header.
class CdrWriter {
 public:
  CdrWriter() { bytes_ = {0x00, 0x01, 0x00, 0x00}; }

  void U8(std::uint8_t v) { Put(v); }
  void Bool(bool v) { Put(static_cast<std::uint8_t>(v ? 1 : 0)); }
  void U32(std::uint32_t v) { Put(v); }
  void I32(std::int32_t v) { Put(v); }
  void F32(float v) { Put(v); }
  void F64(double v) { Put(v); }
  void String(std::string_view s) {
    U32(static_cast<std::uint32_t>(s.size() + 1));
    bytes_.insert(bytes_.end(), s.begin(), s.end());
    bytes_.push_back(0);
  }
  // uint8[] / octet sequences.
  void Bytes(const std::vector<std::uint8_t>& data) {
    U32(static_cast<std::uint32_t>(data.size()));
    bytes_.insert(bytes_.end(), data.begin(), data.end());
  }
  const std::vector<std::uint8_t>& bytes() const { return bytes_; }
  std::vector<std::uint8_t> Take() { return std::move(bytes_); }

 private:
  template <typename T>
  void Put(T v) {
    const std::size_t pad = (sizeof(T) - (bytes_.size() - 4) % sizeof(T)) % sizeof(T);
    bytes_.insert(bytes_.end(), pad, 0);
    const std::size_t at = bytes_.size();
    bytes_.resize(at + sizeof(T));
    std::memcpy(bytes_.data() + at, &v, sizeof(T));  // little-endian hosts (mcap_writer.cpp)
  }

  std::vector<std::uint8_t> bytes_;
};

}  // namespace dammloam::io
