// The core odometry on real decoded Ouster data: the 3-frame OS1-128 capture against its
// reference poses (a KISS-ICP estimate by Ouster, not survey ground truth).
#include <gtest/gtest.h>

#include <fstream>

#include "core/odometry/pipeline.hpp"
#include "drivers/net/pcap_reader.hpp"
#include "drivers/ouster/cloud.hpp"
#include "drivers/ouster/packet_decoder.hpp"
#include "drivers/velodyne/calibration.hpp"
#include "drivers/velodyne/decoder.hpp"
#include "tests/support/data_dir.hpp"

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
  const auto dir = test::DataDir() / "ouster_sdk_pcaps";
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

// The HDL-32E driving capture (Velodyne's 2012 sample: a road through vegetation, mostly ground
// planes plus trees): five revolutions at ~11.7 Hz while the GPS reports 28.8 kn (14.8 m/s).
// There are no reference poses, so the test checks what a driving car must show: every scan
// registered, every scan's speed near the GPS speed although odometry starts from rest (1.3 m of
// unmodelled motion and skew in the first scans: the first registration measures the motion,
// then the first scan and itself are deskewed again), a steady heading and no vertical jumps.
// Measured: 13.8, 14.5, 15.6, 15.1 m/s; before the bootstrap re-deskew 6.6 to 18.8 m/s.
TEST(OdometryOnRealData, Hdl32eDrivingCaptureTracksPlausibleMotion) {
  const auto pcap = test::DataDir() / "velodyne_ouster_pcaps_rust_lidar_utils" / "hdl32e_example.pcap";
  DAMMLOAM_REQUIRE_DATA(pcap);
  velodyne::Decoder decoder(
      velodyne::DecoderConfig{.model = velodyne::Model::kHDL32E},
      velodyne::LoadCalibration(std::filesystem::path(DAMMLOAM_DRIVERS_CALIBRATION_DIR) / "HDL32E.yaml"));
  OdometryPipeline pipeline(OdometryConfig{}, decoder.sensor_model());
  std::vector<OdometryResult> results;
  PcapReader reader(pcap, PcapFilter{2368});
  for (UdpDatagram d; reader.Next(d);) {
    if (auto scan = decoder.Push(d.payload, d.capture_time)) results.push_back(pipeline.Process(std::move(*scan)));
  }
  ASSERT_EQ(results.size(), 5u);
  constexpr double kGpsSpeed = 28.8 * 1852.0 / 3600.0;  // knots to m/s
  Eigen::Vector3d first_heading = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < results.size(); ++k) {
    ASSERT_TRUE(Registered(results[k].status)) << "scan " << k << ": " << Name(results[k].status);
    if (k == 0) continue;
    const Eigen::Isometry3d step = results[k - 1].T_world_sensor.inverse() * results[k].T_world_sensor;
    const double speed = step.translation().norm() / (results[k].stamp - results[k - 1].stamp);
    EXPECT_NEAR(speed, kGpsSpeed, 0.15 * kGpsSpeed) << "scan " << k;
    EXPECT_LT(std::abs(step.translation().z()), 0.15) << "scan " << k;
    EXPECT_LT(Eigen::AngleAxisd(step.linear()).angle(), 3.0 * M_PI / 180.0) << "scan " << k;
    const Eigen::Vector3d heading = step.translation().normalized();
    if (k == 1) first_heading = heading;
    EXPECT_GT(heading.dot(first_heading), std::cos(10.0 * M_PI / 180.0)) << "scan " << k;
  }
  const Eigen::Vector3d travelled = results.back().T_world_sensor.translation() - results.front().T_world_sensor.translation();
  const double average_speed = travelled.norm() / (results.back().stamp - results.front().stamp);
  EXPECT_NEAR(average_speed, kGpsSpeed, 0.08 * kGpsSpeed);
}

}  // namespace
}  // namespace dammloam::drivers
