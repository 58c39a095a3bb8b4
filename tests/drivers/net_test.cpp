// Link-layer / IPv4 / UDP parsing and pcap reading, on hand-built frames and real captures.
#include <gtest/gtest.h>

#include <unistd.h>

#include <fstream>

#include "drivers/net/link_parser.hpp"
#include "drivers/net/pcap_reader.hpp"
#include "tests/support/data_dir.hpp"
#include "tests/support/temp_dir.hpp"

namespace dammloam::drivers {
namespace {

using Bytes = std::vector<std::uint8_t>;

// a followed by b (copies into a pre-sized vector: GCC 12 warns falsely on small inserts).
Bytes Concat(const Bytes& a, const Bytes& b) {
  Bytes out(a.size() + b.size());
  std::copy(a.begin(), a.end(), out.begin());
  std::copy(b.begin(), b.end(), out.begin() + static_cast<long>(a.size()));
  return out;
}

void PutBE16(Bytes& b, std::size_t at, std::uint16_t v) {
  b[at] = static_cast<std::uint8_t>(v >> 8);
  b[at + 1] = static_cast<std::uint8_t>(v & 0xFF);
}

// IPv4 packet: header (20 B) + `ip_payload`, with id/flags/fragment offset as given.
Bytes Ipv4(const Bytes& ip_payload, std::uint16_t id = 1, bool more = false, std::size_t frag_offset = 0,
           std::uint8_t protocol = 17) {
  Bytes ip(20, 0);
  ip[0] = 0x45;
  PutBE16(ip, 2, static_cast<std::uint16_t>(20 + ip_payload.size()));
  PutBE16(ip, 4, id);
  PutBE16(ip, 6, static_cast<std::uint16_t>((more ? 0x2000 : 0) | (frag_offset / 8)));
  ip[8] = 64;
  ip[9] = protocol;
  ip[12] = 10; ip[15] = 1;    // 10.0.0.1
  ip[16] = 127; ip[19] = 1;   // 127.0.0.1
  return Concat(ip, ip_payload);
}

Bytes Udp(const Bytes& payload, std::uint16_t src, std::uint16_t dst) {
  Bytes u(8, 0);
  PutBE16(u, 0, src);
  PutBE16(u, 2, dst);
  PutBE16(u, 4, static_cast<std::uint16_t>(8 + payload.size()));
  return Concat(u, payload);
}

Bytes Ethernet(const Bytes& ip, std::uint16_t ether_type = 0x0800) {
  Bytes f(14, 0);
  PutBE16(f, 12, ether_type);
  return Concat(f, ip);
}

Bytes Payload(std::size_t n) {
  Bytes p(n);
  for (std::size_t i = 0; i < n; ++i) p[i] = static_cast<std::uint8_t>(i * 7 + 3);
  return p;
}

TEST(LinkParser, EthernetUdp) {
  const Bytes payload = Payload(100);
  Ipv4Reassembler r;
  Diagnostics diag;
  UdpDatagram d;
  ASSERT_TRUE(ParseLinkFrame(LinkType::kEthernet, Ethernet(Ipv4(Udp(payload, 2368, 7502))), r, d, diag));
  EXPECT_EQ(d.src_port, 2368);
  EXPECT_EQ(d.dst_port, 7502);
  EXPECT_EQ(d.src_ip, 0x0A000001u);
  EXPECT_EQ(d.payload, payload);
}

TEST(LinkParser, LinuxCookedAndVlan) {
  const Bytes payload = Payload(40);
  const Bytes ip = Ipv4(Udp(payload, 1, 2));
  Bytes sll(16, 0);
  PutBE16(sll, 14, 0x0800);
  sll = Concat(sll, ip);
  Ipv4Reassembler r;
  Diagnostics diag;
  UdpDatagram d;
  ASSERT_TRUE(ParseLinkFrame(LinkType::kLinuxSll, sll, r, d, diag));
  EXPECT_EQ(d.payload, payload);

  Bytes vlan(18, 0);
  PutBE16(vlan, 12, 0x8100);
  PutBE16(vlan, 16, 0x0800);
  vlan = Concat(vlan, ip);
  ASSERT_TRUE(ParseLinkFrame(LinkType::kEthernet, vlan, r, d, diag));
  EXPECT_EQ(d.payload, payload);
}

TEST(LinkParser, ReassemblesFragmentsInAnyOrder) {
  const Bytes payload = Payload(3000);
  const Bytes udp = Udp(payload, 7502, 7502);
  // Three fragments of 1480, 1480 and the rest; delivered last, first, middle.
  std::vector<Bytes> frames;
  for (std::size_t off = 0; off < udp.size(); off += 1480) {
    const std::size_t n = std::min<std::size_t>(1480, udp.size() - off);
    frames.push_back(Ethernet(Ipv4(Bytes(udp.begin() + static_cast<long>(off), udp.begin() + static_cast<long>(off + n)), 77,
                                   off + n < udp.size(), off)));
  }
  ASSERT_EQ(frames.size(), 3u);
  Ipv4Reassembler r;
  Diagnostics diag;
  UdpDatagram d;
  EXPECT_FALSE(ParseLinkFrame(LinkType::kEthernet, frames[2], r, d, diag));
  EXPECT_FALSE(ParseLinkFrame(LinkType::kEthernet, frames[0], r, d, diag));
  ASSERT_TRUE(ParseLinkFrame(LinkType::kEthernet, frames[1], r, d, diag));
  EXPECT_EQ(d.payload, payload);
  EXPECT_EQ(diag.Get("datagrams_reassembled"), 1u);
}

TEST(LinkParser, RejectsDamagedAndForeignFrames) {
  Ipv4Reassembler r;
  Diagnostics diag;
  UdpDatagram d;
  const Bytes good = Ethernet(Ipv4(Udp(Payload(64), 1, 2)));
  EXPECT_FALSE(ParseLinkFrame(LinkType::kEthernet, Bytes(good.begin(), good.begin() + 30), r, d, diag));  // cut
  EXPECT_FALSE(ParseLinkFrame(LinkType::kEthernet, Bytes(8, 0), r, d, diag));
  EXPECT_FALSE(ParseLinkFrame(LinkType::kEthernet, Ethernet(Ipv4(Payload(30), 1, false, 0, 6)), r, d, diag));  // TCP
  EXPECT_FALSE(ParseLinkFrame(LinkType::kEthernet, Ethernet(Payload(40), 0x86DD), r, d, diag));               // IPv6
  Bytes bad_udp_len = good;
  PutBE16(bad_udp_len, 14 + 20 + 4, 5000);
  EXPECT_FALSE(ParseLinkFrame(LinkType::kEthernet, bad_udp_len, r, d, diag));
  EXPECT_EQ(diag.Get("bad_ip_header"), 1u);
  EXPECT_EQ(diag.Get("short_link_header"), 1u);
  EXPECT_EQ(diag.Get("not_udp"), 1u);
  EXPECT_EQ(diag.Get("not_ipv4"), 1u);
  EXPECT_EQ(diag.Get("bad_udp_header"), 1u);
}

// A classic pcap file written by hand: Linux SLL link type, one good record, one record whose
// capture was cut short (caplen < len), and one fragmented datagram.
TEST(PcapReader, ReadsSllCaptureWithTruncatedRecordAndFragments) {
  const test::TempDir tmp;
  const auto file = tmp / "sll.pcap";
  std::ofstream out(file, std::ios::binary);
  auto u32 = [&](std::uint32_t v) { out.write(reinterpret_cast<const char*>(&v), 4); };
  auto u16 = [&](std::uint16_t v) { out.write(reinterpret_cast<const char*>(&v), 2); };
  u32(0xA1B2C3D4); u16(2); u16(4); u32(0); u32(0); u32(65535); u32(113);  // LINKTYPE_LINUX_SLL
  auto sll = [](const Bytes& ip) {
    Bytes f(16, 0);
    f[14] = 0x08;
    return Concat(f, ip);
  };
  auto record = [&](const Bytes& frame, std::uint32_t sec, std::size_t caplen) {
    u32(sec); u32(500000); u32(static_cast<std::uint32_t>(caplen)); u32(static_cast<std::uint32_t>(frame.size()));
    out.write(reinterpret_cast<const char*>(frame.data()), static_cast<std::streamsize>(caplen));
  };
  const Bytes a = Payload(200), b = Payload(2000);
  record(sll(Ipv4(Udp(a, 5, 7502))), 10, sll(Ipv4(Udp(a, 5, 7502))).size());
  const Bytes cut = sll(Ipv4(Udp(a, 5, 7502)));
  record(cut, 11, 60);
  const Bytes udp_b = Udp(b, 5, 7502);
  record(sll(Ipv4(Bytes(udp_b.begin(), udp_b.begin() + 1480), 9, true, 0)), 12, sll(Ipv4(Bytes(udp_b.begin(), udp_b.begin() + 1480), 9, true, 0)).size());
  const Bytes tail(udp_b.begin() + 1480, udp_b.end());
  record(sll(Ipv4(tail, 9, false, 1480)), 13, sll(Ipv4(tail, 9, false, 1480)).size());
  record(sll(Ipv4(Udp(a, 5, 9999))), 14, sll(Ipv4(Udp(a, 5, 9999))).size());  // other port
  out.close();

  PcapReader reader(file, PcapFilter{7502});
  UdpDatagram d;
  ASSERT_TRUE(reader.Next(d));
  EXPECT_EQ(d.payload, a);
  EXPECT_DOUBLE_EQ(d.capture_time, 10.5);
  ASSERT_TRUE(reader.Next(d));
  EXPECT_EQ(d.payload, b);
  EXPECT_FALSE(reader.Next(d));
  EXPECT_EQ(reader.diagnostics().Get("truncated_records"), 1u);
  EXPECT_EQ(reader.diagnostics().Get("other_ports"), 1u);
}

TEST(PcapReader, MissingOrGarbageFileGivesClearError) {
  EXPECT_THROW(PcapReader("/nonexistent/capture.pcap"), DriverError);
  const test::TempDir tmp;
  const auto file = tmp / "garbage.pcap";
  std::ofstream(file) << "this is not a capture";
  try {
    PcapReader reader(file);
    FAIL() << "expected DriverError";
  } catch (const DriverError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
}

TEST(PcapReader, RealCapturesCountLidarAndOtherPackets) {
  const auto dir = test::DataDir() / "velodyne_ouster_pcaps_rust_lidar_utils";
  DAMMLOAM_REQUIRE_DATA(dir / "hdl32e_example.pcap");
  PcapReader reader(dir / "hdl32e_example.pcap", PcapFilter{2368});
  std::size_t n = 0;
  for (UdpDatagram d; reader.Next(d);) {
    EXPECT_EQ(d.payload.size(), 1206u);
    ++n;
  }
  EXPECT_EQ(n, 876u);
  EXPECT_EQ(reader.diagnostics().Get("other_ports"), 100u);  // GPS position packets on 8308
}

}  // namespace
}  // namespace dammloam::drivers
