#include "drivers/net/udp_receiver.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "drivers/diagnostics.hpp"

namespace dammloam::drivers {

UdpReceiver::UdpReceiver(std::uint16_t port, const std::string& address, int receive_buffer_bytes) {
  fd_ = ::socket(AF_INET, SOCK_DGRAM, 0);
  if (fd_ < 0) throw DriverError(std::string("cannot create UDP socket: ") + std::strerror(errno));
  // Sensors send faster than we may read for a moment: a large buffer avoids drops (the kernel
  // caps it at net.core.rmem_max).
  ::setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &receive_buffer_bytes, sizeof(receive_buffer_bytes));
  const int one = 1;
  ::setsockopt(fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  if (::inet_pton(AF_INET, address.c_str(), &addr.sin_addr) != 1) {
    ::close(fd_);
    throw DriverError("bad IPv4 bind address '" + address + "'");
  }
  if (::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) {
    const std::string why = std::strerror(errno);
    ::close(fd_);
    throw DriverError("cannot bind UDP " + address + ":" + std::to_string(port) + ": " + why);
  }
  socklen_t len = sizeof(addr);
  ::getsockname(fd_, reinterpret_cast<sockaddr*>(&addr), &len);
  port_ = ntohs(addr.sin_port);
}

UdpReceiver::~UdpReceiver() {
  if (fd_ >= 0) ::close(fd_);
}

bool UdpReceiver::Receive(UdpDatagram& out, std::chrono::milliseconds timeout) {
  pollfd p{fd_, POLLIN, 0};
  if (::poll(&p, 1, static_cast<int>(timeout.count())) <= 0) return false;
  out.payload.resize(65536);
  sockaddr_in from{};
  socklen_t len = sizeof(from);
  const ssize_t n = ::recvfrom(fd_, out.payload.data(), out.payload.size(), 0,
                               reinterpret_cast<sockaddr*>(&from), &len);
  if (n < 0) return false;
  out.payload.resize(static_cast<std::size_t>(n));
  out.src_ip = ntohl(from.sin_addr.s_addr);
  out.src_port = ntohs(from.sin_port);
  out.dst_port = port_;
  out.capture_time = std::chrono::duration<double>(
                         std::chrono::system_clock::now().time_since_epoch()).count();
  return true;
}

}  // namespace dammloam::drivers
