// The pcap reader (PcapReader: libpcap, link layers, IPv4 reassembly, UDP), as dammloam-driver
// reads a capture file.
//
// Input: the whole capture file (pcap or pcapng), written to a scratch file since PcapReader
// takes a path. A file libpcap cannot open or with an unknown link type must throw DriverError;
// everything else in the file is counted, never thrown.
#include <cstdint>

#include "drivers/net/pcap_reader.hpp"
#include "tests/fuzz/fuzz_support.hpp"

namespace {

using namespace dammloam;
using namespace dammloam::drivers;
using namespace dammloam::fuzz;

void Run(Input& in) {
  const std::span<const std::uint8_t> bytes = in.Rest();
  static const fs::path file = ScratchDir() / "input.pcap";
  WriteFile(file, bytes);
  // The filter is exercised on the port Ouster uses; a datagram for another port is skipped.
  const PcapFilter filter = bytes.size() % 2 == 0 ? PcapFilter{} : PcapFilter{7502};
  try {
    PcapReader reader(file, filter);
    UdpDatagram d;
    for (int i = 0; i < 100000 && reader.Next(d); ++i) {
      if (filter.dst_port && d.dst_port != *filter.dst_port) Finding("PcapReader ignored its port filter");
      if (d.payload.size() > 65535) Finding("PcapReader returned a UDP payload over 64 KiB");
    }
  } catch (const DriverError&) {
    // documented: unreadable capture or unsupported link type
  }
}

// --- seeds --------------------------------------------------------------------------------

void PutBE16(std::vector<std::uint8_t>& b, std::uint16_t v) {
  b.push_back(static_cast<std::uint8_t>(v >> 8));
  b.push_back(static_cast<std::uint8_t>(v));
}

// IPv4 header (no options) + payload; `frag` is the flags/fragment-offset word.
std::vector<std::uint8_t> Ipv4(std::span<const std::uint8_t> payload, std::uint16_t frag, std::uint16_t id) {
  std::vector<std::uint8_t> ip = {0x45, 0};
  PutBE16(ip, static_cast<std::uint16_t>(20 + payload.size()));
  PutBE16(ip, id);
  PutBE16(ip, frag);
  ip.insert(ip.end(), {64, 17, 0, 0, 192, 168, 1, 201, 192, 168, 1, 100});
  ip.insert(ip.end(), payload.begin(), payload.end());
  return ip;
}

std::vector<std::uint8_t> Udp(std::uint16_t dst_port, std::size_t payload_size) {
  std::vector<std::uint8_t> udp;
  PutBE16(udp, 7502);
  PutBE16(udp, dst_port);
  PutBE16(udp, static_cast<std::uint16_t>(8 + payload_size));
  PutBE16(udp, 0);
  for (std::size_t i = 0; i < payload_size; ++i) udp.push_back(static_cast<std::uint8_t>(i * 7));
  return udp;
}

std::vector<std::uint8_t> Ethernet(std::span<const std::uint8_t> ip, bool vlan) {
  std::vector<std::uint8_t> f(12, 0x11);
  if (vlan) f.insert(f.end(), {0x81, 0x00, 0x00, 0x05});
  f.insert(f.end(), {0x08, 0x00});
  f.insert(f.end(), ip.begin(), ip.end());
  return f;
}

Bytes PcapHeader(std::uint32_t magic, std::uint32_t linktype) {
  Bytes b;
  b.Put(magic).Put<std::uint16_t>(2).Put<std::uint16_t>(4).Put<std::int32_t>(0).Put<std::uint32_t>(0);
  b.Put<std::uint32_t>(65535).Put(linktype);
  return b;
}

void Record(Bytes& b, std::span<const std::uint8_t> frame, std::uint32_t sec) {
  b.Put(sec).Put<std::uint32_t>(1234).Put(static_cast<std::uint32_t>(frame.size()));
  b.Put(static_cast<std::uint32_t>(frame.size())).Append(frame);
}

void WriteSeeds(const fs::path& dir, const std::optional<fs::path>& shared) {
  const auto udp = Udp(7502, 64);
  const auto ip = Ipv4(udp, 0, 1);
  {  // Ethernet, plain and VLAN, a fragmented datagram, a non-UDP frame; microsecond magic.
    Bytes b = PcapHeader(0xa1b2c3d4, 1);
    Record(b, Ethernet(ip, false), 100);
    Record(b, Ethernet(ip, true), 101);
    const auto big = Udp(7502, 100);
    const auto first = Ipv4(std::span(big).first(56), 0x2000, 9);
    const auto second = Ipv4(std::span(big).subspan(56), 56 / 8, 9);
    Record(b, Ethernet(second, false), 102);
    Record(b, Ethernet(first, false), 102);
    auto tcp = ip;
    tcp[9] = 6;
    Record(b, Ethernet(tcp, false), 103);
    Record(b, Ethernet(Ipv4(Udp(2368, 16), 0, 2), false), 104);
    WriteSeed(dir, "ethernet", b.data);
  }
  {  // Linux SLL, nanosecond magic.
    Bytes b = PcapHeader(0xa1b23c4d, 113);
    std::vector<std::uint8_t> sll(14, 0);
    sll.insert(sll.end(), {0x08, 0x00});
    sll.insert(sll.end(), ip.begin(), ip.end());
    Record(b, sll, 200);
    WriteSeed(dir, "linux-sll", b.data);
  }
  {  // BSD loopback (AF_INET = 2, host order) and raw IP.
    Bytes b = PcapHeader(0xa1b2c3d4, 0);
    std::vector<std::uint8_t> null = {2, 0, 0, 0};
    null.insert(null.end(), ip.begin(), ip.end());
    Record(b, null, 300);
    WriteSeed(dir, "bsd-loopback", b.data);
    Bytes raw = PcapHeader(0xa1b2c3d4, 101);
    Record(raw, ip, 301);
    WriteSeed(dir, "raw-ip", raw.data);
  }
  {  // pcapng: section header, interface description (Ethernet), one enhanced packet block.
    Bytes b;
    b.Put<std::uint32_t>(0x0A0D0D0A).Put<std::uint32_t>(28).Put<std::uint32_t>(0x1A2B3C4D);
    b.Put<std::uint16_t>(1).Put<std::uint16_t>(0).Put<std::int64_t>(-1).Put<std::uint32_t>(28);
    b.Put<std::uint32_t>(1).Put<std::uint32_t>(20).Put<std::uint16_t>(1).Put<std::uint16_t>(0);
    b.Put<std::uint32_t>(65535).Put<std::uint32_t>(20);
    const auto frame = Ethernet(ip, false);
    const std::uint32_t padded = static_cast<std::uint32_t>((frame.size() + 3) / 4 * 4);
    b.Put<std::uint32_t>(6).Put<std::uint32_t>(32 + padded).Put<std::uint32_t>(0);
    b.Put<std::uint32_t>(0).Put<std::uint32_t>(1000).Put(static_cast<std::uint32_t>(frame.size()));
    b.Put(static_cast<std::uint32_t>(frame.size())).Append(frame);
    b.Append(std::vector<std::uint8_t>(padded - frame.size(), 0)).Put<std::uint32_t>(32 + padded);
    WriteSeed(dir, "pcapng", b.data);
  }
  if (!shared) return;
  // Real captures: the file header and the first records, up to ~60 KB each.
  std::error_code ec;
  for (const auto& e : fs::recursive_directory_iterator(*shared, ec)) {
    if (e.path().extension() != ".pcap") continue;
    const auto bytes = ReadFile(e.path());
    if (bytes.size() < 24) continue;
    std::size_t end = 24;
    const bool swapped = bytes[0] == 0xa1;  // big-endian file
    while (end + 16 <= bytes.size()) {
      std::uint32_t caplen = 0;
      std::memcpy(&caplen, &bytes[end + 8], 4);
      if (swapped) caplen = __builtin_bswap32(caplen);
      if (end + 16 + caplen > bytes.size() || end + 16 + caplen > 60000) break;
      end += 16 + caplen;
    }
    WriteSeed(dir, "real-" + e.path().stem().string(), std::span(bytes).first(end));
  }
}

}  // namespace

DAMMLOAM_FUZZ_TARGET(WriteSeeds, Run)
