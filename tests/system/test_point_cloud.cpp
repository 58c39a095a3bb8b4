// PointCloud <-> Scan conversion and validation: round trips and every malformed-input case.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "services/dds/point_cloud.hpp"

namespace dammloam::dds {
namespace {

Scan SmallScan(std::size_t n = 50) {
  Scan scan;
  scan.t_start = 1700000000.1;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 0.1 * static_cast<double>(i);
    scan.points.emplace_back(5.0 * std::cos(a), 5.0 * std::sin(a), 0.01 * static_cast<double>(i));
    scan.intensities.push_back(static_cast<float>(i));
    scan.times.push_back(0.001f * static_cast<float>(i));
    scan.rings.push_back(static_cast<std::int16_t>(i % 16));
  }
  return scan;
}

CloudConversion Convert(const CloudMessage& msg, CloudLimits limits = {}) {
  limits.max_ring = 16;
  return CloudToScan(CloudView(msg).get(), limits);
}

void SetFloat(CloudMessage& msg, std::size_t point, std::uint32_t offset, float value) {
  std::memcpy(msg.data.data() + point * msg.point_step + offset, &value, sizeof(value));
}

void ExpectError(const CloudConversion& c, const std::string& code, const std::string& text) {
  EXPECT_FALSE(c.scan.has_value());
  EXPECT_EQ(c.code, code) << c.error;
  EXPECT_NE(c.error.find(text), std::string::npos) << "error was: " << c.error;
}

TEST(PointCloudConversion, RoundTripKeepsEveryField) {
  const Scan scan = SmallScan();
  const CloudMessage msg = ScanToCloud(scan, "os1", 7);
  EXPECT_EQ(msg.width * msg.point_step, msg.data.size());
  const CloudConversion c = Convert(msg);
  ASSERT_TRUE(c.scan) << c.error;
  const Scan& back = *c.scan;
  EXPECT_DOUBLE_EQ(back.t_start, scan.t_start);
  ASSERT_EQ(back.size(), scan.size());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    EXPECT_NEAR((back.points[i] - scan.points[i]).norm(), 0.0, 1e-5);
    EXPECT_EQ(back.times[i], scan.times[i]);
    EXPECT_EQ(back.rings[i], scan.rings[i]);
    EXPECT_EQ(back.intensities[i], scan.intensities[i]);
  }
}

TEST(PointCloudConversion, StampRoundTripIsExactToTheNanosecond) {
  for (double t : {0.0, 1.5, 1700000000.1, 1700000123.999999999}) {
    const dammloam_msg_Time m = ToMsgTime(t);
    EXPECT_LT(m.nanosec, 1000000000u);
    EXPECT_NEAR(ToSeconds(m), t, 1e-6);
    EXPECT_EQ(ToMsgTime(ToSeconds(m)).nanosec, m.nanosec);
  }
}

TEST(PointCloudConversion, ReadsOrganisedCloudWithRowPaddingDoublesAndNanosecondTimes) {
  // 2 x 3 organised cloud, float64 xyz, Ouster-style uint32 t in ns, uint8 ring, 8 bytes row pad.
  CloudMessage msg;
  msg.height = 2;
  msg.width = 3;
  msg.fields = {{"x", 0, dammloam_msg_DATATYPE_FLOAT64, 1},
                {"y", 8, dammloam_msg_DATATYPE_FLOAT64, 1},
                {"z", 16, dammloam_msg_DATATYPE_FLOAT64, 1},
                {"t", 24, dammloam_msg_DATATYPE_UINT32, 1},
                {"ring", 28, dammloam_msg_DATATYPE_UINT8, 1}};
  msg.point_step = 32;
  msg.row_step = 3 * 32 + 8;
  msg.data.assign(2 * msg.row_step, 0);
  for (std::uint32_t r = 0; r < 2; ++r) {
    for (std::uint32_t c = 0; c < 3; ++c) {
      std::uint8_t* p = msg.data.data() + r * msg.row_step + c * msg.point_step;
      const double xyz[3] = {1.0 + c, 2.0 + r, 3.0};
      const std::uint32_t t_ns = 1000000u * c;  // 1 ms per column
      std::memcpy(p, xyz, sizeof(xyz));
      std::memcpy(p + 24, &t_ns, 4);
      p[28] = static_cast<std::uint8_t>(r);
    }
  }
  const CloudConversion c = Convert(msg);
  ASSERT_TRUE(c.scan) << c.error;
  ASSERT_EQ(c.scan->size(), 6u);
  EXPECT_EQ(c.scan->points[4], Eigen::Vector3d(2.0, 3.0, 3.0));  // row 1, column 1
  EXPECT_FLOAT_EQ(c.scan->times[4], 0.001f);
  EXPECT_EQ(c.scan->rings[4], 1);
  EXPECT_TRUE(c.scan->intensities.empty());
}

TEST(PointCloudConversion, SkipsNoReturnsAndNonFiniteInNonDenseClouds) {
  CloudMessage msg = ScanToCloud(SmallScan(10), "lidar", 0);
  msg.is_dense = false;
  SetFloat(msg, 2, 0, std::numeric_limits<float>::quiet_NaN());
  for (std::uint32_t off : {0u, 4u, 8u}) SetFloat(msg, 5, off, 0.0f);  // no return
  const CloudConversion c = Convert(msg);
  ASSERT_TRUE(c.scan) << c.error;
  EXPECT_EQ(c.scan->size(), 8u);
  EXPECT_EQ(c.skipped_points, 2u);
  EXPECT_EQ(c.scan->times.size(), 8u);
}

