// The core odometry on real decoded Ouster data: the 3-frame OS1-128 capture against its
// reference poses (a KISS-ICP estimate by Ouster, not survey ground truth).
#include <gtest/gtest.h>

#include <fstream>

#include "core/odometry/pipeline.hpp"
#include "drivers/net/pcap_reader.hpp"
#include "drivers/ouster/cloud.hpp"
#include "drivers/ouster/packet_decoder.hpp"
#include "test_data.hpp"

namespace dammloam::drivers {
namespace {

std::vector<Eigen::Vector3d> ReadKittiTranslations(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::vector<Eigen::Vector3d> t;
  double v[12];
  while (in >> v[0]) {
    for (int i = 1; i < 12; ++i) in >> v[i];
    t.emplace_back(v[3], v[7], v[11]);
  }
  return t;
}

TEST(OdometryOnRealData, Os1128ThreeFramesTrackReferencePoses) {
  const auto dir = testing::DataDir() / "ouster_sdk_pcaps";
  DAMMLOAM_REQUIRE_DATA(dir / "OS-1-128_v2.3.0_1024x10_lb_n3.pcap");
  const auto meta = ouster::LoadMetadata(dir / "OS-1-128_v2.3.0_1024x10.json");
  const auto reference = ReadKittiTranslations(dir / "OS-1-128_v2.3.0_1024x10_lb_n3_poses_kitti.txt");
  ASSERT_EQ(reference.size(), 3u);

  ouster::PacketDecoder decoder(meta);
  const ouster::CloudMaker cloud(meta);
  PcapReader reader(dir / "OS-1-128_v2.3.0_1024x10_lb_n3.pcap", PcapFilter{meta.udp_port_lidar});
  // Deskew off: the first two scans cannot be deskewed (no velocity estimate yet), so with it on
  // the third, deskewed scan is registered against a map of skewed scans and lands about half a
  // scan's motion short (measured: 0.382 m instead of 0.498 m). Over 3 frames that bootstrap
  // effect dominates; without deskew every scan is treated alike.
  OdometryConfig config;
  config.deskew = false;
  OdometryPipeline pipeline(config, ouster::ToSensorModel(meta));
  std::vector<OdometryResult> results;
  for (UdpDatagram d; reader.Next(d);) {
    if (auto f = decoder.Push(d.payload)) results.push_back(pipeline.Process(cloud.ToScan(*f)));
  }
  ASSERT_EQ(results.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_TRUE(Registered(results[k].status)) << Name(results[k].status);
    const Eigen::Vector3d t = results[k].T_world_sensor.translation();
    EXPECT_LT((t - reference[k]).norm(), 0.05) << "frame " << k << " at " << t.transpose() << ", reference "
                                               << reference[k].transpose();
  }
}

}  // namespace
}  // namespace dammloam::drivers
