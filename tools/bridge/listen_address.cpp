#include "tools/bridge/listen_address.hpp"

#include <stdexcept>

namespace dammloam::bridge {

ListenAddress ParseListenAddress(const std::string& text) {
  const std::size_t colon = text.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == text.size()) {
    throw std::invalid_argument("--listen '" + text + "': expected ADDR:PORT, e.g. 127.0.0.1:8765");
  }
  ListenAddress address;
  address.host = text.substr(0, colon);
  if (address.host.size() > 2 && address.host.front() == '[' && address.host.back() == ']') {
    address.host = address.host.substr(1, address.host.size() - 2);
  }
  const std::string port = text.substr(colon + 1);
  if (port.find_first_not_of("0123456789") != std::string::npos || port.size() > 5 ||
      std::stoul(port) > 65535) {
    throw std::invalid_argument("--listen '" + text + "': port '" + port +
                                "' is not a number from 0 to 65535");
  }
  address.port = static_cast<std::uint16_t>(std::stoul(port));
  return address;
}

}  // namespace dammloam::bridge
