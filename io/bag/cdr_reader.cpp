#include "io/bag/cdr_reader.hpp"

namespace dammloam::io {
namespace {
constexpr std::size_t kEncapsulationBytes = 4;
}

CdrReader::CdrReader(const std::uint8_t* data, std::size_t size, std::uint64_t file_offset,
                     std::string where)
    : cursor_(data, size, file_offset, std::move(where)) {
  const std::uint8_t* header = cursor_.Bytes(kEncapsulationBytes, "CDR encapsulation header");
  if (header[0] != 0 || header[1] > 1) {
    cursor_.SetPosition(0, "header");
    cursor_.Fail("CDR encapsulation " + std::to_string(header[0]) + " " +
                 std::to_string(header[1]) +
                 " is not plain CDR (00 00 big-endian or 00 01 little-endian)");
  }
  big_endian_ = header[1] == 0;
  // Alignment counts from the end of the header: restart the cursor there.
  cursor_ = ByteCursor(data + kEncapsulationBytes, size - kEncapsulationBytes,
                       file_offset + kEncapsulationBytes, cursor_.where(), big_endian_);
}

bool CdrReader::Bool(std::string_view what) {
  const std::uint8_t value = U8(what);
  if (value > 1) Fail(std::string(what) + " is " + std::to_string(value) + ", not a bool");
  return value == 1;
}

void CdrReader::Align(std::size_t n, std::string_view what) {
  const std::size_t pad = (n - cursor_.position() % n) % n;
  cursor_.Skip(pad, what);
}

std::string_view CdrReader::String(std::string_view what) {
  const std::uint32_t length = U32(what);
  if (length == 0) return {};  // some writers omit the NUL of an empty string
  const auto* bytes = cursor_.Bytes(length, what);
  if (bytes[length - 1] != 0) Fail(std::string(what) + " does not end with NUL");
  return {reinterpret_cast<const char*>(bytes), length - 1};
}

std::uint32_t CdrReader::SequenceLength(std::string_view what, std::size_t min_bytes) {
  const std::uint32_t n = U32(what);
  if (min_bytes > 0 && n > cursor_.remaining() / min_bytes) {
    Fail(std::string(what) + " says " + std::to_string(n) + " elements but only " +
         std::to_string(cursor_.remaining()) + " bytes are left");
  }
  return n;
}

}  // namespace dammloam::io
