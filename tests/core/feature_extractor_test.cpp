#include "core/preprocess/feature_extractor.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <thread>

#include "tests/core/lidar_raycast.hpp"
#include "tests/support/data_dir.hpp"

namespace dammloam {
namespace {

using test::CastScan;
using test::Scene;
using test::SyntheticLidar;

Scene Room() {
  Scene scene;
  scene.has_room = true;
  scene.room = {{-7.0, -6.0, -1.4}, {7.0, 6.0, 1.6}};  // sensor at the origin, 1.4 m up
  return scene;
}

TEST(FeatureExtractor, DropsInvalidPointsAndKeepsFieldsAligned) {
  const SyntheticLidar lidar;
  Scan scan = CastScan(lidar, Room(), Eigen::Isometry3d::Identity(), nullptr);
  const std::size_t valid = scan.size();
  // intensities carry the original index so alignment can be checked after compaction.
  scan.times.resize(valid);
  for (std::size_t i = 0; i < valid; ++i) {
    scan.intensities[i] = static_cast<float>(i);
    scan.times[i] = 0.05f;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<Eigen::Vector3d> bad = {{nan, 1, 1}, {inf, 0, 0}, {0.1, 0, 0}, {500, 0, 0}};
  for (const auto& p : bad) {
    scan.points.insert(scan.points.begin() + 100, p);
    scan.intensities.insert(scan.intensities.begin() + 100, -1.0f);
    scan.times.insert(scan.times.begin() + 100, 0.05f);
    scan.rings.insert(scan.rings.begin() + 100, 3);
  }
  // A valid point with a NaN time is dropped as well.
  scan.points.push_back({2, 0, 0});
  scan.intensities.push_back(-1.0f);
  scan.times.push_back(std::numeric_limits<float>::quiet_NaN());
  scan.rings.push_back(32);

  const FeatureExtractor extractor(PreprocessConfig{}, lidar.Model());
  const ClassifiedScan out = extractor.Extract(scan, Eigen::Matrix3d::Identity());
  EXPECT_EQ(out.dropped_invalid, 5u);
  ASSERT_EQ(out.scan.size(), valid);
  ASSERT_EQ(out.scan.intensities.size(), valid);
  ASSERT_EQ(out.scan.times.size(), valid);
  ASSERT_EQ(out.scan.rings.size(), valid);
  ASSERT_EQ(out.labels.size(), valid);
  ASSERT_EQ(out.normals.size(), valid);
  for (std::size_t i = 0; i < valid; ++i) ASSERT_EQ(out.scan.intensities[i], float(i));
  std::uint32_t total = 0;
  for (const auto count : out.class_counts) total += count;
  EXPECT_EQ(total, valid);
  EXPECT_GE(out.projection_ms, 0.0);
  EXPECT_GE(out.normals_ms, 0.0);
  EXPECT_GE(out.classification_ms, 0.0);
}

TEST(FeatureExtractor, InconsistentOptionalFieldsAreDiscarded) {
  const SyntheticLidar lidar;
  Scan scan = CastScan(lidar, Room(), Eigen::Isometry3d::Identity(), nullptr);
  scan.times.assign(10, 0.0f);
  const ClassifiedScan out = FeatureExtractor(PreprocessConfig{}, lidar.Model())
                                 .Extract(scan, Eigen::Matrix3d::Identity());
  EXPECT_TRUE(out.scan.times.empty());
  EXPECT_EQ(out.scan.rings.size(), out.scan.size());
  EXPECT_EQ(out.labels.size(), out.scan.size());
}

TEST(FeatureExtractor, LabelsAndNormalsOfARoom) {
  const SyntheticLidar lidar;
  std::vector<int> surfaces;
  const Scan scan = CastScan(lidar, Room(), Eigen::Isometry3d::Identity(), &surfaces);
  const ClassifiedScan out = FeatureExtractor(PreprocessConfig{}, lidar.Model())
                                 .Extract(scan, Eigen::Matrix3d::Identity());
  int right = 0;
  for (std::size_t i = 0; i < out.scan.size(); ++i) {
    const PointClass expected = surfaces[i] == 4   ? PointClass::Ground
                                : surfaces[i] == 5 ? PointClass::Roof
                                                   : PointClass::Wall;
    right += out.labels[i] == expected;
    const float norm = out.normals[i].norm();
    EXPECT_TRUE(norm == 0.0f || std::abs(norm - 1.0f) < 1e-5f);
    if (IsPlanar(out.labels[i])) {
      EXPECT_NEAR(norm, 1.0f, 1e-5f);
      EXPECT_LE(out.normals[i].cast<double>().dot(out.scan.points[i]), 0.0);
    }
  }
  EXPECT_GT(double(right) / out.scan.size(), 0.9);
  EXPECT_GT(out.class_counts[Index(PointClass::Edge)], 0u);
}

// Points that lose their pixel to a nearer one: a close one inherits the winner's label and
// normal, a far one (another surface behind) stays Unknown without a normal.
TEST(FeatureExtractor, PixelLosersInheritOnlyWhenClose) {
  const SyntheticLidar lidar;
  Scan scan = CastScan(lidar, Room(), Eigen::Isometry3d::Identity(), nullptr);
  const std::size_t n = scan.size();
  std::vector<std::size_t> near_of, far_of;
  for (std::size_t i = 0; i < n; i += 97) {
    const Eigen::Vector3d dir = scan.points[i].normalized();
    near_of.push_back(i);
    scan.points.push_back(scan.points[i] + 0.05 * dir);
    scan.rings.push_back(scan.rings[i]);
    scan.intensities.push_back(0.0f);
    far_of.push_back(i);
    scan.points.push_back(scan.points[i] + 1.0 * dir);
    scan.rings.push_back(scan.rings[i]);
    scan.intensities.push_back(0.0f);
  }
  const ClassifiedScan out = FeatureExtractor(PreprocessConfig{}, lidar.Model())
                                 .Extract(scan, Eigen::Matrix3d::Identity());
  for (std::size_t k = 0; k < near_of.size(); ++k) {
    const std::size_t winner = near_of[k];
    const std::size_t close = n + 2 * k, far = n + 2 * k + 1;
    EXPECT_EQ(out.labels[close], out.labels[winner]);
    EXPECT_EQ(out.normals[close], out.normals[winner]);
    EXPECT_EQ(out.labels[far], PointClass::Unknown);
    EXPECT_EQ(out.normals[far], Eigen::Vector3f::Zero());
  }
}

TEST(FeatureExtractor, ConcurrentCallsGiveIdenticalResults) {
  const SyntheticLidar lidar;
  const Scan scan = CastScan(lidar, Room(), Eigen::Isometry3d::Identity(), nullptr);
  const FeatureExtractor extractor(PreprocessConfig{}, lidar.Model());
  ClassifiedScan a, b;
  std::thread ta([&] { a = extractor.Extract(scan, Eigen::Matrix3d::Identity()); });
  std::thread tb([&] { b = extractor.Extract(scan, Eigen::Matrix3d::Identity()); });
  ta.join();
  tb.join();
  EXPECT_EQ(a.labels, b.labels);
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.class_counts, b.class_counts);
}

// Real data: KITTI HDL-64E scans (x y z reflectance float32, no rings, no times).
std::filesystem::path KittiDir() { return test::DataDir() / "kitti_hdl64_patchworkpp_6frames"; }

Scan ReadKittiBin(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::vector<float> values(std::filesystem::file_size(file) / sizeof(float));
  in.read(reinterpret_cast<char*>(values.data()),
          static_cast<std::streamsize>(values.size() * sizeof(float)));
  Scan scan;
  for (std::size_t i = 0; i + 3 < values.size(); i += 4) {
    scan.points.emplace_back(values[i], values[i + 1], values[i + 2]);
    scan.intensities.push_back(values[i + 3]);
  }
  return scan;
}

TEST(FeatureExtractor, KittiRoadBelowTheSensorIsGround) {
  const std::filesystem::path dir = KittiDir();
  DAMMLOAM_REQUIRE_DATA(dir / "000000.bin");
  SensorModel hdl64;
  hdl64.rings = 64;
  hdl64.columns = 1024;  // ~2000 returns per beam: 1024 columns leave few holes
  hdl64.max_range = 120.0;
  const FeatureExtractor extractor(PreprocessConfig{}, hdl64);
  for (const char* name : {"000000.bin", "000003.bin"}) {
    const ClassifiedScan out =
        extractor.Extract(ReadKittiBin(dir / name), Eigen::Matrix3d::Identity());
    ASSERT_GT(out.scan.size(), 100000u);
    int road = 0, ground = 0;
    for (std::size_t i = 0; i < out.scan.size(); ++i) {
      const Eigen::Vector3d& p = out.scan.points[i];
      const double horizontal = p.head<2>().norm();
      if (std::abs(p.z() + 1.73) > 0.15 || horizontal < 4.0 || horizontal > 20.0) continue;
      ++road;
      ground += out.labels[i] == PointClass::Ground;
    }
    ASSERT_GT(road, 5000) << name;
    const double share = double(ground) / road;
    std::printf("%s: %d road points, %.1f %% ground; counts u/g/r/w/e = %u %u %u %u %u\n", name,
                road, 100.0 * share, out.class_counts[0], out.class_counts[1], out.class_counts[2],
                out.class_counts[3], out.class_counts[4]);
    EXPECT_GT(share, 0.5) << name;
  }
}

}  // namespace
}  // namespace dammloam
