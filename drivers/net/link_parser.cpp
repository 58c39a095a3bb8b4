#include "drivers/net/link_parser.hpp"

#include <algorithm>

#include "drivers/bytes.hpp"

namespace dammloam::drivers {
namespace {

constexpr std::uint16_t kEtherTypeIpv4 = 0x0800;
constexpr std::uint16_t kEtherTypeVlan = 0x8100;
constexpr std::uint8_t kProtocolUdp = 17;

// Returns the offset of the IPv4 header inside `frame`, or -1 when the frame carries no IPv4.
long Ipv4Offset(LinkType link, std::span<const std::uint8_t> f, Diagnostics& diag) {
  switch (link) {
    case LinkType::kEthernet: {
      if (f.size() < 14) return diag.Count("short_link_header", "ethernet frame under 14 bytes"), -1;
      std::size_t off = 12;
      std::uint16_t type = LoadBE16(&f[off]);
      while (type == kEtherTypeVlan && f.size() >= off + 6) {  // 802.1Q tags
        off += 4;
        type = LoadBE16(&f[off]);
      }
      if (type != kEtherTypeIpv4) return diag.Count("not_ipv4"), -1;
      return static_cast<long>(off + 2);
    }
    case LinkType::kLinuxSll: {
      if (f.size() < 16) return diag.Count("short_link_header", "Linux SLL header under 16 bytes"), -1;
      if (LoadBE16(&f[14]) != kEtherTypeIpv4) return diag.Count("not_ipv4"), -1;
      return 16;
    }
    case LinkType::kNull: {
      if (f.size() < 4) return diag.Count("short_link_header", "BSD loopback header under 4 bytes"), -1;
      if (LoadLE<std::uint32_t>(&f[0]) != 2) return diag.Count("not_ipv4"), -1;  // AF_INET
      return 4;
    }
    case LinkType::kRawIp:
      return 0;
  }
  return -1;
}

}  // namespace

bool Ipv4Reassembler::Add(std::uint32_t src, std::uint32_t dst, std::uint16_t id,
                          std::uint8_t protocol, std::size_t offset_bytes, bool more_fragments,
                          std::span<const std::uint8_t> data, std::vector<std::uint8_t>& ip_payload,
                          Diagnostics& diag) {
  const Key key{src, dst, id, protocol};
  auto it = pending_.find(key);
  if (it == pending_.end()) {
    if (pending_.size() >= max_pending_) {
      auto oldest = pending_.begin();
      for (auto j = pending_.begin(); j != pending_.end(); ++j) {
        if (j->second.arrival < oldest->second.arrival) oldest = j;
      }
      pending_.erase(oldest);
      diag.Count("fragments_evicted", "incomplete fragmented datagram dropped (too many pending)");
    }
    it = pending_.emplace(key, Pending{}).first;
    it->second.arrival = arrivals_++;
  }
  Pending& p = it->second;
  p.pieces[offset_bytes].assign(data.begin(), data.end());
  if (!more_fragments) p.total = offset_bytes + data.size();
  if (p.total == 0) return false;

  // Complete when the pieces cover [0, total) without holes.
  std::size_t covered = 0;
  for (const auto& [off, bytes] : p.pieces) {
    if (off > covered) return false;
    covered = std::max(covered, off + bytes.size());
  }
  if (covered < p.total) return false;

  ip_payload.assign(p.total, 0);
  for (const auto& [off, bytes] : p.pieces) {
    // A piece past the end (a later fragment than the last one claims) holds nothing of the
    // datagram, and begin() + off would point beyond the vector.
    if (off >= p.total) continue;
    const std::size_t n = std::min(bytes.size(), p.total - off);
    std::copy_n(bytes.begin(), n, ip_payload.begin() + static_cast<long>(off));
  }
  pending_.erase(it);
  diag.Count("datagrams_reassembled");
  return true;
}

bool ParseLinkFrame(LinkType link, std::span<const std::uint8_t> f, Ipv4Reassembler& reassembler,
                    UdpDatagram& out, Diagnostics& diag) {
  const long ip_off = Ipv4Offset(link, f, diag);
  if (ip_off < 0) return false;
  auto ip = f.subspan(static_cast<std::size_t>(ip_off));
  if (ip.size() < 20 || (ip[0] >> 4) != 4) {
    diag.Count("bad_ip_header", "IPv4 header truncated or wrong version");
    return false;
  }
  const std::size_t ihl = static_cast<std::size_t>(ip[0] & 0x0F) * 4;
  const std::size_t total_len = LoadBE16(&ip[2]);
  if (ihl < 20 || total_len < ihl || total_len > ip.size()) {
    diag.Count("bad_ip_header", "IPv4 header length or total length inconsistent with the frame");
    return false;
  }
  if (ip[9] != kProtocolUdp) {
    diag.Count("not_udp");
    return false;
  }
  const std::uint32_t src = LoadBE32(&ip[12]);
  const std::uint32_t dst = LoadBE32(&ip[16]);
  auto ip_payload = ip.subspan(ihl, total_len - ihl);

  const std::uint16_t flags_frag = LoadBE16(&ip[6]);
  const bool more = (flags_frag & 0x2000) != 0;
  const std::size_t frag_off = static_cast<std::size_t>(flags_frag & 0x1FFF) * 8;
  std::vector<std::uint8_t> whole;
  if (more || frag_off != 0) {
    diag.Count("ip_fragments");
    if (!reassembler.Add(src, dst, LoadBE16(&ip[4]), ip[9], frag_off, more, ip_payload, whole, diag)) {
      return false;
    }
    ip_payload = whole;
  }

  if (ip_payload.size() < 8) {
    diag.Count("bad_udp_header", "UDP header truncated");
    return false;
  }
  const std::size_t udp_len = LoadBE16(&ip_payload[4]);
  if (udp_len < 8 || udp_len > ip_payload.size()) {
    diag.Count("bad_udp_header", "UDP length field inconsistent with the IP payload");
    return false;
  }
  out.src_ip = src;
  out.dst_ip = dst;
  out.src_port = LoadBE16(&ip_payload[0]);
  out.dst_port = LoadBE16(&ip_payload[2]);
  out.payload.assign(ip_payload.begin() + 8, ip_payload.begin() + static_cast<long>(udp_len));
  return true;
}

}  // namespace dammloam::drivers
