// dammloam-driver end to end: pcap conversion, live UDP over loopback, bad input.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <thread>

#include "drivers/net/pcap_reader.hpp"
#include "drivers/net/udp_receiver.hpp"
#include "drivers/ouster/cloud.hpp"
#include "drivers/ouster/packet_decoder.hpp"
#include "io/sequence_io.hpp"
#include "tests/support/data_dir.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"

extern char** environ;

namespace dammloam::drivers {
namespace {

namespace fs = std::filesystem;
using test::DataDir;

const fs::path kDriver = fs::path(DAMMLOAM_DRIVER_BIN_DIR) / "dammloam-driver";
fs::path OusterDir() { return DataDir() / "ouster_sdk_pcaps"; }
fs::path Lbn3Pcap() { return OusterDir() / "OS-1-128_v2.3.0_1024x10_lb_n3.pcap"; }
fs::path Lbn3Json() { return OusterDir() / "OS-1-128_v2.3.0_1024x10.json"; }

// Runs the driver, returns its exit code; stdout+stderr go to `log`.
int RunDriver(const std::vector<std::string>& args, const fs::path& log) {
  std::string cmd = kDriver.string();
  for (const auto& a : args) cmd += " '" + a + "'";
  cmd += " > '" + log.string() + "' 2>&1";
  const int rc = std::system(cmd.c_str());
  return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

std::string ReadBytes(const fs::path& p) { return test::ReadText(p); }

TEST(DriverCli, PcapConversionWritesSequenceAndRangeDump) {
  DAMMLOAM_REQUIRE_DATA(Lbn3Pcap());
  const test::TempDir dir("drivers-convert");
  const int rc = RunDriver({"ouster", "--metadata", Lbn3Json().string(), "--pcap", Lbn3Pcap().string(),
                            "--to-sequence", (dir / "seq").string(), "--dump-range", (dir / "range.bin").string()},
                           dir / "log.txt");
  ASSERT_EQ(rc, 0) << ReadBytes(dir / "log.txt");

  // The dump is the staggered range images of the 3 frames, byte for byte.
  const ouster::Metadata meta = ouster::LoadMetadata(Lbn3Json());
  ouster::PacketDecoder decoder(meta);
  PcapReader reader(Lbn3Pcap(), PcapFilter{meta.udp_port_lidar});
  std::string expected;
  std::vector<std::size_t> sizes;
  const ouster::CloudMaker cloud(meta);
  for (UdpDatagram d; reader.Next(d);) {
    if (auto f = decoder.Push(d.payload)) {
      expected.append(reinterpret_cast<const char*>(f->range.data()), f->range.size() * 4);
      sizes.push_back(cloud.ToScan(*f).size());
    }
  }
  ASSERT_EQ(sizes.size(), 3u);
  const std::string dump = ReadBytes(dir / "range.bin");
  EXPECT_EQ(dump.size(), 3u * 128u * 1024u * 4u);
  EXPECT_TRUE(dump == expected);

  const auto seq = io::SequenceReader::Open(dir / "seq");
  ASSERT_EQ(seq.size(), 3u);
  EXPECT_EQ(seq.meta().sensor, "os1-128");
  EXPECT_EQ(seq.meta().model.rings, 128);
  EXPECT_EQ(seq.meta().model.vertical_angles_deg.size(), 128u);
  for (std::size_t i = 0; i < 3; ++i) {
    const Scan s = seq.ReadScan(i);
    EXPECT_EQ(s.size(), sizes[i]);
    EXPECT_TRUE(s.has_times());
    EXPECT_TRUE(s.has_rings());
  }
}

// Port of a UDP socket nobody holds right now (the kernel picks it).
std::uint16_t FreeUdpPort() { return UdpReceiver(0, "127.0.0.1").port(); }

// True once some socket is bound to `port` (/proc/net/udp lists local ports in hex).
bool UdpPortBound(std::uint16_t port) {
  std::ifstream in("/proc/net/udp");
  char hex[8];
  std::snprintf(hex, sizeof(hex), ":%04X", port);
  for (std::string line; std::getline(in, line);) {
    if (line.find(hex) != std::string::npos && line.find(hex) < 40) return true;
  }
  return false;
}

// Starts the driver with `args` (live mode on `port`), sends every UDP payload of `pcap` to it
// over loopback like a sensor would, and returns the driver's exit code.
int RunLiveDriver(std::vector<std::string> args, std::uint16_t port, const fs::path& pcap) {
  args.insert(args.begin(), kDriver.string());
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, kDriver.c_str(), nullptr, nullptr, argv.data(), environ) != 0) return -1;
  for (int i = 0; i < 500 && !UdpPortBound(port); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_TRUE(UdpPortBound(port)) << "driver did not bind UDP port " << port;

  const int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(port);
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  PcapReader reader(pcap);
  int sent = 0;
  for (UdpDatagram d; reader.Next(d);) {
    ::sendto(fd, d.payload.data(), d.payload.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof(to));
    // Pace the burst so the receive buffer never overflows.
    if (++sent % 8 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ::close(fd);
  int status = 0;
  if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status)) return -1;
  return WEXITSTATUS(status);
}

TEST(DriverCli, OusterLiveModeOverLoopbackMatchesPcapMode) {
  DAMMLOAM_REQUIRE_DATA(Lbn3Pcap());
  const test::TempDir dir("drivers-live");
  const std::uint16_t port = FreeUdpPort();
  EXPECT_EQ(RunLiveDriver({"ouster", "--metadata", Lbn3Json().string(), "--udp-port", std::to_string(port), "--bind",
                           "127.0.0.1", "--dump-range", (dir / "live.bin").string(), "--to-sequence",
                           (dir / "seq").string(), "--max-scans", "3", "--idle-timeout", "20"},
                          port, Lbn3Pcap()),
            0);
  // Same frames as the pcap path, bit for bit.
  ASSERT_EQ(RunDriver({"ouster", "--metadata", Lbn3Json().string(), "--pcap", Lbn3Pcap().string(), "--dump-range",
                       (dir / "pcap.bin").string()},
                      dir / "log.txt"),
            0);
  const std::string live = ReadBytes(dir / "live.bin");
  EXPECT_EQ(live.size(), 3u * 128u * 1024u * 4u);
  EXPECT_TRUE(live == ReadBytes(dir / "pcap.bin"));
  EXPECT_EQ(io::SequenceReader::Open(dir / "seq").size(), 3u);
}

TEST(DriverCli, VelodyneLiveModeOverLoopbackMatchesPcapMode) {
  const fs::path neb = DataDir() / "velodyne_nebula_rosbag2";
  const fs::path pcap = neb / "vlp16" / "vlp16_packets_from_rosbag2.pcap";
  DAMMLOAM_REQUIRE_DATA(pcap);
  const test::TempDir dir("drivers-vlive");
  const std::vector<std::string> common = {"velodyne", "--model", "vlp16", "--calibration",
                                           (neb / "calibration" / "VLP16.yaml").string()};
  auto args = common;
  for (const std::string& a : {std::string("--pcap"), pcap.string(), std::string("--to-sequence"), (dir / "pcap").string()}) {
    args.push_back(a);
  }
  ASSERT_EQ(RunDriver(args, dir / "log.txt"), 0) << ReadBytes(dir / "log.txt");
  const auto from_pcap = io::SequenceReader::Open(dir / "pcap");
  ASSERT_GE(from_pcap.size(), 2u);

  const std::uint16_t port = FreeUdpPort();
  args = common;
  for (const std::string& a : {std::string("--udp-port"), std::to_string(port), std::string("--bind"), std::string("127.0.0.1"),
                               std::string("--to-sequence"), (dir / "live").string(), std::string("--idle-timeout"),
                               std::string("1")}) {
    args.push_back(a);
  }
  EXPECT_EQ(RunLiveDriver(args, port, pcap), 0);
  const auto live = io::SequenceReader::Open(dir / "live");
  ASSERT_EQ(live.size(), from_pcap.size());
  for (std::size_t i = 0; i < live.size(); ++i) {
    const Scan a = live.ReadScan(i), b = from_pcap.ReadScan(i);
    ASSERT_EQ(a.size(), b.size());
    EXPECT_TRUE(a.points == b.points);  // same packets, same geometry
  }
}

TEST(DriverCli, BadInputGivesClearErrors) {
  const test::TempDir dir("drivers-bad");
  {
    std::ofstream(dir / "broken.json") << "{\"beam_altitude_angles\": [1, 2]}";
    EXPECT_EQ(RunDriver({"ouster", "--metadata", (dir / "broken.json").string(), "--udp-port", "1"}, dir / "log1.txt"), 1);
    const std::string log = ReadBytes(dir / "log1.txt");
    EXPECT_NE(log.find("broken.json"), std::string::npos) << log;
    EXPECT_NE(log.find("beam_azimuth_angles"), std::string::npos) << log;
  }
  {
    std::ofstream(dir / "one.yaml") << "lasers:\n  - {laser_id: 0, vert_correction: 0.1}\n";
    EXPECT_EQ(RunDriver({"velodyne", "--model", "vlp16", "--calibration", (dir / "one.yaml").string(), "--udp-port", "1"},
                        dir / "log2.txt"),
              1);
    const std::string log = ReadBytes(dir / "log2.txt");
    EXPECT_NE(log.find("1 lasers but model vlp16 has 16"), std::string::npos) << log;
  }
  {
    // A capture without a single complete frame: exit code 2 and the partial frame named.
    const auto fusa = OusterDir() / "OS-1-128_767798045_1024x10_20230712_120049.pcap";
    if (fs::exists(fusa)) {
      EXPECT_EQ(RunDriver({"ouster", "--metadata", (OusterDir() / "OS-1-128_767798045_1024x10_20230712_120049.json").string(),
                           "--pcap", fusa.string(), "--dump-range", (dir / "r.bin").string()},
                          dir / "log3.txt"),
                2);
      const std::string log = ReadBytes(dir / "log3.txt");
      EXPECT_NE(log.find("partial_frames"), std::string::npos) << log;
    }
  }
}

}  // namespace
}  // namespace dammloam::drivers
