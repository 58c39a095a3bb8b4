#pragma once
// --listen ADDR:PORT, checked, with an error naming what is wrong.
#include <cstdint>
#include <string>

namespace dammloam::bridge {

struct ListenAddress {
  std::string host;
  std::uint16_t port = 0;
};

// "127.0.0.1:8765", "0.0.0.0:0", "[::1]:8765". Throws std::invalid_argument naming the problem.
ListenAddress ParseListenAddress(const std::string& text);

}  // namespace dammloam::bridge
