#pragma once
#include <chrono>
#include <cstdint>
#include <string>

#include "drivers/net/udp_datagram.hpp"

namespace dammloam::drivers {

// Live input: a bound UDP socket (IPv4). Owns the descriptor.
class UdpReceiver {
 public:
  // Binds `address:port` (port 0 picks a free port, see port()); throws DriverError.
  explicit UdpReceiver(std::uint16_t port, const std::string& address = "0.0.0.0",
                       int receive_buffer_bytes = 8 << 20);
  ~UdpReceiver();
  UdpReceiver(const UdpReceiver&) = delete;
  UdpReceiver& operator=(const UdpReceiver&) = delete;

  // Waits up to `timeout` for one datagram; false on timeout (or EINTR).
  bool Receive(UdpDatagram& out, std::chrono::milliseconds timeout);
  std::uint16_t port() const { return port_; }

 private:
  int fd_ = -1;
  std::uint16_t port_ = 0;
};

}  // namespace dammloam::drivers
