// Ouster and Velodyne captures as inputs of dammloam-odometry (tools/inputs/pcap_source.cpp), and
// bags of raw Ouster packets (tools/inputs/ouster_bag_source.cpp):
// the real pcaps of ../shared/data (ouster_sdk_pcaps, velodyne_ouster_pcaps_rust_lidar_utils),
// skipped when that folder is absent. The odometry on them: inputs_odometry_test.cpp.
#include <gtest/gtest.h>

#include <fstream>

#include "io/io_error.hpp"
#include "io/tum.hpp"
#include "tests/bag/inputs_fixture.hpp"
#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/tools/test_support.hpp"
#include "tools/inputs/pcap_source.hpp"
#include "tools/inputs/scan_input.hpp"

namespace dammloam {
namespace {

namespace fs = std::filesystem;

// m, odometry vs the reference poses (measured 2026-11-29: 1.7 cm at frame 1, 2.7 cm at frame 2)

using test::OusterDir;
using test::RustDir;

struct Decoded {
  std::vector<std::size_t> points;
  std::vector<double> stamps;
  SensorModel model;
};

Decoded DecodeAll(const fs::path& pcap, const tools::PcapSourceOptions& options) {
  auto source = tools::OpenPcap(pcap, options);
  Decoded d;
  d.model = source->model();
  while (auto scan = source->Next()) {
    d.points.push_back(scan->size());
    d.stamps.push_back(scan->t_start);
    EXPECT_TRUE(scan->has_times());
    EXPECT_TRUE(scan->has_rings());
    for (float t : scan->times) {
      EXPECT_GE(t, 0.0f);
      EXPECT_LT(t, 0.11f);
    }
  }
  return d;
}

// Every Ouster capture with a complete frame gives it, with the valid pixels of the README's
// table (first return) as points; the FUSA capture holds a partial frame only: an error.
TEST(OusterPcap, EachCaptureGivesItsCompleteFramesWithTheirPoints) {
  DAMMLOAM_REQUIRE_DATA(OusterDir() / "README.md");
  struct Case {
    const char* pcap;
    const char* json;
    std::vector<std::size_t> points;
    int rings;
  };
  const std::vector<Case> cases = {
      {"OS-0-128-U1_v2.3.0_1024x10.pcap", "OS-0-128-U1_v2.3.0_1024x10.json", {97299}, 128},
      {"OS-0-32-U1_v2.2.0_1024x10.pcap", "OS-0-32-U1_v2.2.0_1024x10.json", {21631}, 32},
      {"OS-1-32-G_v2.1.1_1024x10.pcap", "OS-1-32-G_v2.1.1_1024x10.json", {27310}, 32},
      {"OS-2-32-U0_v2.0.0_1024x10.pcap", "OS-2-32-U0_v2.0.0_1024x10.json", {28541}, 32},
      {"OS-1-64_1024x10_fw20.pcap", "OS-1-64_sensor_config_reduced.json", {16749}, 64},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.pcap);
    const Decoded d = DecodeAll(OusterDir() / c.pcap, {OusterDir() / c.json, "", ""});
    EXPECT_EQ(d.points, c.points);
    EXPECT_EQ(d.model.rings, c.rings);
    EXPECT_EQ(d.model.columns, 1024);
  }
  const Decoded rust = DecodeAll(RustDir() / "ouster_os1_64_example.pcap", {});  // JSON found beside it
  EXPECT_EQ(rust.points, std::vector<std::size_t>{58797});

