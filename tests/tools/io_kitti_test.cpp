#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "tests/support/data_dir.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"
#include "tests/tools/test_support.hpp"
#include "io/sequence_io.hpp"

namespace dammloam::io {
namespace {

using test::TempDir;

ReadOptions XyziOptions() {
  ReadOptions options;
  options.layout = PointLayout::kXYZI;
  return options;
}

void WriteXyzi(const std::filesystem::path& file, std::size_t points, float offset) {
  std::vector<float> values;
  for (std::size_t i = 0; i < points; ++i) {
    values.insert(values.end(), {offset + static_cast<float>(i), -1.0f, -1.73f, 0.5f});
  }
  std::ofstream out(file, std::ios::binary);
  out.write(reinterpret_cast<const char*>(values.data()),
            static_cast<std::streamsize>(values.size() * sizeof(float)));
}

TEST(KittiFolder, VelodyneSubfolderIsDetectedWithoutMeta) {
  TempDir tmp;
  std::filesystem::create_directories(tmp / "velodyne");
  for (std::size_t i = 0; i < 3; ++i) WriteXyzi(tmp / "velodyne" / ScanFileName(i), 5 + i, 10.0f * i);
  const SequenceReader reader = SequenceReader::Open(tmp.path());
  EXPECT_EQ(reader.meta().layout, PointLayout::kXYZI);
  EXPECT_EQ(reader.meta().model.rings, 64);
  EXPECT_EQ(reader.meta().model.columns, 2048);
  EXPECT_EQ(reader.meta().model.scan_period, 0.1);
  EXPECT_TRUE(reader.meta().model.vertical_angles_deg.empty());
  ASSERT_EQ(reader.size(), 3u);
  EXPECT_EQ(reader.times(), (std::vector<double>{0.0, 0.1, 0.2}));
  const Scan scan = reader.ReadScan(2);
  ASSERT_EQ(scan.size(), 7u);
  EXPECT_EQ(scan.t_start, 0.2);
  EXPECT_EQ(scan.points[1], Eigen::Vector3d(21.0, -1.0, static_cast<double>(-1.73f)));
  EXPECT_FLOAT_EQ(scan.intensities[6], 0.5f);
  EXPECT_TRUE(scan.times.empty());
  EXPECT_TRUE(scan.rings.empty());
}

TEST(KittiFolder, FlatFolderNeedsExplicitLayoutAndUsesTimesTxt) {
  TempDir tmp;
  for (std::size_t i = 0; i < 2; ++i) WriteXyzi(tmp / ScanFileName(i), 6, 0.0f);
  test::WriteText(tmp / "notes.txt", "not a scan");
  // Never guessed from the file size (6 points x 16 bytes is also 4 points x 24 bytes).
  const std::string error = test::IoErrorOf([&] { SequenceReader::Open(tmp.path()); });
  EXPECT_NE(error.find("meta.json"), std::string::npos) << error;

  test::WriteText(tmp / "times.txt", "0.000000e+00\n1.037359e-01\n");
  const SequenceReader reader = SequenceReader::Open(tmp.path(), XyziOptions());
  ASSERT_EQ(reader.size(), 2u);
  EXPECT_EQ(reader.times()[1], 0.1037359);
  EXPECT_EQ(reader.ReadScan(1).size(), 6u);
}

TEST(KittiFolder, ExplicitLayoutOverridesMeta) {
  TempDir tmp;
  SequenceMeta meta;
  meta.sensor = "x";
  {
    SequenceWriter writer(tmp.path(), meta);  // meta says xyzitr
  }
  WriteXyzi(tmp / "scans" / ScanFileName(0), 3, 0.0f);
  test::WriteText(tmp / "times.txt", "1.5\n");
  const SequenceReader reader = SequenceReader::Open(tmp.path(), XyziOptions());
  EXPECT_EQ(reader.ReadScan(0).size(), 3u);
  EXPECT_EQ(reader.ReadScan(0).t_start, 1.5);
}

// Real HDL-64E scans (KITTI format, see the folder's README): sizes and geometry as documented.
TEST(KittiFolder, RealHdl64Scans) {
  const auto dir = test::DataDir() / "kitti_hdl64_patchworkpp_6frames";
  DAMMLOAM_REQUIRE_DATA(dir);
  const SequenceReader reader = SequenceReader::Open(dir, XyziOptions());
  ASSERT_EQ(reader.size(), 6u);
  EXPECT_EQ(reader.times().back(), 0.5);
  ScanReadReport report;
  const Scan scan = reader.ReadScan(0, &report);
  EXPECT_EQ(scan.size() + report.dropped_nonfinite, 124668u);
  EXPECT_EQ(reader.ReadScan(5).size(), 123924u);
  // Road surface 1.73 m below the sensor: most points 4-12 m away lie at z in [-2.0, -1.6].
  std::size_t near = 0, road = 0;
  for (const auto& p : scan.points) {
    const double range = p.head<2>().norm();
    if (range < 4.0 || range > 12.0) continue;
    ++near;
    if (p.z() > -2.0 && p.z() < -1.6) ++road;
  }
  EXPECT_GT(near, 10000u);
  EXPECT_GT(static_cast<double>(road) / static_cast<double>(near), 0.5);
  const auto [lo, hi] = std::minmax_element(scan.intensities.begin(), scan.intensities.end());
  EXPECT_GE(*lo, 0.0f);
  EXPECT_LT(*hi, 1.0f);
}

}  // namespace
}  // namespace dammloam::io
