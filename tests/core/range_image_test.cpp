#include "core/preprocess/range_image.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "tests/core/lidar_raycast.hpp"

namespace dammloam {
namespace {

using test::SyntheticLidar;

// The sensor's own grid (no pixel budget): these tests check where rays land in it.
RangeImageConfig SensorGrid() {
  RangeImageConfig config;
  config.max_auto_pixels = 0;
  return config;
}

TEST(RangeImage, RingAndColumnRaysLandInTheirPixel) {
  const SyntheticLidar lidar;  // 64 x 1024
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> ring(0, lidar.rings - 1), col(0, lidar.cols - 1);
  std::uniform_real_distribution<double> range(0.5, 80.0);
  std::vector<Eigen::Vector3d> points;
  std::vector<std::int16_t> rings;
  std::vector<std::pair<int, int>> pixels;
  for (int i = 0; i < 2000; ++i) {
    const int r = ring(rng), c = col(rng);
    points.push_back(range(rng) * lidar.Direction(r, c));
    rings.push_back(static_cast<std::int16_t>(r));
    pixels.emplace_back(r, c);
  }
  RangeImage image(SensorGrid(), lidar.Model());
  image.Build(points, rings);
  ASSERT_EQ(image.rows(), 64);
  ASSERT_EQ(image.cols(), 1024);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto [r, c] = pixels[i];
    EXPECT_EQ(image.pixel_of(i), r * 1024 + c) << "point " << i;
    const int owner = image.index(r, c);
    ASSERT_GE(owner, 0);
    // Whoever owns the pixel is the nearest of the points that fell in it.
    EXPECT_LE(image.range(r, c), static_cast<float>(points[i].norm()));
    EXPECT_EQ(image.point(r, c), points[static_cast<std::size_t>(owner)].cast<float>());
    EXPECT_FLOAT_EQ(image.range(r, c),
                    static_cast<float>(points[static_cast<std::size_t>(owner)].norm()));
  }
}

TEST(RangeImage, ColumnConventionAndWrap) {
  SensorModel model;
  model.rings = 1;
  model.columns = 8;
  RangeImage image(SensorGrid(), model);
  const double eps = 1e-6;
  const std::vector<Eigen::Vector3d> points = {
      {-1.0, -eps, 0.0},  // azimuth just above -pi: column 0
      {-1.0, +eps, 0.0},  // azimuth just below +pi: last column, neighbour of column 0
      {0.0, -1.0, 0.0},   // -y: a quarter turn on, column 2
      {1.0, 0.0, 0.0},    // +x: column 4
      {0.0, 1.0, 0.0}};   // +y: column 6
  image.Build(points, std::vector<std::int16_t>(points.size(), 0));
  EXPECT_EQ(image.pixel_of(0), 0);
  EXPECT_EQ(image.pixel_of(1), 7);
  EXPECT_EQ(image.pixel_of(2), 2);
  EXPECT_EQ(image.pixel_of(3), 4);
  EXPECT_EQ(image.pixel_of(4), 6);
}

TEST(RangeImage, NearestWinsAndTiesGoToTheLowerIndex) {
  const SyntheticLidar lidar;
  const Eigen::Vector3d d = lidar.Direction(10, 100);
  const std::vector<Eigen::Vector3d> points = {10.0 * d, 5.0 * d, 5.0 * d, 7.0 * d};
  RangeImage image(SensorGrid(), lidar.Model());
  image.Build(points, std::vector<std::int16_t>(points.size(), 10));
  EXPECT_EQ(image.index(10, 100), 1);
  EXPECT_FLOAT_EQ(image.range(10, 100), 5.0f);
  for (std::size_t i = 0; i < points.size(); ++i) EXPECT_EQ(image.pixel_of(i), 10 * 1024 + 100);
  // Every other pixel is empty.
  int occupied = 0;
  for (int r = 0; r < image.rows(); ++r) {
    for (int c = 0; c < image.cols(); ++c) occupied += image.empty(r, c) ? 0 : 1;
  }
  EXPECT_EQ(occupied, 1);
  EXPECT_EQ(image.index(0, 0), -1);
  EXPECT_EQ(image.range(0, 0), 0.0f);
}

TEST(RangeImage, InvalidPointsAndNegativeRingsAreNotProjected) {
  const SyntheticLidar lidar;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Eigen::Vector3d> points = {{nan, 0, 0},
                                               Eigen::Vector3d::Zero(),
                                               3.0 * lidar.Direction(5, 5),
                                               3.0 * lidar.Direction(6, 6)};
  RangeImage image(SensorGrid(), lidar.Model());
  image.Build(points, {5, 5, 5, -1});
  EXPECT_EQ(image.pixel_of(0), -1);
  EXPECT_EQ(image.pixel_of(1), -1);
  EXPECT_EQ(image.pixel_of(2), 5 * 1024 + 5);
  EXPECT_EQ(image.pixel_of(3), -1);
}

TEST(RangeImage, RingsBeyondTheModelGrowTheImage) {
  SensorModel model;
  model.rings = 16;
  model.columns = 360;
  RangeImage image(SensorGrid(), model);
  image.Build({{1, 0, 0}}, {31});
  EXPECT_EQ(image.rows(), 32);
  EXPECT_EQ(image.pixel_of(0) / 360, 31);
}

// Without rings: the nearest listed vertical angle (VLP-16 lists its beams interleaved in
// firing order elsewhere; here they are listed bottom-up to show the order does not matter).
TEST(RangeImage, VerticalAnglesGiveTheNearestBeamRow) {
  SyntheticLidar lidar;
  lidar.rings = 16;
  lidar.cols = 1800;
  lidar.top_deg = 15.0;
  lidar.bottom_deg = -15.0;
  SensorModel model = lidar.Model();
  for (int r = lidar.rings - 1; r >= 0; --r)
    model.vertical_angles_deg.push_back(lidar.ElevationDeg(r));
  std::vector<Eigen::Vector3d> points;
  std::vector<int> expected;
  for (int r = 0; r < lidar.rings; ++r) {
    for (const double offset_deg : {-0.9, 0.0, 0.9}) {  // beams are 2 deg apart
      SyntheticLidar shifted = lidar;
      shifted.top_deg += offset_deg;
      shifted.bottom_deg += offset_deg;
      points.push_back(12.0 * shifted.Direction(r, 300));
      expected.push_back(r);
    }
  }
  // Beyond the outermost beams: clamped to them.
  points.push_back(5.0 * Eigen::Vector3d(1, 0, 1));  // 45 deg up
  expected.push_back(0);
  points.push_back(5.0 * Eigen::Vector3d(1, 0, -1));  // 45 deg down
  expected.push_back(15);
  RangeImage image(SensorGrid(), model);
  image.Build(points, {});
  ASSERT_EQ(image.rows(), 16);
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(image.pixel_of(i) / image.cols(), expected[i]) << "point " << i;
  }
}