  const fs::path fusa = OusterDir() / "OS-1-128_767798045_1024x10_20230712_120049.pcap";
  EXPECT_IO_ERROR(DecodeAll(fusa, {}), fusa.string() + ": no complete Ouster frame", "UDP port 7502");
}

TEST(OusterPcap, MetadataIsFoundBesideTheCapture) {
  DAMMLOAM_REQUIRE_DATA(OusterDir() / "README.md");
  EXPECT_EQ(tools::FindOusterMetadata(OusterDir() / "OS-1-128_v2.3.0_1024x10_lb_n3.pcap"),
            OusterDir() / "OS-1-128_v2.3.0_1024x10.json");  // longest name prefix
  EXPECT_EQ(tools::FindOusterMetadata(OusterDir() / "OS-0-128-U1_v2.3.0_1024x10.pcap"),
            OusterDir() / "OS-0-128-U1_v2.3.0_1024x10.json");  // same name, not the _digest.json
  EXPECT_EQ(tools::FindOusterMetadata(OusterDir() / "OS-1-64_1024x10_fw20.pcap"), std::nullopt);
}

// Velodyne captures: the HDL-32E drive (about 5 revolutions at 15 m/s) and the VLP-16 capture.
TEST(VelodynePcap, CapturesGiveTheirCompleteScans) {
  DAMMLOAM_REQUIRE_DATA(RustDir() / "README.md");
  const fs::path hdl32 = fs::path(DAMMLOAM_SOURCE_DIR) / "drivers" / "calibration" / "HDL32E.yaml";
  const Decoded drive = DecodeAll(RustDir() / "hdl32e_example.pcap", {"", "hdl32e", hdl32});
  std::cout << "hdl32e_example: " << drive.points.size() << " scans\n";
  EXPECT_EQ(drive.points.size(), 5u);
  for (std::size_t p : drive.points) EXPECT_GT(p, 40000u);  // 44.1-44.6 k
  EXPECT_EQ(drive.model.rings, 32);
  // The VLP-16 capture covers 1.1 revolutions starting far from azimuth 0: two partial scans and
  // no complete one (its product id byte says HDL-32E: counted, the model given wins).
  const fs::path vlp16 = test::DataDir() / "velodyne_nebula_rosbag2" / "calibration" / "VLP16.yaml";
  if (fs::exists(vlp16)) {
    const fs::path capture = RustDir() / "velodyne_vlp16.pcap";
    EXPECT_IO_ERROR(DecodeAll(capture, {"", "vlp16", vlp16}),
                    capture.string() + ": no complete Velodyne scan (84 data packets of 1206 bytes",
                    "partial_scans=2", "product_id_mismatch=84");
  }
  // Half a revolution only, and a capture of another sensor: errors naming the file.
  const fs::path partial = RustDir() / "velodyne_vlp32_actually_hdl32e.pcap";
  EXPECT_IO_ERROR(DecodeAll(partial, {"", "hdl32e", hdl32}), partial.string() + ": no complete Velodyne scan (91 data packets");
  const fs::path ouster = RustDir() / "ouster_os1_64_example.pcap";
  EXPECT_IO_ERROR(DecodeAll(ouster, {"", "hdl32e", hdl32}), ouster.string() + ": no complete Velodyne scan (0 data packets");
  EXPECT_IO_ERROR(DecodeAll(RustDir() / "hdl32e_example.pcap", {RustDir() / "ouster_os1_64_example.json", "", ""}),
                  "hdl32e_example.pcap: no complete Ouster frame");
}

TEST(Pcap, TruncatedCaptureIsAnErrorNamingTheRecordAndOffset) {
  DAMMLOAM_REQUIRE_DATA(OusterDir() / "README.md");
  test::TempDir tmp;
  std::ifstream in(OusterDir() / "OS-0-128-U1_v2.3.0_1024x10.pcap", std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const fs::path cut = tmp / "cut.pcap";
  std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size() / 2));
  EXPECT_IO_ERROR(DecodeAll(cut, {OusterDir() / "OS-0-128-U1_v2.3.0_1024x10.json", "", ""}), cut.string() + ": pcap read stopped after record",
                  "which ends at byte");
  std::ofstream(tmp / "empty.pcap", std::ios::binary).write(bytes.data(), 10);
  EXPECT_IO_ERROR(DecodeAll(tmp / "empty.pcap", {OusterDir() / "OS-0-128-U1_v2.3.0_1024x10.json", "", ""}), "empty.pcap");
}

// ouster-ros records raw packets (PacketMsg on /ouster/lidar_packets and /ouster/imu_packets):
// a bag of the capture's own packets, written by @mcap/core, gives the capture's scans exactly.
TEST(OusterPacketBag, GivesTheScansOfTheCaptureItWasRecordedFrom) {
  const fs::path pcap = OusterDir() / "OS-1-128_v2.3.0_1024x10_lb_n3.pcap";
  const fs::path metadata = OusterDir() / "OS-1-128_v2.3.0_1024x10.json";
  DAMMLOAM_REQUIRE_DATA(pcap);
  if (const std::string why = test::NodeMissing(); !why.empty()) GTEST_SKIP() << why;
  test::TempDir tmp;
  const fs::path bag = tmp / "packets.mcap";
  const auto w = test::RunCommand("node " + (test::BagTestDir() / "node" / "write_ouster_packets_mcap.cjs").string() +
                                  " " + pcap.string() + " " + bag.string() + " 2>&1");
  ASSERT_EQ(w.exit_code, 0) << w.output;
  EXPECT_NE(w.output.find("222 packets"), std::string::npos) << w.output;  // 192 lidar + 30 IMU

  tools::ScanInputOptions from_bag;
  from_bag.path = bag;
  from_bag.ouster_metadata = metadata;
  from_bag.quiet = true;
  tools::ScanInputOptions from_pcap;
  from_pcap.path = pcap;
  from_pcap.quiet = true;
  auto a = tools::OpenScanInput(from_bag);
  auto b = tools::OpenScanInput(from_pcap);
  EXPECT_EQ(a->kind(), "ouster packets");
  EXPECT_EQ(a->model().rings, b->model().rings);
  std::size_t scans = 0;
  for (std::optional<Scan> sa = a->Next(), sb = b->Next(); sa || sb; sa = a->Next(), sb = b->Next(), ++scans) {
    ASSERT_TRUE(sa && sb) << "scan " << scans;
    EXPECT_EQ(sa->t_start, sb->t_start);
    ASSERT_EQ(sa->size(), sb->size());
    EXPECT_EQ(sa->points, sb->points);
    EXPECT_EQ(sa->times, sb->times);
  }
  EXPECT_EQ(scans, 3u);

  // Without the metadata the error says what is missing.
  tools::ScanInputOptions bare;
  bare.path = bag;
  EXPECT_IO_ERROR(tools::OpenScanInput(bare), "no sensor_msgs/msg/PointCloud2 topic", "--ouster-metadata");
  // The IMU packets are no lidar packets: a clear error, never a crash.
  from_bag.topic = "/ouster/imu_packets";
  EXPECT_IO_ERROR(tools::OpenScanInput(from_bag)->Next(), "no complete Ouster frame");
}

}  // namespace
}  // namespace dammloam
