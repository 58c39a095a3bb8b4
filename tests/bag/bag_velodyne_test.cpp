// Raw Velodyne packets from a rosbag2 (velodyne_msgs/msg/VelodyneScan, the nebula recording of
// ../shared/data/velodyne_nebula_rosbag2) decoded by drivers/velodyne: the same scans as the
// pcap made from that bag, and nebula's own cloud.
#include <gtest/gtest.h>

#include "drivers/net/pcap_reader.hpp"
#include "drivers/velodyne/calibration.hpp"
#include "drivers/velodyne/decoder.hpp"
#include "io/bag/bag_reader.hpp"
#include "io/bag/cdr_reader.hpp"
#include "tests/drivers/reference_cloud.hpp"
#include "io/tum.hpp"
#include "tests/support/data_dir.hpp"
#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"

namespace dammloam {
namespace {

namespace velodyne = drivers::velodyne;

std::filesystem::path NebulaDir() { return test::DataDir() / "velodyne_nebula_rosbag2"; }

velodyne::Decoder Vlp16Decoder() {
  const velodyne::DecoderConfig config{.model = velodyne::Model::kVLP16, .min_range = 0.3,
                                       .max_range = 300.0, .scan_phase_deg = 0.0};
  return velodyne::Decoder(config, velodyne::LoadCalibration(NebulaDir() / "calibration" / "VLP16.yaml"));
}

// Every packet of every VelodyneScan, with its stamp as the capture time.
std::vector<Scan> DecodeBag(const std::filesystem::path& dir) {
  velodyne::Decoder decoder = Vlp16Decoder();
  const auto bag = io::OpenBag(dir);
  bag->Select(bag->topics().at(0).name);
  std::vector<Scan> scans;
  io::BagMessage m;
  while (bag->Next(m)) {
    io::CdrReader cdr(m.data, m.size, m.data_offset, m.where);
    cdr.I32("header.stamp.sec");
    cdr.U32("header.stamp.nanosec");
    cdr.String("header.frame_id");
    const std::uint32_t n = cdr.SequenceLength("packets", velodyne::kPacketSize);
    for (std::uint32_t i = 0; i < n; ++i) {
      const double sec = cdr.I32("stamp.sec");
      const double nanosec = cdr.U32("stamp.nanosec");
      const std::uint8_t* packet = cdr.Bytes(velodyne::kPacketSize, "data");
      if (auto s = decoder.Push({packet, velodyne::kPacketSize}, sec + nanosec * 1e-9)) {
        scans.push_back(std::move(*s));
      }
    }
  }
  return scans;
}

TEST(BagVelodyne, Vlp16PacketsFromTheBagGiveThePcapsScans) {
  const auto dir = NebulaDir() / "vlp16" / "1673400471837873222";
  const auto pcap = NebulaDir() / "vlp16" / "vlp16_packets_from_rosbag2.pcap";
  DAMMLOAM_REQUIRE_DATA(dir);
  DAMMLOAM_REQUIRE_DATA(pcap);
  const std::vector<Scan> from_bag = DecodeBag(dir);

  velodyne::Decoder decoder = Vlp16Decoder();
  drivers::PcapReader reader(pcap, drivers::PcapFilter{2368});
  drivers::UdpDatagram d;
  std::vector<Scan> from_pcap;
  while (reader.Next(d)) {
    if (auto s = decoder.Push(d.payload, d.capture_time)) from_pcap.push_back(std::move(*s));
  }
  ASSERT_GE(from_bag.size(), 2u);
  ASSERT_EQ(from_bag.size(), from_pcap.size());
  for (std::size_t s = 0; s < from_bag.size(); ++s) {
    ASSERT_EQ(from_bag[s].size(), from_pcap[s].size()) << "scan " << s;
    EXPECT_EQ(from_bag[s].points, from_pcap[s].points) << "scan " << s;
    EXPECT_EQ(from_bag[s].rings, from_pcap[s].rings) << "scan " << s;
  }
  // And nebula's cloud of the same packets (as tests/drivers/velodyne_test.cpp on the pcap).
  const auto expected = drivers::testing::ReadPcdXyz(NebulaDir() / "vlp16" / "1673400472138016708.pcd");
  double best = 1e9;
  for (const Scan& s : from_bag) best = std::min(best, drivers::testing::NearestNeighbourStats(s.points, expected).median);
  EXPECT_LT(best, 0.01);
}

// dammloam-odometry on the same bag: one pose per decoded scan; the VLP-16 stood still indoors.
TEST(BagVelodyne, OdometryRunsOnTheRawPacketBag) {
  const auto dir = NebulaDir() / "vlp16" / "1673400471837873222";
  DAMMLOAM_REQUIRE_DATA(dir);
  const std::string binary = DAMMLOAM_BIN_DIR "/dammloam-odometry";
  if (!std::filesystem::exists(binary)) GTEST_SKIP() << binary << " not built";
  test::TempDir tmp;
  const auto r = test::RunCommand(binary + " " + dir.string() + " --quiet --no-loop-closure" +
                                  " --velodyne-model vlp16 --velodyne-calibration " +
                                  (NebulaDir() / "calibration" / "VLP16.yaml").string() +
                                  " --out " + (tmp / "poses.tum").string() + " 2>&1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto poses = io::ReadTum(tmp / "poses.tum");
  EXPECT_EQ(poses.size(), DecodeBag(dir).size());
  for (const auto& p : poses) EXPECT_LT(p.T.translation().norm(), 0.05) << p.t;
  // Without the model the packets are not a point cloud: the error lists the topic.
  const auto plain = test::RunCommand(binary + " " + dir.string() + " --out " + (tmp / "x.tum").string() + " 2>&1");
  EXPECT_NE(plain.exit_code, 0);
  EXPECT_NE(plain.output.find("/velodyne_packets (velodyne_msgs/msg/VelodyneScan, 4 messages)"), std::string::npos)
      << plain.output;
}

}  // namespace
}  // namespace dammloam