TEST(RangeImage, UniformElevationBinsWithoutRingsOrAngles) {
  SyntheticLidar lidar;
  lidar.rings = 16;
  lidar.cols = 1800;
  lidar.top_deg = 15.0;
  lidar.bottom_deg = -15.0;
  std::vector<Eigen::Vector3d> points;
  std::vector<int> expected;
  for (int c = 0; c < lidar.cols; c += 7) {
    for (int r = 0; r < lidar.rings; ++r) {
      points.push_back((3.0 + r) * lidar.Direction(r, c));
      expected.push_back(r);
    }
  }
  RangeImage image(SensorGrid(), lidar.Model());
  image.Build(points, {});
  ASSERT_EQ(image.rows(), 16);
  for (std::size_t i = 0; i < points.size(); ++i) {
    ASSERT_EQ(image.pixel_of(i) / image.cols(), expected[i]) << "point " << i;
  }
}

// HDL-64-like beams (denser near the horizon) stored ring after ring like KITTI .bin files,
// azimuth sweeping -pi..pi per ring: the wrap-arounds give the rows, where uniform elevation
// bins would merge the dense beams. Stragglers across the seam must not start a ring.
TEST(RangeImage, RingMajorOrderGivesTheRings) {
  SyntheticLidar lidar;
  lidar.rings = 64;
  lidar.cols = 1024;
  std::vector<double> elevation_deg;
  for (int r = 0; r < 32; ++r) elevation_deg.push_back(2.0 - r / 3.0);
  for (int r = 0; r < 32; ++r) elevation_deg.push_back(-8.83 - r / 2.0);
  std::vector<Eigen::Vector3d> points;
  std::vector<int> expected;
  for (int r = 0; r < 64; ++r) {
    const double el = elevation_deg[static_cast<std::size_t>(r)] * std::numbers::pi / 180.0;
    for (int c = 0; c < 2000; ++c) {
      const double az = -std::numbers::pi + (c + 0.5) * 2.0 * std::numbers::pi / 2000;
      points.push_back(20.0 * Eigen::Vector3d(std::cos(el) * std::cos(az),
                                              std::cos(el) * std::sin(az), std::sin(el)));
      expected.push_back(r);
      if (r == 31 && c == 0) {  // a late point of ring 30 at azimuth ~+pi after ring 31 began
        const double el30 = elevation_deg[30] * std::numbers::pi / 180.0;
        points.push_back(20.0 * Eigen::Vector3d(-std::cos(el30), 1e-4, std::sin(el30)));
        expected.push_back(30);
      }
    }
  }
  RangeImage image(SensorGrid(), lidar.Model());
  image.Build(points, {});
  ASSERT_EQ(image.rows(), 64);
  int wrong = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    wrong += image.pixel_of(i) / image.cols() != expected[i] ? 1 : 0;
  }
  EXPECT_LE(wrong, 1);  // at most the straggler, which lands in the ring it interrupts
}

