#pragma once
#include <cstdint>
#include <vector>

namespace dammloam::drivers {

// One UDP payload as the sensor sent it, with where and when it was seen.
struct UdpDatagram {
  double capture_time = 0.0;  // seconds (pcap record time or receive time)
  std::uint32_t src_ip = 0;   // host order
  std::uint32_t dst_ip = 0;
  std::uint16_t src_port = 0;
  std::uint16_t dst_port = 0;
  std::vector<std::uint8_t> payload;
};

}  // namespace dammloam::drivers
