// dammloam-driver publishing PointCloud on DDS (loopback only), read back and validated with
// the daemon's own conversion.
#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>

#include "drivers/net/pcap_reader.hpp"
#include "drivers/ouster/cloud.hpp"
#include "drivers/ouster/packet_decoder.hpp"
#include "services/dds/dds.hpp"
#include "services/dds/point_cloud.hpp"
#include "services/dds/topics.hpp"
#include "tests/support/data_dir.hpp"

extern char** environ;

namespace dammloam::drivers {
namespace {

namespace fs = std::filesystem;

TEST(DriverDds, PublishesEveryFrameAsAValidPointCloud) {
  const fs::path dir = test::DataDir() / "ouster_sdk_pcaps";
  const fs::path pcap = dir / "OS-1-128_v2.3.0_1024x10_lb_n3.pcap";
  const fs::path json = dir / "OS-1-128_v2.3.0_1024x10.json";
  DAMMLOAM_REQUIRE_DATA(pcap);
  ::setenv("CYCLONEDDS_URI", "file://" DAMMLOAM_DRIVERS_DDS_CONFIG, 1);  // loopback only
  const int domain = 87;                                                   // this test's own
  const std::string topic_name = "drivers_test_points_" + std::to_string(::getpid());

  // Expected point counts from the library.
  const ouster::Metadata meta = ouster::LoadMetadata(json);
  ouster::PacketDecoder decoder(meta);
  const ouster::CloudMaker cloud(meta);
  std::vector<std::size_t> expected;
  PcapReader reader(pcap, PcapFilter{meta.udp_port_lidar});
  for (UdpDatagram d; reader.Next(d);) {
    if (auto f = decoder.Push(d.payload)) expected.push_back(cloud.ToScan(*f).size());
  }
  ASSERT_EQ(expected.size(), 3u);

  dds::Participant participant(domain);
  dds::Topic topic(participant, dammloam_msg_PointCloud_desc, topic_name, dds::PointsQos(8));
  dds::Reader<dammloam_msg_PointCloud> points(participant, topic, dds::PointsQos(8));
  dds::WaitSet waitset(participant);
  waitset.Attach(points);

  std::vector<std::string> args = {DAMMLOAM_DRIVERS_DRIVER_EXE, "ouster", "--metadata", json.string(), "--pcap",
                                   pcap.string(), "--domain", std::to_string(domain), "--topic", topic_name,
                                   "--rate", "1", "--wait-for-subscriber", "20"};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ), 0);

  std::vector<std::size_t> received;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (received.size() < 3 && std::chrono::steady_clock::now() < deadline) {
    waitset.Wait(std::chrono::milliseconds(200));
    points.TakeEach([&](const dammloam_msg_PointCloud& msg, const dds_sample_info_t&) {
      const dds::CloudConversion c = dds::CloudToScan(msg, dds::CloudLimits{});
      EXPECT_TRUE(c.scan.has_value()) << c.error;
      if (c.scan) {
        EXPECT_TRUE(c.scan->has_times());
        EXPECT_TRUE(c.scan->has_rings());
        received.push_back(c.scan->size());
      }
    });
  }
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_EQ(received, expected);
}

}  // namespace
}  // namespace dammloam::drivers
