// The real rosbag2 recordings of ../shared/data/velodyne_nebula_rosbag2 (SQLite, written by
// ros2 bag for TIER IV's nebula tests): metadata, topics and every VelodyneScan message decoded
// from CDR (its README gives the packet counts and the factory bytes).
#include <gtest/gtest.h>

#include "io/bag/bag_reader.hpp"
#include "io/bag/bag_scans.hpp"
#include "io/bag/cdr_reader.hpp"
#include "tests/support/data_dir.hpp"

namespace dammloam {
namespace {

constexpr std::size_t kPacketBytes = 1206;

struct VelodyneScan {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
  std::string frame_id;
  std::vector<std::array<std::uint8_t, 2>> factory;  // last two bytes of each packet
};

// velodyne_msgs/msg/VelodyneScan: std_msgs/Header, VelodynePacket[] (Time stamp, uint8[1206]).
VelodyneScan Decode(const io::BagMessage& m) {
  io::CdrReader cdr(m.data, m.size, m.data_offset, m.where);
  VelodyneScan scan;
  scan.sec = cdr.I32("header.stamp.sec");
  scan.nanosec = cdr.U32("header.stamp.nanosec");
  scan.frame_id = std::string(cdr.String("header.frame_id"));
  const std::uint32_t n = cdr.SequenceLength("packets", kPacketBytes);
  for (std::uint32_t i = 0; i < n; ++i) {
    cdr.I32("stamp.sec");
    cdr.U32("stamp.nanosec");
    const std::uint8_t* data = cdr.Bytes(kPacketBytes, "data");
    scan.factory.push_back({data[kPacketBytes - 2], data[kPacketBytes - 1]});
  }
  EXPECT_LT(cdr.remaining(), 4u) << m.where;
  return scan;
}

TEST(RealRosbag2, Vlp16PacketsDecodeAsTheReadmeSays) {
  const auto dir = test::DataDir() / "velodyne_nebula_rosbag2" / "vlp16" / "1673400471837873222";
  DAMMLOAM_REQUIRE_DATA(dir);
  const auto bag = io::OpenBag(dir);
  ASSERT_EQ(bag->topics().size(), 1u);
  const io::BagTopic& topic = bag->topics()[0];
  EXPECT_EQ(topic.name, "/velodyne_packets");
  EXPECT_EQ(topic.type, "velodyne_msgs/msg/VelodyneScan");
  EXPECT_EQ(topic.serialization_format, "cdr");
  EXPECT_EQ(topic.message_count, std::optional<std::uint64_t>(4));
  bag->Select(topic.name);
  std::vector<std::size_t> packets;
  io::BagMessage m;
  std::uint64_t last_time = 0;
  while (bag->Next(m)) {
    const VelodyneScan scan = Decode(m);
    packets.push_back(scan.factory.size());
    // The driver stamps a scan with its packets' time; the recorder logs it on arrival.
    const double stamp = scan.sec + scan.nanosec * 1e-9;
    EXPECT_NEAR(stamp, static_cast<double>(m.log_time) * 1e-9, 1.0);
    EXPECT_EQ(scan.frame_id, "velodyne");
    for (const auto& f : scan.factory) {
      ASSERT_EQ(f[0], 0x39);  // dual return
      ASSERT_EQ(f[1], 0x22);  // VLP-16
    }
    EXPECT_GT(m.log_time, last_time);
    last_time = m.log_time;
  }
  EXPECT_EQ(packets, (std::vector<std::size_t>{151, 151, 151, 150}));
}

TEST(RealRosbag2, Vlp32AndVls128TopicsAndCounts) {
  const auto root = test::DataDir() / "velodyne_nebula_rosbag2";
  DAMMLOAM_REQUIRE_DATA(root / "vlp32");
  const auto vlp32 = io::OpenBag(root / "vlp32" / "1713492677464078412");
  ASSERT_EQ(vlp32->topics().size(), 1u);
  EXPECT_EQ(vlp32->topics()[0].name, "/sensing/lidar/front/velodyne_packets");
  vlp32->Select(vlp32->topics()[0].name);
  std::vector<std::size_t> packets;
  io::BagMessage m;
  while (vlp32->Next(m)) {
    const VelodyneScan scan = Decode(m);
    EXPECT_EQ(scan.frame_id, "velodyne_front");
    packets.push_back(scan.factory.size());
  }
  EXPECT_EQ(packets, (std::vector<std::size_t>{76, 76, 76, 75, 76}));

  const auto vls128 = io::OpenBag(root / "vls128" / "1614315746471294674");
  vls128->Select(vls128->topics().at(0).name);
  std::size_t total = 0;
  while (vls128->Next(m)) total += Decode(m).factory.size();
  EXPECT_EQ(total, 2193u);
}

TEST(RealRosbag2, PacketBagHasNoPointCloudTopic) {
  const auto dir = test::DataDir() / "velodyne_nebula_rosbag2" / "vlp16" / "1673400471837873222";
  DAMMLOAM_REQUIRE_DATA(dir);
  try {
    io::BagScans scans(dir, {});
    FAIL() << "no error";
  } catch (const io::IoError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "no sensor_msgs/msg/PointCloud2 topic (topics: /velodyne_packets "
                  "(velodyne_msgs/msg/VelodyneScan, 4 messages))"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace dammloam
