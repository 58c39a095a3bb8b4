// Folders of .pcd / .ply files as inputs (io/bag/cloud_folder.hpp, io/ply.hpp): stamps from file
// names, PLY parsing and its errors. The odometry on folders: inputs_odometry_test.cpp.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <sstream>

#include "io/bag/cloud_folder.hpp"
#include "io/bag/scan_source.hpp"
#include "io/pcd/labelled_pcd.hpp"
#include "io/io_error.hpp"
#include "io/ply.hpp"
#include "tests/bag/bag_fixture.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/tools/test_support.hpp"

namespace dammloam {
namespace {

namespace fs = std::filesystem;

Scan ParseText(const std::string& text) {
  return io::ParsePly(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), "test.ply");
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

// The three PCD encodings io/pcd reads, named by decimal stamps; a broken file is an error
// naming it.
TEST(CloudFolder, PcdEncodingsAndABrokenFile) {
  test::TempDir tmp;
  fs::create_directories(tmp / "clouds");
  io::LabelledCloud cloud;
  for (int i = 0; i < 200; ++i) {
    cloud.points.emplace_back(1.0 + 0.01 * i, -2.0 + 0.5 * (i % 7), 0.25 * (i % 3));
    cloud.intensities.push_back(static_cast<float>(i % 50));
  }
  cloud.points.emplace_back(0.0, 0.0, 0.0);  // an invalid return, dropped
  cloud.intensities.push_back(0.0f);
  io::WriteLabelledPcd(tmp / "clouds" / "10.1.pcd", cloud, io::PcdEncoding::kAscii);
  io::WriteLabelledPcd(tmp / "clouds" / "10.2.pcd", cloud, io::PcdEncoding::kBinary);
  io::WriteLabelledPcd(tmp / "clouds" / "10.3.pcd", cloud, io::PcdEncoding::kBinaryCompressed);
  auto source = io::OpenScanSource(tmp / "clouds");
  EXPECT_EQ(source->kind(), "cloud folder");
  EXPECT_EQ(source->size(), std::optional<std::size_t>(3));
  for (int k = 0; k < 3; ++k) {
    const auto scan = source->Next();
    ASSERT_TRUE(scan);
    EXPECT_DOUBLE_EQ(scan->t_start, 10.1 + 0.1 * k);
    ASSERT_EQ(scan->size(), 200u);
    for (std::size_t i = 0; i < 200; ++i) {
      EXPECT_NEAR((scan->points[i] - cloud.points[i]).norm(), 0.0, 1e-6) << "file " << k << " point " << i;
      EXPECT_EQ(scan->intensities[i], cloud.intensities[i]);
    }
  }
  EXPECT_FALSE(source->Next());
  std::ofstream(tmp / "clouds" / "10.4.ply") << "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\n"
                                               "property float y\nproperty float z\nend_header\n1 2 3\n";
  auto broken = io::OpenScanSource(tmp / "clouds");
  for (int k = 0; k < 3; ++k) broken->Next();
  EXPECT_IO_ERROR(broken->Next(), (tmp / "clouds" / "10.4.ply").string() + ": PLY truncated");
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
