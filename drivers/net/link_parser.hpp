#pragma once
#include <cstddef>
#include <cstdint>
#include <map>
#include <span>
#include <tuple>
#include <vector>

#include "drivers/diagnostics.hpp"
#include "drivers/net/udp_datagram.hpp"

namespace dammloam::drivers {

// Link-layer header types we understand (values of pcap's DLT_* / LINKTYPE_*).
enum class LinkType : int { kNull = 0, kEthernet = 1, kRawIp = 101, kLinuxSll = 113 };

// Reassembles fragmented IPv4 datagrams. Bounded: at most `max_pending` incomplete datagrams
// are kept; the oldest is dropped (and counted) when a new one would exceed that.
class Ipv4Reassembler {
 public:
  explicit Ipv4Reassembler(std::size_t max_pending = 64) : max_pending_(max_pending) {}

  // Adds one fragment (the IP payload after the IP header). Returns true and fills `ip_payload`
  // once every fragment of that datagram has arrived.
  bool Add(std::uint32_t src, std::uint32_t dst, std::uint16_t id, std::uint8_t protocol,
           std::size_t offset_bytes, bool more_fragments, std::span<const std::uint8_t> data,
           std::vector<std::uint8_t>& ip_payload, Diagnostics& diag);

 private:
  using Key = std::tuple<std::uint32_t, std::uint32_t, std::uint16_t, std::uint8_t>;
  struct Pending {
    std::map<std::size_t, std::vector<std::uint8_t>> pieces;  // offset -> bytes
    std::size_t total = 0;                                     // known once the last piece came
    std::uint64_t arrival = 0;
  };
  std::size_t max_pending_;
  std::uint64_t arrivals_ = 0;
  std::map<Key, Pending> pending_;
};

// Extracts the IPv4/UDP datagram from one captured link-layer frame. Anything else (ARP, IPv6,
// TCP, truncated headers, bad lengths) is counted in `diag` and yields false; a fragment
// yields false until its datagram is complete.
bool ParseLinkFrame(LinkType link, std::span<const std::uint8_t> frame, Ipv4Reassembler& reassembler,
                    UdpDatagram& out, Diagnostics& diag);

}  // namespace dammloam::drivers