TEST(RangeImage, ColumnMajorOrderFallsBackToElevationBins) {
  SyntheticLidar lidar;  // firing order: column by column; azimuth wraps once
  const Scan scan = [&] {
    test::Scene scene;
    scene.planes.push_back({0, 0, 1, 30.0});
    scene.has_room = true;
    scene.room = {{-10, -10, -3}, {10, 10, 3}};
    return test::CastScan(lidar, scene, Eigen::Isometry3d::Identity(), nullptr);
  }();
  RangeImage image(SensorGrid(), lidar.Model());
  image.Build(scan.points, {});
  ASSERT_EQ(image.rows(), 64);
  for (std::size_t i = 0; i < scan.size(); i += 13) {
    ASSERT_EQ(image.pixel_of(i) / image.cols(), scan.rings[i]) << "point " << i;
  }
}

TEST(RangeImage, CorruptRingsAreNotProjected) {
  RangeImage image(SensorGrid(), SensorModel{});
  image.Build({{1, 0, 0}, {0, 1, 0}}, {30000, 2});
  EXPECT_EQ(image.rows(), 64);
  EXPECT_EQ(image.pixel_of(0), -1);
  EXPECT_GE(image.pixel_of(1), 0);
}

TEST(RangeImage, ConfigOverridesTheSensorGrid) {
  RangeImageConfig config;
  config.rows = 8;
  config.cols = 16;
  RangeImage image(config, SensorModel{});
  image.Build({{1, 0, 0}}, {3});
  EXPECT_EQ(image.rows(), 8);
  EXPECT_EQ(image.cols(), 16);
  EXPECT_EQ(image.pixel_of(0), 3 * 16 + 8);
}

TEST(RangeImage, AutomaticColumnsAreTheSensorsUpToTheCap) {
  SensorModel os1;
  os1.rings = 64;
  os1.columns = 1024;
  SensorModel coarse = os1;
  coarse.columns = 256;
  RangeImageConfig config;  // cols 0: automatic
  config.max_auto_pixels = 0;
  EXPECT_EQ(RangeImage(config, os1).cols(), 1024) << "no cap without a pixel budget";
  config.max_auto_cols = 512;
  EXPECT_EQ(RangeImage(config, os1).cols(), 512);
  EXPECT_EQ(RangeImage(config, coarse).cols(), 256);
  config.cols = 2048;  // an explicit count is taken as it is
  config.max_auto_cols = 512;
  EXPECT_EQ(RangeImage(config, os1).cols(), 2048);
}

// The default pixel budget halves a dense sensor's columns and leaves a sparse one's grid.
TEST(RangeImage, PixelBudgetCutsOnlyDenseSensors) {
  SensorModel os1;
  os1.rings = 64;
  os1.columns = 1024;
  SensorModel vlp;
  vlp.rings = 16;
  vlp.columns = 1800;
  SensorModel os1_128 = os1;
  os1_128.rings = 128;
  const RangeImageConfig defaults;
  EXPECT_EQ(RangeImage(defaults, os1).cols(), 512);
  EXPECT_EQ(RangeImage(defaults, vlp).cols(), 1800);
  EXPECT_EQ(RangeImage(defaults, os1_128).cols(), 512) << "never below min_auto_cols";
  RangeImageConfig config;
  config.rows = 32;  // the image's rows, not the sensor's, count
  EXPECT_EQ(RangeImage(config, os1).cols(), 1024);
  config.rows = 0;
  config.min_auto_cols = 64;
  EXPECT_EQ(RangeImage(config, os1_128).cols(), 256);
  config.cols = 2048;  // an explicit count is taken as it is
  EXPECT_EQ(RangeImage(config, os1).cols(), 2048);
}

}  // namespace
}  // namespace dammloam
