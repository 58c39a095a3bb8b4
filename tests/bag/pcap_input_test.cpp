// Ouster and Velodyne captures as inputs of dammloam-odometry (tools/odometry/pcap_source.cpp):
// the real pcaps of ../shared/data (ouster_sdk_pcaps, velodyne_ouster_pcaps_rust_lidar_utils),
// skipped when that folder is absent.
#include <gtest/gtest.h>

#include <fstream>

#include "io/io_error.hpp"
#include "io/tum.hpp"
#include "tests/support/data_dir.hpp"
#include "tests/support/run_command.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/tools/test_support.hpp"
#include "tools/odometry/pcap_source.hpp"

namespace dammloam {
namespace {

namespace fs = std::filesystem;

// m, odometry vs the reference poses (measured 2026-11-29: 1.7 cm at frame 1, 2.7 cm at frame 2)
constexpr double kOusterTolerance = 0.04;
constexpr std::size_t kHdl32Scans = 5;
constexpr double kHdl32SpeedTolerance = 1.5;  // m/s (measured 15.5 m/s)

fs::path OusterDir() { return test::DataDir() / "ouster_sdk_pcaps"; }
fs::path RustDir() { return test::DataDir() / "velodyne_ouster_pcaps_rust_lidar_utils"; }

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

std::vector<io::StampedPose> RunOdometry(const std::string& args, const fs::path& out) {
  const std::string binary = DAMMLOAM_BIN_DIR "/dammloam-odometry";
  const auto r = test::RunCommand(binary + " " + args + " --no-loop-closure --out " + out.string() + " 2>&1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  std::cout << r.output;
  return r.exit_code == 0 ? io::ReadTum(out) : std::vector<io::StampedPose>{};
}

// The 3 frames of the OS1-128 street capture: the odometry against Ouster's reference poses
// (a KISS-ICP estimate, README: frame 1 at x = +0.245 m, frame 2 at +0.498 m).
TEST(OusterPcap, OdometryOverTheThreeFramesFollowsTheReferencePoses) {
  const std::string binary = DAMMLOAM_BIN_DIR "/dammloam-odometry";
  if (!fs::exists(binary)) GTEST_SKIP() << binary << " not built";
  const fs::path pcap = OusterDir() / "OS-1-128_v2.3.0_1024x10_lb_n3.pcap";
  DAMMLOAM_REQUIRE_DATA(pcap);
  test::TempDir tmp;
  const auto poses = RunOdometry(pcap.string(), tmp / "poses.tum");  // metadata found beside it
  ASSERT_EQ(poses.size(), 3u);
  std::ifstream kitti(OusterDir() / "OS-1-128_v2.3.0_1024x10_lb_n3_poses_kitti.txt");
  for (std::size_t i = 0; i < 3; ++i) {
    Eigen::Matrix<double, 3, 4> m;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) kitti >> m(r, c);
    }
    ASSERT_TRUE(kitti) << "reference pose " << i;
    const Eigen::Vector3d expected = m.col(3);
    const Eigen::Vector3d got = poses[0].T.inverse() * poses[i].T.translation();
    std::cout << "frame " << i << ": odometry " << got.transpose() << ", reference " << expected.transpose()
              << ", difference " << (got - expected).norm() << " m\n";
    EXPECT_LT((got - expected).norm(), kOusterTolerance) << "frame " << i;
  }
  EXPECT_NEAR(poses[1].t - poses[0].t, 0.1, 0.002);  // stamps from the column timestamps, 10 Hz
}

// Velodyne captures: the HDL-32E drive (about 5 revolutions at 15 m/s) and the VLP-16 capture.
TEST(VelodynePcap, CapturesGiveTheirCompleteScans) {
  DAMMLOAM_REQUIRE_DATA(RustDir() / "README.md");
  const fs::path hdl32 = fs::path(DAMMLOAM_SOURCE_DIR) / "drivers" / "calibration" / "HDL32E.yaml";
  const Decoded drive = DecodeAll(RustDir() / "hdl32e_example.pcap", {"", "hdl32e", hdl32});
  std::cout << "hdl32e_example: " << drive.points.size() << " scans\n";
  EXPECT_EQ(drive.points.size(), kHdl32Scans);
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

TEST(VelodynePcap, OdometryOnTheHdl32eDrive) {
  const std::string binary = DAMMLOAM_BIN_DIR "/dammloam-odometry";
  if (!fs::exists(binary)) GTEST_SKIP() << binary << " not built";
  DAMMLOAM_REQUIRE_DATA(RustDir() / "hdl32e_example.pcap");
  test::TempDir tmp;
  const fs::path hdl32 = fs::path(DAMMLOAM_SOURCE_DIR) / "drivers" / "calibration" / "HDL32E.yaml";
  const auto poses = RunOdometry((RustDir() / "hdl32e_example.pcap").string() +
                                     " --velodyne-model hdl32e --velodyne-calibration " + hdl32.string(),
                                 tmp / "poses.tum");
  ASSERT_EQ(poses.size(), kHdl32Scans);
  const double distance = (poses.back().T.translation() - poses.front().T.translation()).norm();
  const double speed = distance / (poses.back().t - poses.front().t);
  std::cout << "HDL-32E drive: " << distance << " m in " << poses.back().t - poses.front().t << " s = " << speed
            << " m/s (GPS RMC: 28.8 kn = 14.8 m/s)\n";
  EXPECT_NEAR(speed, 14.8, kHdl32SpeedTolerance);
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

}  // namespace
}  // namespace dammloam
