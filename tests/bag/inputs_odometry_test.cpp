// dammloam-odometry on the input kinds of issue 54, release build only (seven odometry runs would
// add about a minute under ASan; the readers they exercise run there in bag_ros1_test and
// bag_inputs_test): ROS 1 bags written by python3-rosbag against the sequence directory, bit for
// bit; the Ouster OS1-128 capture against Ouster's reference poses; the HDL-32E drive against its
// GPS speed; the HDL-32E PCD pair against fast_gicp's relative pose; PLY files against their
// sequence, bit for bit.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/geometry/se3.hpp"
#include "io/sequence_io.hpp"
#include "io/tum.hpp"
#include "tests/bag/inputs_fixture.hpp"
#include "tests/bag/simulated_sequence.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"

namespace dammloam {
namespace {

namespace fs = std::filesystem;
using test::OusterDir;
using test::RosbagMissing;
using test::RustDir;
using test::WriteRosbag;

constexpr double kOusterTolerance = 0.04;
constexpr std::size_t kHdl32Scans = 5;
constexpr double kHdl32SpeedTolerance = 1.5;  // m/s (measured 15.5 m/s)

std::string Binary() { return DAMMLOAM_BIN_DIR "/dammloam-odometry"; }

std::string RunCli(const std::string& args) {
  const auto r = test::RunCommand(Binary() + " " + args + " 2>&1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return r.output;
}

// Writes a scan as PLY: x y z intensity t ring, ascii or binary_little_endian, with a face
// element after the vertices (ignored) and a comment.
void WritePly(const fs::path& file, const Scan& scan, bool binary) {
  std::ofstream out(file, std::ios::binary);
  out << "ply\nformat " << (binary ? "binary_little_endian" : "ascii") << " 1.0\ncomment written by the test\n"
      << "element vertex " << scan.size()
      << "\nproperty float x\nproperty float y\nproperty float z\nproperty float intensity\n"
      << "property float t\nproperty ushort ring\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n";
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const float v[5] = {static_cast<float>(scan.points[i].x()), static_cast<float>(scan.points[i].y()),
                        static_cast<float>(scan.points[i].z()), scan.intensities[i], scan.times[i]};
    const auto ring = static_cast<std::uint16_t>(scan.rings[i]);
    if (binary) {
      out.write(reinterpret_cast<const char*>(v), sizeof(v));
      out.write(reinterpret_cast<const char*>(&ring), sizeof(ring));
    } else {
      char line[256];
      // %.9g: a float32 printed so that it reads back to the same float.
      std::snprintf(line, sizeof(line), "%.9g %.9g %.9g %.9g %.9g %u\n", v[0], v[1], v[2], v[3], v[4], ring);
      out << line;
    }
  }
}

TEST(Ros1Bag, OdometryPosesFromRosbagsEqualPosesFromTheSequenceBitForBit) {
  const std::string binary = DAMMLOAM_BIN_DIR "/dammloam-odometry";
  if (!fs::exists(binary)) GTEST_SKIP() << binary << " not built";
  if (const std::string why = RosbagMissing(); !why.empty()) GTEST_SKIP() << why;
  test::TempDir tmp;
  constexpr int kScans = 10;
  test::WriteSimulatedOutdoorSequence(tmp / "seq", kScans);
  auto run = [&](const fs::path& input, const std::string& name, const std::string& extra) {
    const auto r = test::RunCommand(binary + " " + input.string() + " --quiet --out " + (tmp / (name + ".tum")).string() +
                                    " " + extra + " 2>&1");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return test::ReadText(tmp / (name + ".tum"));
  };
  const std::string expected = run(tmp / "seq", "seq", "");
  ASSERT_EQ(std::count(expected.begin(), expected.end(), '\n'), kScans);
  for (const std::string compression : {"none", "bz2", "lz4"}) {
    WriteRosbag(tmp / "seq", tmp / (compression + ".bag"), compression);
    EXPECT_EQ(run(tmp / (compression + ".bag"), compression,
                  "--sensor-meta " + (tmp / "seq" / "meta.json").string()),
              expected)
        << compression;
  }
  // --topic picks the cloud topic; a topic of another type is refused by name.
  EXPECT_EQ(run(tmp / "lz4.bag", "topic", "--topic /points --sensor-meta " + (tmp / "seq" / "meta.json").string()),
            expected);
  const auto r = test::RunCommand(binary + " " + (tmp / "lz4.bag").string() + " --topic /chatter --out " +
                                  (tmp / "x.tum").string() + " 2>&1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("topic /chatter is std_msgs/msg/String, not sensor_msgs/msg/PointCloud2"), std::string::npos)
      << r.output;
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

// The real pair: T_target_source from the registration of the second scan onto the first against
// fast_gicp's relative.txt (README: the estimates agree within 1-2 cm and 0.4 deg).
TEST(CloudFolder, Hdl32ePairOfPcdFilesMatchesTheGicpRelativePose) {
  if (!fs::exists(Binary())) GTEST_SKIP() << Binary() << " not built";
  const fs::path data = test::DataDir() / "hdl32_pair_fast_gicp";
  DAMMLOAM_REQUIRE_DATA(data / "relative.txt");
  test::TempDir tmp;
  fs::create_directories(tmp / "pair");
  for (const char* name : {"251370668.pcd", "251371071.pcd"}) fs::copy_file(data / name, tmp / "pair" / name);
  // HDL-32E: 32 rings from +10.67 to -30.67 deg, ~2170 columns at 10 Hz (as odometry_real_pair_test).
  SensorModel hdl32;
  hdl32.rings = 32;
  hdl32.columns = 2170;
  for (int r = 0; r < 32; ++r) hdl32.vertical_angles_deg.push_back(10.67 - r * (41.34 / 31.0));
  hdl32.max_range = 120.0;
  io::WriteMeta(tmp / "hdl32.json", io::SequenceMeta{"hdl-32e", hdl32, io::PointLayout::kXYZI});
  const std::string log = RunCli((tmp / "pair").string() + " --sensor-meta " + (tmp / "hdl32.json").string() +
                              " --no-loop-closure --out " + (tmp / "poses.tum").string());
  // Without --sensor-meta the 32 beams come from the elevations of the first cloud: same poses.
  const std::string guessed = RunCli((tmp / "pair").string() + " --no-loop-closure --out " + (tmp / "guessed.tum").string());
  EXPECT_NE(guessed.find("32 beams from the elevations of the first cloud"), std::string::npos) << guessed;
  EXPECT_EQ(guessed.find("warn"), std::string::npos) << guessed;
  const auto guessed_poses = io::ReadTum(tmp / "guessed.tum");
  ASSERT_EQ(guessed_poses.size(), 2u);
  EXPECT_LT((guessed_poses[1].T.translation() - io::ReadTum(tmp / "poses.tum")[1].T.translation()).norm(), 0.01);
  EXPECT_NE(log.find("2 cloud files, stamps from the file names (ms)"), std::string::npos) << log;
  const auto poses = io::ReadTum(tmp / "poses.tum");
  ASSERT_EQ(poses.size(), 2u);
  EXPECT_DOUBLE_EQ(poses[0].t, 251370.668);
  EXPECT_DOUBLE_EQ(poses[1].t, 251371.071);
  std::ifstream in(data / "relative.txt");
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) in >> m(r, c);
  }
  ASSERT_TRUE(in);
  Eigen::Isometry3d expected;
  expected.matrix() = m;
  const Eigen::Isometry3d got = poses[0].T.inverse() * poses[1].T;
  const Vector6d error = LogSE3(expected.inverse() * got);
  std::cout << "registered t = " << got.translation().transpose() << ", relative.txt t = "
            << expected.translation().transpose() << ": " << error.head<3>().norm() * 100 << " cm, "
            << error.tail<3>().norm() * 180 / M_PI << " deg\n";
  EXPECT_LT(error.head<3>().norm(), 0.05);
  EXPECT_LT(error.tail<3>().norm(), 0.5 * M_PI / 180);
}

// PLY files named by the scans' stamps give the poses of the sequence they came from, bit for bit.
TEST(CloudFolder, PlyFilesGiveThePosesOfTheirSequenceBitForBit) {
  if (!fs::exists(Binary())) GTEST_SKIP() << Binary() << " not built";
  test::TempDir tmp;
  constexpr int kScans = 8;
  test::WriteSimulatedOutdoorSequence(tmp / "seq", kScans);
  const io::SequenceReader reader = io::SequenceReader::Open(tmp / "seq");
  std::istringstream times(test::ReadText(tmp / "seq" / "times.txt"));
  fs::create_directories(tmp / "ply");
  std::string stamp;
  for (std::size_t i = 0; i < reader.size(); ++i) {
    ASSERT_TRUE(std::getline(times, stamp));
    // Half ascii, half binary; named by the stamp as times.txt writes it.
    WritePly(tmp / "ply" / (stamp + ".ply"), reader.ReadScan(i), i % 2 == 0);
  }
  const std::string meta = " --sensor-meta " + (tmp / "seq" / "meta.json").string();
  RunCli((tmp / "seq").string() + " --quiet --out " + (tmp / "seq.tum").string());
  const std::string log = RunCli((tmp / "ply").string() + meta + " --out " + (tmp / "ply.tum").string());
  EXPECT_NE(log.find("8 cloud files, stamps from the file names (s)"), std::string::npos) << log;
  const std::string expected = test::ReadText(tmp / "seq.tum");
  ASSERT_EQ(std::count(expected.begin(), expected.end(), '\n'), kScans);
  EXPECT_EQ(test::ReadText(tmp / "ply.tum"), expected);
  // --scan-period numbers the files instead (other stamps, so only the count is compared).
  RunCli((tmp / "ply").string() + meta + " --quiet --scan-period 0.1 --out " + (tmp / "period.tum").string());
  const auto period = io::ReadTum(tmp / "period.tum");
  ASSERT_EQ(period.size(), static_cast<std::size_t>(kScans));
  EXPECT_DOUBLE_EQ(period[3].t, 0.30000000000000004);
}

}  // namespace
}  // namespace dammloam
