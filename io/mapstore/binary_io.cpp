#include "io/mapstore/binary_io.hpp"

namespace dammloam::mapstore {

std::uint64_t Fnv1a64(const std::vector<std::uint8_t>& data) {
  std::uint64_t hash = 14695981039346656037ull;
  for (std::uint8_t byte : data) {
    hash ^= byte;
    hash *= 1099511628211ull;
  }
  return hash;
}

}  // namespace dammloam::mapstore
