#include "core/preprocess/normal_map.hpp"

#include <gtest/gtest.h>

#include <utility>

#include <cmath>
#include <numbers>

#include "tests/core/lidar_raycast.hpp"

namespace dammloam {
namespace {

using test::CastScan;
using test::Scene;
using test::SyntheticLidar;

double AngleDeg(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 /
         std::numbers::pi;
}

struct PlaneResult {
  int hit_pixels = 0;
  int valid = 0;
  double worst_angle_deg = 0.0;
  bool all_face_sensor = true;
};

// The OS1-64-like sensor's own 64 x 1024 grid (no pixel budget).
RangeImageConfig SensorGrid() {
  RangeImageConfig config;
  config.max_auto_pixels = 0;
  return config;
}

// Casts one infinite plane with an OS1-64-like sensor and checks every valid normal.
PlaneResult CheckPlane(const Eigen::Vector3d& normal_towards_sensor, double offset,
                       const RangeImageConfig& grid = SensorGrid()) {
  Scene scene;
  scene.planes.push_back(
      {normal_towards_sensor.x(), normal_towards_sensor.y(), normal_towards_sensor.z(), offset});
  const SyntheticLidar lidar;
  const Scan scan = CastScan(lidar, scene, Eigen::Isometry3d::Identity(), nullptr, 60.0);
  RangeImage image(grid, lidar.Model());
  image.Build(scan.points, scan.rings);
  const NormalMap normals(image, NormalMapConfig{});
  PlaneResult result;
  for (int r = 0; r < image.rows(); ++r) {
    for (int c = 0; c < image.cols(); ++c) {
      if (image.empty(r, c)) continue;
      ++result.hit_pixels;
      if (!normals.valid(r, c)) {
        EXPECT_EQ(normals.normal(r, c), Eigen::Vector3f::Zero());
        continue;
      }
      ++result.valid;
      const Eigen::Vector3d n = normals.normal(r, c).cast<double>();
      EXPECT_NEAR(n.norm(), 1.0, 1e-6);
      result.worst_angle_deg = std::max(result.worst_angle_deg, AngleDeg(n, normal_towards_sensor));
      if (n.dot(image.point(r, c).cast<double>()) > 0.0) result.all_face_sensor = false;
    }
  }
  return result;
}

TEST(NormalMap, FloorBelowTheSensor) {
  const PlaneResult result = CheckPlane({0, 0, 1}, 1.5);  // z = -1.5
  ASSERT_GT(result.hit_pixels, 20000);
  // Rows next to the empty upper half and the grazing far field are invalid; the rest is not.
  EXPECT_GT(result.valid, result.hit_pixels / 2);
  EXPECT_LT(result.worst_angle_deg, 1.0);
  EXPECT_TRUE(result.all_face_sensor);
}

TEST(NormalMap, WallBesideTheSensor) {
  const PlaneResult result = CheckPlane({0, -1, 0}, 2.0);  // y = 2
  ASSERT_GT(result.hit_pixels, 20000);
  EXPECT_GT(result.valid, result.hit_pixels / 2);
  EXPECT_LT(result.worst_angle_deg, 1.0);
  EXPECT_TRUE(result.all_face_sensor);
}

// The default pixel budget gives this sensor 512 columns (0.7 deg pixels): the normals of a
// floor and a wall are as good as on the sensor's grid.
TEST(NormalMap, PlanesOnTheDefaultBudgetedGrid) {
  for (const auto& [normal, offset] : {std::pair{Eigen::Vector3d(0, 0, 1), 1.5},
                                       std::pair{Eigen::Vector3d(0, -1, 0), 2.0}}) {
    const PlaneResult result = CheckPlane(normal, offset, RangeImageConfig{});
    ASSERT_GT(result.hit_pixels, 10000);
    EXPECT_GT(result.valid, result.hit_pixels / 2);
    EXPECT_LT(result.worst_angle_deg, 1.0);
    EXPECT_TRUE(result.all_face_sensor);
  }
}

TEST(NormalMap, TiltedPlane) {
  const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.4, 1.0).normalized();
  const PlaneResult result = CheckPlane(n, 2.0);  // n.x = -2: below, facing up to the sensor
  ASSERT_GT(result.hit_pixels, 10000);
  EXPECT_GT(result.valid, result.hit_pixels / 2);
  EXPECT_LT(result.worst_angle_deg, 1.0);
  EXPECT_TRUE(result.all_face_sensor);
}

// A box standing 3 m in front of a wall 6 m away: pixels whose 4-neighbourhood mixes box and
// wall lie across a depth discontinuity and must be invalid; pixels fully on one surface away
// from the silhouette keep their exact normal.
TEST(NormalMap, DepthDiscontinuityIsInvalid) {
  Scene scene;
  scene.planes.push_back({-1, 0, 0, 6.0});  // x = 6, normal towards the sensor
  scene.solids.push_back({{3.0, -1.0, -1.0}, {3.5, 1.0, 1.0}});
  const SyntheticLidar lidar;
  std::vector<int> surfaces;
  const Scan scan = CastScan(lidar, scene, Eigen::Isometry3d::Identity(), &surfaces, 60.0);
  RangeImage image(RangeImageConfig{}, lidar.Model());
  image.Build(scan.points, scan.rings);
  const NormalMap normals(image, NormalMapConfig{});

  auto surface_at = [&](int r, int c) {
    const int i = image.index(r, (c + image.cols()) % image.cols());
    return i < 0 ? -1 : surfaces[static_cast<std::size_t>(i)];
  };
  int boundary = 0, interior_box = 0, interior_wall = 0;
  for (int r = 1; r + 1 < image.rows(); ++r) {
    for (int c = 0; c < image.cols(); ++c) {
      const int s = surface_at(r, c);
      if (s < 0) continue;
      const int neighbours[4] = {surface_at(r, c - 1), surface_at(r, c + 1), surface_at(r - 1, c),
                                 surface_at(r + 1, c)};
      bool mixed = false;
      for (const int q : neighbours) mixed |= (q == 10) != (s == 10);
      if (mixed) {
        ++boundary;
        EXPECT_FALSE(normals.valid(r, c)) << "pixel " << r << "," << c;
        continue;
      }
      // Interior: all 4 neighbours on this surface and those on the box on its front face.
      if (s == 20 && normals.valid(r, c)) {
        ++interior_wall;
        EXPECT_LT(AngleDeg(normals.normal(r, c).cast<double>(), {-1, 0, 0}), 1.0);
      }
      if (s == 10 && normals.valid(r, c) && image.point(r, c).x() < 3.0f + 1e-6f) {
        ++interior_box;
      }
    }
  }
  EXPECT_GT(boundary, 100);
  EXPECT_GT(interior_box, 500);
  EXPECT_GT(interior_wall, 5000);
}

}  // namespace
}  // namespace dammloam
