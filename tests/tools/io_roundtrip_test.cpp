#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "core/geometry/se3.hpp"
#include "tests/tools/test_support.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"
#include "io/sequence_io.hpp"

namespace dammloam::io {
namespace {

using test::TempDir;

SequenceMeta Os1Meta() {
  SequenceMeta meta;
  meta.sensor = "os1-64";
  meta.model.rings = 4;
  meta.model.columns = 16;
  meta.model.scan_period = 0.1;
  meta.model.vertical_angles_deg = {22.5, 7.123456789012345, -7.5, -22.5};
  meta.model.min_range = 0.3;
  meta.model.max_range = 120.25;
  return meta;
}

Scan RandomScan(double t_start, std::size_t n, const SensorModel& model, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> coord(-50.0, 50.0);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  Scan scan;
  scan.t_start = t_start;
  for (std::size_t i = 0; i < n; ++i) {
    scan.points.emplace_back(coord(rng), coord(rng), coord(rng));
    scan.intensities.push_back(255.0f * unit(rng));
    scan.times.push_back(static_cast<float>(model.scan_period * i / n));
    scan.rings.push_back(static_cast<std::int16_t>(i % model.rings));
  }
  return scan;
}

std::vector<StampedPose> SomePoses(const std::vector<double>& times) {
  std::vector<StampedPose> poses;
  for (std::size_t i = 0; i < times.size(); ++i) {
    Vector6d xi;
    xi << 1.5 * i, -0.25 * i, 0.01, 0.1, -0.2, 0.3 * i;
    poses.push_back({times[i], ExpSE3(xi)});
  }
  return poses;
}

void ExpectSamePoints(const Scan& written, const Scan& read) {
  ASSERT_EQ(read.size(), written.size());
  for (std::size_t i = 0; i < written.size(); ++i) {
    // The file stores float32: exact equality with the float-rounded input.
    EXPECT_EQ(read.points[i], written.points[i].cast<float>().cast<double>()) << "point " << i;
    EXPECT_EQ(read.intensities[i], written.intensities[i]);
  }
}

TEST(SequenceRoundTrip, XyzitrKeepsEveryField) {
  TempDir tmp;
  const SequenceMeta meta = Os1Meta();
  const std::vector<double> times = {1700000000.1, 1700000000.2000003, 1700000000.3};
  std::vector<Scan> scans;
  {
    SequenceWriter writer(tmp.path(), meta);
    for (std::size_t i = 0; i < times.size(); ++i) {
      scans.push_back(RandomScan(times[i], 100 + i, meta.model, static_cast<unsigned>(i)));
      writer.Write(scans.back());
    }
    writer.WriteGroundTruth(SomePoses(times));
    EXPECT_EQ(writer.size(), 3u);
  }
  const SequenceReader reader = SequenceReader::Open(tmp.path());
  ASSERT_EQ(reader.size(), 3u);
  EXPECT_EQ(reader.times(), times);  // exact, full double precision
  EXPECT_EQ(reader.meta().sensor, "os1-64");
  EXPECT_EQ(reader.meta().layout, PointLayout::kXYZITR);
  EXPECT_EQ(reader.meta().model.vertical_angles_deg, meta.model.vertical_angles_deg);
  for (std::size_t i = 0; i < scans.size(); ++i) {
    ScanReadReport report;
    const Scan scan = reader.ReadScan(i, &report);
    EXPECT_EQ(scan.t_start, times[i]);
    EXPECT_EQ(report.dropped_nonfinite, 0u);
    ExpectSamePoints(scans[i], scan);
    EXPECT_EQ(scan.times, scans[i].times);
    EXPECT_EQ(scan.rings, scans[i].rings);
  }
  const auto gt = reader.ReadGroundTruth();
  ASSERT_TRUE(gt.has_value());
  const auto expected = SomePoses(times);
  ASSERT_EQ(gt->size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ((*gt)[i].t, expected[i].t);
    EXPECT_TRUE((*gt)[i].T.isApprox(expected[i].T, 1e-14));
  }
  EXPECT_THROW(reader.ReadScan(3), std::out_of_range);
}

TEST(SequenceRoundTrip, XyziFromMetaHasNoTimesOrRings) {
  TempDir tmp;
  SequenceMeta meta = Os1Meta();
  meta.layout = PointLayout::kXYZI;
  const Scan written = RandomScan(5.0, 50, meta.model, 7);
  {
    SequenceWriter writer(tmp.path(), meta);
    writer.Write(written);
  }
  EXPECT_EQ(std::filesystem::file_size(tmp / "scans/000000.bin"), 50u * 16u);
  const SequenceReader reader = SequenceReader::Open(tmp.path());
  EXPECT_EQ(reader.meta().layout, PointLayout::kXYZI);
  const Scan scan = reader.ReadScan(0);
  ExpectSamePoints(written, scan);
  EXPECT_TRUE(scan.times.empty());
  EXPECT_TRUE(scan.rings.empty());
  EXPECT_FALSE(reader.ReadGroundTruth().has_value());
}

TEST(SequenceRoundTrip, EmptyScanAndMissingIntensities) {
  TempDir tmp;
  const SequenceMeta meta = Os1Meta();
  Scan no_intensity = RandomScan(1.0, 10, meta.model, 3);
  no_intensity.intensities.clear();
  {
    SequenceWriter writer(tmp.path(), meta);
    Scan empty;
    empty.t_start = 0.5;
    writer.Write(empty);
    writer.Write(no_intensity);
  }
  const SequenceReader reader = SequenceReader::Open(tmp.path());
  EXPECT_TRUE(reader.ReadScan(0).empty());
  const Scan scan = reader.ReadScan(1);
  ASSERT_EQ(scan.size(), 10u);
  for (const float intensity : scan.intensities) EXPECT_EQ(intensity, 0.0f);
}

TEST(SequenceRoundTrip, NonFinitePointsAreDroppedAndCounted) {
  TempDir tmp;
  const SequenceMeta meta = Os1Meta();
  Scan scan = RandomScan(1.0, 20, meta.model, 5);
  scan.points[3].x() = std::numeric_limits<double>::quiet_NaN();
  scan.points[11].z() = std::numeric_limits<double>::infinity();
  {
    SequenceWriter writer(tmp.path(), meta);
    writer.Write(scan);
  }
  ScanReadReport report;
  const Scan read = SequenceReader::Open(tmp.path()).ReadScan(0, &report);
  EXPECT_EQ(read.size(), 18u);
  EXPECT_EQ(report.dropped_nonfinite, 2u);
  EXPECT_EQ(read.times.size(), 18u);
  EXPECT_EQ(read.points[3], scan.points[4].cast<float>().cast<double>());

  ReadOptions strict;
  strict.strict = true;
  const std::string error = test::IoErrorOf(
      [&] { SequenceReader::Open(tmp.path(), strict).ReadScan(0); });
  EXPECT_NE(error.find("000000.bin"), std::string::npos) << error;
  EXPECT_NE(error.find("point 3"), std::string::npos) << error;
  EXPECT_NE(error.find("NaN"), std::string::npos) << error;
}

TEST(SequenceRoundTrip, WriterRefusesToOverwriteUnlessAsked) {
  TempDir tmp;
  const SequenceMeta meta = Os1Meta();
  {
    SequenceWriter writer(tmp.path(), meta);
    writer.Write(RandomScan(1.0, 5, meta.model, 1));
    writer.Write(RandomScan(2.0, 5, meta.model, 2));
  }
  const std::string error = test::IoErrorOf([&] { SequenceWriter writer(tmp.path(), meta); });
  EXPECT_NE(error.find("refusing to overwrite"), std::string::npos) << error;
  {
    SequenceWriter writer(tmp.path(), meta, /*overwrite=*/true);
    writer.Write(RandomScan(3.0, 5, meta.model, 3));
  }
  const SequenceReader reader = SequenceReader::Open(tmp.path());
  EXPECT_EQ(reader.size(), 1u);
  EXPECT_EQ(reader.times().front(), 3.0);
}

TEST(SequenceRoundTrip, WriterRejectsBadScans) {
  TempDir tmp;
  const SequenceMeta meta = Os1Meta();
  SequenceWriter writer(tmp.path(), meta);
  writer.Write(RandomScan(2.0, 5, meta.model, 1));
  EXPECT_NE(test::IoErrorOf([&] { writer.Write(RandomScan(2.0, 5, meta.model, 2)); })
                .find("not after the previous"),
            std::string::npos);
  Scan no_rings = RandomScan(3.0, 5, meta.model, 3);
  no_rings.rings.clear();
  EXPECT_NE(test::IoErrorOf([&] { writer.Write(no_rings); }).find("needs per-point times and rings"),
            std::string::npos);
  Scan late = RandomScan(4.0, 5, meta.model, 4);
  late.times[2] = 0.1f;
  EXPECT_NE(test::IoErrorOf([&] { writer.Write(late); }).find("outside [0, scan_period"),
            std::string::npos);
  EXPECT_EQ(writer.size(), 1u);
}

TEST(MetaRoundTrip, ExactValues) {
  TempDir tmp;
  SequenceMeta meta = Os1Meta();
  meta.layout = PointLayout::kXYZI;
  meta.model.scan_period = 0.05000000000000001;
  WriteMeta(tmp / "meta.json", meta);
  const SequenceMeta read = ReadMeta(tmp / "meta.json");
  EXPECT_EQ(read.sensor, meta.sensor);
  EXPECT_EQ(read.layout, meta.layout);
  EXPECT_EQ(read.model.rings, meta.model.rings);
  EXPECT_EQ(read.model.columns, meta.model.columns);
  EXPECT_EQ(read.model.scan_period, meta.model.scan_period);
  EXPECT_EQ(read.model.vertical_angles_deg, meta.model.vertical_angles_deg);
  EXPECT_EQ(read.model.min_range, meta.model.min_range);
  EXPECT_EQ(read.model.max_range, meta.model.max_range);
}

TEST(MetaRoundTrip, OptionalKeysTakeDefaultsAndUnknownKeysAreIgnored) {
  TempDir tmp;
  test::WriteText(tmp / "meta.json",
                  R"({"sensor": "vlp-16", "rings": 16, "columns": 1800, "scan_period": 0.1,
                      "firmware": "3.0", "vertical_angles_deg": []})");
  const SequenceMeta meta = ReadMeta(tmp / "meta.json");
  EXPECT_EQ(meta.model.rings, 16);
  EXPECT_TRUE(meta.model.vertical_angles_deg.empty());
  EXPECT_EQ(meta.layout, PointLayout::kXYZITR);
  EXPECT_EQ(meta.model.min_range, SensorModel{}.min_range);
}

TEST(TumRoundTrip, FullPrecisionAndComments) {
  TempDir tmp;
  std::vector<StampedPose> poses;
  for (int i = 0; i < 5; ++i) {
    Vector6d xi;
    xi << 1234.5678901234567 * i, -0.1 * i, 1e-9 * i, 0.3 * i, -0.7, 2.9;
    poses.push_back({1700000000.123456789 + 0.1 * i, ExpSE3(xi)});
  }
  WriteTum(tmp / "a.tum", poses);
  const auto read = ReadTum(tmp / "a.tum");
  ASSERT_EQ(read.size(), poses.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    EXPECT_EQ(read[i].t, poses[i].t);
    EXPECT_EQ(read[i].T.translation(), poses[i].T.translation());
    EXPECT_TRUE(read[i].T.linear().isApprox(poses[i].T.linear(), 1e-15));
  }

  test::WriteText(tmp / "b.tum", "# t tx ty tz qx qy qz qw\n\n1.0 1 2 3 0 0 0 2\n  \n");
  const auto commented = ReadTum(tmp / "b.tum");
  ASSERT_EQ(commented.size(), 1u);
  EXPECT_EQ(commented[0].T.translation(), Eigen::Vector3d(1, 2, 3));
  EXPECT_TRUE(commented[0].T.linear().isApprox(Eigen::Matrix3d::Identity()));  // normalised
}

}  // namespace
}  // namespace dammloam::io
