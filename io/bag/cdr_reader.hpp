#pragma once
#include <cstdint>
#include <string>
#include <string_view>

#include "io/bag/byte_cursor.hpp"

namespace dammloam::io {

// A ROS 2 message serialised as plain CDR (XCDR1), as rmw and rosbag2 store it: a 4-byte
// encapsulation header (00 00 big-endian, 00 01 little-endian, then 2 option bytes), then the
// members, each aligned to its own size counted from the end of that header.
class CdrReader {
 public:
  // Reads the encapsulation header; IoError for a short message or another representation
  // (parameter lists, XCDR2): PointCloud2 and the messages we read are final types.
  CdrReader(const std::uint8_t* data, std::size_t size, std::uint64_t file_offset,
            std::string where);

  bool big_endian() const { return big_endian_; }

  std::uint8_t U8(std::string_view what) { return cursor_.Read<std::uint8_t>(what); }
  bool Bool(std::string_view what);
  std::uint16_t U16(std::string_view what) { return Aligned<std::uint16_t>(what); }
  std::uint32_t U32(std::string_view what) { return Aligned<std::uint32_t>(what); }
  std::int32_t I32(std::string_view what) { return Aligned<std::int32_t>(what); }
  std::uint64_t U64(std::string_view what) { return Aligned<std::uint64_t>(what); }
  double F64(std::string_view what) { return Aligned<double>(what); }
  // string: uint32 length including the terminating NUL, the bytes, the NUL.
  std::string_view String(std::string_view what);
  // sequence length, checked against the bytes left (each element takes at least min_bytes).
  std::uint32_t SequenceLength(std::string_view what, std::size_t min_bytes);
  // n raw bytes (octet sequences), not copied.
  const std::uint8_t* Bytes(std::uint32_t n, std::string_view what) {
    return cursor_.Bytes(n, what);
  }
  void Align(std::size_t n, std::string_view what);
  std::size_t remaining() const { return cursor_.remaining(); }
  [[noreturn]] void Fail(const std::string& problem) const { cursor_.Fail(problem); }

 private:
  template <typename T>
  T Aligned(std::string_view what) {
    Align(sizeof(T), what);
    return cursor_.Read<T>(what);
  }

  ByteCursor cursor_;
  bool big_endian_ = false;
};

}  // namespace dammloam::io
