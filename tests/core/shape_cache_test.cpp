#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/map/voxel_hash_map.hpp"
#include "core/registration/registration_config.hpp"
#include "core/registration/shape_cache.hpp"

namespace dammloam {
namespace {

// A floor z = 0 sampled every 0.1 m over 6 m x 6 m, in 0.5 m voxels.
std::vector<MapPoint> Floor() {
  std::vector<MapPoint> points;
  for (double x = -2.95; x < 3.0; x += 0.1) {
    for (double y = -2.95; y < 3.0; y += 0.1) {
      points.push_back({{x, y, 0.0}, {0, 0, 1}, PointClass::Ground});
    }
  }
  return points;
}

// A wall x = 0.3 m standing on the floor, up to 1 m.
std::vector<MapPoint> WallAcrossTheOrigin() {
  std::vector<MapPoint> points;
  for (double y = -1.0; y <= 1.0; y += 0.1) {
    for (double z = 0.05; z <= 1.0; z += 0.1) {
      points.push_back({{0.3, y, z}, {-1, 0, 0}, PointClass::Wall});
    }
  }
  return points;
}

Eigen::Vector3d Centre(const Eigen::Vector3d& p, const VoxelHashMap& map) {
  const double size = map.voxel_size();
  return (PointToVoxel(p, size).cast<double>().array() + 0.5).matrix() * size;
}

void ExpectSameShape(const LocalShape& a, const LocalShape& b) {
  EXPECT_EQ(a.judged, b.judged);
  EXPECT_EQ(a.planes, b.planes);
  for (int k = 0; k < a.planes; ++k) EXPECT_EQ(a.n[k], b.n[k]);  // bit for bit
}

// Kept across map updates, a shape is forgotten exactly where the map changed around it: at a
// voxel a wall now crosses the cache answers what a fresh look at the map answers (no longer a
// floor), while a floor voxel 2 m away keeps its answer.
TEST(ShapeCache, ForgetsShapesWhoseNeighbourhoodChanged) {
  VoxelHashMap map(0.5, 100.0, 50);
  map.AddPoints(Floor());
  RegistrationConfig config;
  config.point_shape_min_points = 5;
  ShapeCache cache;
  cache.Forget(map.TakeChanges());
  cache.Bind(map, config);
  const std::vector<Eigen::Vector3d> targets{{0.1, 0.1, 0.0}, {2.6, 2.6, 0.0}};
  const auto at = [&](std::size_t i) { return targets[i]; };
  std::vector<const LocalShape*> shapes = cache.Lookup(2, at);
  ASSERT_TRUE(shapes[0]->judged);
  EXPECT_EQ(shapes[0]->planes, 1);
  EXPECT_NEAR(std::abs(shapes[0]->n[0].z()), 1.0, 1e-9);
  EXPECT_EQ(cache.size(), 2u);

  map.AddPoints(WallAcrossTheOrigin());
  const LocalShape fresh = ShapeAround(map, Centre(targets[0], map), config);
  ASSERT_NE(fresh.planes, 1);  // the floor and the wall: no longer one plane
  // Not told of the change, the cache still answers the floor: it relies on Forget.
  EXPECT_EQ(cache.Lookup(1, at)[0]->planes, 1);

  cache.Forget(map.TakeChanges());
  EXPECT_EQ(cache.size(), 1u);  // the far floor voxel is kept
  cache.Bind(map, config);
  shapes = cache.Lookup(2, at);
  ExpectSameShape(*shapes[0], fresh);
  ExpectSameShape(*shapes[1], ShapeAround(map, Centre(targets[1], map), config));

  // Other shape settings: nothing cached is valid for them.
  config.point_flatness = 0.05;
  cache.Bind(map, config);
  EXPECT_EQ(cache.size(), 0u);
}

}  // namespace
}  // namespace dammloam
