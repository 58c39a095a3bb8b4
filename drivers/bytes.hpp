#pragma once
#include <bit>
#include <cstdint>
#include <cstring>

namespace dammloam::drivers {

static_assert(std::endian::native == std::endian::little,
              "packet decoders read little-endian fields with memcpy");

// Unaligned little-endian load; the caller has checked the bounds.
template <typename T>
inline T LoadLE(const std::uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

// Network-order (big-endian) 16/32-bit loads for IP/UDP headers.
inline std::uint16_t LoadBE16(const std::uint8_t* p) {
  return static_cast<std::uint16_t>((p[0] << 8) | p[1]);
}
inline std::uint32_t LoadBE32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}

}  // namespace dammloam::drivers