TEST(PointCloudConversion, RejectsNaNInDenseCloud) {
  CloudMessage msg = ScanToCloud(SmallScan(10), "lidar", 0);
  SetFloat(msg, 3, 4, std::numeric_limits<float>::infinity());
  ExpectError(Convert(msg), "non_finite", "point 3 (row 0, column 3) has a non-finite");
}

TEST(PointCloudConversion, RejectsMissingAndMistypedFields) {
  CloudMessage missing = ScanToCloud(SmallScan(), "lidar", 0);
  missing.fields.erase(missing.fields.begin() + 2);  // z
  ExpectError(Convert(missing), "missing_field", "required field 'z' is missing");

  CloudMessage mistyped = ScanToCloud(SmallScan(), "lidar", 0);
  mistyped.fields[0].datatype = dammloam_msg_DATATYPE_UINT16;
  ExpectError(Convert(mistyped), "field_type", "field 'x' is uint16, expected float32 or float64");

  CloudMessage unknown = ScanToCloud(SmallScan(), "lidar", 0);
  unknown.fields[3].datatype = 42;
  ExpectError(Convert(unknown), "fields", "field 'intensity' has unknown datatype 42");

  CloudMessage beyond = ScanToCloud(SmallScan(), "lidar", 0);
  beyond.fields[5].offset = 23;  // uint16 ring at 23..24 > point_step 24
  ExpectError(Convert(beyond), "fields", "field 'ring' (offset 23, 2 bytes) ends beyond point_step 24");

  CloudMessage twice = ScanToCloud(SmallScan(), "lidar", 0);
  twice.fields[1].name = "x";
  ExpectError(Convert(twice), "fields", "field 'x' appears twice");

  CloudMessage zero_count = ScanToCloud(SmallScan(), "lidar", 0);
  zero_count.fields[4].count = 0;
  ExpectError(Convert(zero_count), "fields", "field 't' has count 0");
}

TEST(PointCloudConversion, RejectsInconsistentSizes) {
  CloudMessage truncated = ScanToCloud(SmallScan(), "lidar", 0);
  truncated.data.resize(truncated.data.size() - 10);
  ExpectError(Convert(truncated), "payload_size", "payload is 1190 bytes but height x row_step = 1200 (truncated)");

  CloudMessage row = ScanToCloud(SmallScan(), "lidar", 0);
  row.row_step = 100;
  ExpectError(Convert(row), "row_step", "row_step 100 is smaller than width x point_step = 1200");

  CloudMessage step = ScanToCloud(SmallScan(), "lidar", 0);
  step.point_step = 0;
  ExpectError(Convert(step), "point_step", "point_step is 0");

  CloudMessage empty = ScanToCloud(SmallScan(0), "lidar", 0);
  ExpectError(Convert(empty), "zero_points", "cloud has zero points (height 1 x width 0)");

  CloudMessage big_endian = ScanToCloud(SmallScan(), "lidar", 0);
  big_endian.is_bigendian = true;
  ExpectError(Convert(big_endian), "byte_order", "is_bigendian is true");

  CloudMessage huge = ScanToCloud(SmallScan(), "lidar", 0);
  CloudLimits limits;
  limits.max_bytes = 1000;
  ExpectError(Convert(huge, limits), "too_large", "payload of 1200 bytes exceeds the limit of 1000 bytes");

  CloudMessage bad_stamp = ScanToCloud(SmallScan(), "lidar", 0);
  bad_stamp.stamp.nanosec = 1000000000u;
  ExpectError(Convert(bad_stamp), "stamp", "header.stamp.nanosec is 1000000000");
}

TEST(PointCloudConversion, RejectsBadPointValues) {
  CloudMessage all_zero = ScanToCloud(SmallScan(5), "lidar", 0);
  std::fill(all_zero.data.begin(), all_zero.data.end(), 0);
  ExpectError(Convert(all_zero), "no_valid_points", "no valid points: all 5 points");

  CloudMessage late = ScanToCloud(SmallScan(5), "lidar", 0);
  SetFloat(late, 1, 16, 2.5f);
  ExpectError(Convert(late), "point_time", "point 1 (row 0, column 1) has time 2.5");

  CloudMessage ring = ScanToCloud(SmallScan(5), "lidar", 0);
  const std::uint16_t bad_ring = 70;
  std::memcpy(ring.data.data() + 2 * ring.point_step + 20, &bad_ring, 2);
  ExpectError(Convert(ring), "ring", "point 2 (row 0, column 2) has ring 70");
}

TEST(PointCloudConversion, LabelledCloudRoundTrip) {
  LabelledPoints points;
  for (int i = 0; i < 7; ++i) {
    points.points_sensor.emplace_back(i, 1.0, 2.0);
    points.points_map.emplace_back(i + 10.0, 1.0, 2.0);
    points.normals.emplace_back(0.f, 0.f, 1.f);
    points.labels.push_back(static_cast<PointClass>(i % 5));
  }
  const CloudMessage msg = LabelledToCloud(points, "lidar", 3);
  std::string error;
  const auto back = CloudToLabelled(CloudView(msg).get(), &error);
  ASSERT_TRUE(back) << error;
  ASSERT_EQ(back->labels.size(), 7u);
  for (std::size_t i = 0; i < 7; ++i) {
    EXPECT_EQ(back->labels[i], points.labels[i]);
    EXPECT_NEAR((back->points_map[i] - points.points_map[i]).norm(), 0.0, 1e-5);
    EXPECT_NEAR((back->normals[i] - points.normals[i]).norm(), 0.0, 1e-6);
  }
}

}  // namespace
}  // namespace dammloam::dds
