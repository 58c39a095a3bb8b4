// Folders of .pcd / .ply files as inputs (io/bag/cloud_folder.hpp, io/ply.hpp): the real HDL-32E
// pair of ../shared/data/hdl32_pair_fast_gicp through dammloam-odometry against its published
// relative pose; PLY files written here (ascii and binary) from a simulated sequence give the
// sequence's poses bit for bit; PLY parsing and its errors.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <sstream>

#include "core/geometry/se3.hpp"
#include "io/bag/cloud_folder.hpp"
#include "io/io_error.hpp"
#include "io/ply.hpp"
#include "io/sequence_io.hpp"
#include "io/tum.hpp"
#include "tests/bag/bag_fixture.hpp"
#include "tests/support/data_dir.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"
#include "tests/tools/test_support.hpp"
#include "tools/simulate/simulator.hpp"

namespace dammloam {
namespace {

namespace fs = std::filesystem;

std::string Binary() { return DAMMLOAM_BIN_DIR "/dammloam-odometry"; }

std::string RunCli(const std::string& args) {
  const auto r = test::RunCommand(Binary() + " " + args + " 2>&1");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return r.output;
}

Scan ParseText(const std::string& text) {
  return io::ParsePly(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), "test.ply");
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
  constexpr int kScans = 8, kFirstScan = 25;
  sim::SimOptions options;
  options.num_scans = kFirstScan + kScans;
  sim::SensorSpec sensor = sim::Vlp16();
  sensor.columns = 900;
  const sim::Simulator simulator(sim::SceneKind::Outdoor, sensor, options);
  std::vector<Scan> scans;
  for (int i = 0; i < kScans; ++i) {
    Scan scan = simulator.SimulateScan(kFirstScan + i);
    scan.t_start = StampSeconds(SecondsToStamp(scan.t_start));
    scans.push_back(std::move(scan));
  }
  test::WriteSequence(tmp / "seq", scans,
                      io::SequenceMeta{"vlp-16-900", simulator.sensor_model(), io::PointLayout::kXYZITR});
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

TEST(CloudFolder, StampsFromNumericNames) {
  std::string unit;
  const auto ms = io::StampsFromNames({"251370668", "251371071"}, &unit);
  ASSERT_TRUE(ms);
  EXPECT_EQ(unit, "ms");
  EXPECT_DOUBLE_EQ((*ms)[1], 251371.071);
  const auto ns = io::StampsFromNames({"1700000000100000000", "1700000000200000000"}, &unit);
  ASSERT_TRUE(ns);
  EXPECT_EQ(unit, "ns");
  EXPECT_DOUBLE_EQ((*ns)[1], 1700000000.2);
  EXPECT_EQ(io::StampsFromNames({"000000", "000001", "000002"}), std::nullopt);  // frame indices
  EXPECT_EQ(io::StampsFromNames({"scan_a", "scan_b"}), std::nullopt);
  const auto s = io::StampsFromNames({"12.5", "12.6"}, &unit);
  ASSERT_TRUE(s);
  EXPECT_EQ(unit, "s");
  EXPECT_DOUBLE_EQ((*s)[0], 12.5);
}

TEST(Ply, AsciiAndBinaryFieldsAndTimes) {
  // CRLF lines, an element before the vertices, double coordinates, integer nanosecond times.
  const Scan a = ParseText(
      "ply\r\nformat ascii 1.0\r\nelement camera 1\r\nproperty float f\r\nelement vertex 3\r\n"
      "property double x\r\nproperty double y\r\nproperty double z\r\nproperty uint t\r\nend_header\r\n"
      "7\r\n1 2 3 100000000\r\n0 0 0 5\r\n-1.5 nan 2 7\r\n");
  ASSERT_EQ(a.size(), 1u);  // the origin and the NaN dropped
  EXPECT_EQ(a.points[0], Eigen::Vector3d(1, 2, 3));
  ASSERT_EQ(a.times.size(), 1u);
  EXPECT_FLOAT_EQ(a.times[0], 0.1f);
  EXPECT_TRUE(a.intensities.empty());

  std::string bin = "ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                    "property float z\nproperty uchar intensity\nproperty double time\nend_header\n";
  for (int i = 0; i < 2; ++i) {
    const float xyz[3] = {1.0f + static_cast<float>(i), 2.0f, 3.0f};
    const std::uint8_t intensity = 200;
    const double time = 1700000000.0 + 0.05 * i;  // absolute: made relative to the first
    bin.append(reinterpret_cast<const char*>(xyz), sizeof(xyz));
    bin.append(reinterpret_cast<const char*>(&intensity), 1);
    bin.append(reinterpret_cast<const char*>(&time), sizeof(time));
  }
  const Scan b = ParseText(bin);
  ASSERT_EQ(b.size(), 2u);
  EXPECT_EQ(b.points[1], Eigen::Vector3d(2, 2, 3));
  EXPECT_EQ(b.intensities[1], 200.0f);
  EXPECT_NEAR(b.times[1], 0.05f, 1e-6);
  EXPECT_EQ(b.times[0], 0.0f);

  // Errors name the file and the header line, or the vertex and its byte offset.
  EXPECT_IO_ERROR(ParseText("ply\nformat binary_big_endian 1.0\nend_header\n"), "test.ply: PLY header line 2",
                  "binary_big_endian");
  EXPECT_IO_ERROR(ParseText("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n"),
                  "lacks x, y or z");
  EXPECT_IO_ERROR(ParseText(bin.substr(0, bin.size() - 3)), "test.ply: PLY truncated: 2 vertices of 21 bytes");
  EXPECT_IO_ERROR(ParseText("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                            "property float z\nend_header\n1 2 3\n1 x 3\n"),
                  "test.ply: PLY vertex 1 (line 9, byte 106): property 'y' is not a number");
  EXPECT_IO_ERROR(ParseText("ply\nformat ascii 1.0\nelement vertex 2\n"), "PLY header ends without end_header");
  EXPECT_IO_ERROR(ParseText("PK\x03\x04"), "test.ply: not a PLY file");
}

}  // namespace
}  // namespace dammloam
