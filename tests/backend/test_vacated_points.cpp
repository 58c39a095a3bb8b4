// The global map without what moved away: keyframes that later see through a place leave the
// points mapped there out (core/backend/vacated_points.hpp), on exact ray-cast rooms.
#include <gtest/gtest.h>

#include "core/backend/global_map.hpp"
#include "core/backend/point_to_plane_icp.hpp"
#include "tests/core/lidar_raycast.hpp"

namespace dammloam::backend {
namespace {

using test::AlignedBox;
using test::Scene;

constexpr double kKeyframeVoxel = 0.4;  // BackendConfig's default

// A VLP-16's beams: 16 rings over +-15 deg, 0.2 deg columns.
test::SyntheticLidar Vlp16Like() {
  test::SyntheticLidar lidar;
  lidar.rings = 16;
  lidar.cols = 1800;
  lidar.top_deg = 15.0;
  lidar.bottom_deg = -15.0;
  return lidar;
}

SensorModel ModelOf(const test::SyntheticLidar& lidar) {
  SensorModel model = lidar.Model();
  for (int r = 0; r < lidar.rings; ++r) model.vertical_angles_deg.push_back(lidar.ElevationDeg(r));
  return model;
}

// A hall 40 x 12 x 4 m, the sensor 1.4 m above its floor.
Scene Hall() {
  Scene scene;
  scene.has_room = true;
  scene.room = {{-20, -6, -1.4}, {20, 6, 2.6}};
  return scene;
}

// A 0.45 x 0.3 x 1.7 m person on the floor with its centre at (x, y).
AlignedBox Person(double x, double y) { return {{x - 0.15, y - 0.225, -1.4}, {x + 0.15, y + 0.225, 0.3}}; }

constexpr int kFirstSolid = 10;  // surface id of scene.solids[0] (lidar_raycast.hpp)

// Keyframe k: the sensor at x = -8 + 2 k on the hall's axis, its scan thinned as the back-end
// stores it. Points on solid `moving_solid` are what the front end judged moving: kept only as
// occluders.
Keyframe KeyframeIn(const Scene& scene, int k, int moving_solid = -1) {
  const test::SyntheticLidar lidar = Vlp16Like();
  Keyframe kf;
  kf.id = static_cast<std::uint32_t>(k);
  kf.stamp = k;
  kf.T_world_sensor.translation() = Eigen::Vector3d(-8.0 + 2.0 * k, 0.0, 0.0);
  std::vector<int> surfaces;
  const Scan scan = test::CastScan(lidar, scene, kf.T_world_sensor, &surfaces);
  for (std::size_t i : VoxelDownsampleIndices(scan.points, kKeyframeVoxel)) {
    if (surfaces[i] == kFirstSolid + moving_solid) {
      kf.occluders.push_back(scan.points[i]);
      continue;
    }
    kf.points.push_back(scan.points[i]);
    // The floor is ground and the ceiling roof, as the classifier would have them.
    kf.labels.push_back(surfaces[i] == 4 ? PointClass::Ground : surfaces[i] == 5 ? PointClass::Roof : PointClass::Wall);
  }
  return kf;
}

// Keyframes 0..n-1; the person stands at `where` in those for which `present(k)` holds.
template <typename Present>
std::vector<Keyframe> Walk(int n, const AlignedBox& person, Present present) {
  std::vector<Keyframe> keyframes;
  for (int k = 0; k < n; ++k) {
    Scene scene = Hall();
    if (present(k)) scene.solids.push_back(person);
    keyframes.push_back(KeyframeIn(scene, k));
  }
  return keyframes;
}

// Inside the body (grown by 5 cm) and more than `above_floor` metres above the floor: the floor
// under it is no trail.
bool InBody(const AlignedBox& body, const Eigen::Vector3d& p, double above_floor = 0.15) {
  constexpr double kMargin = 0.05;
  return (p.array() >= body.min.array() - kMargin).all() && (p.array() <= body.max.array() + kMargin).all() &&
         p.z() > body.min.z() + above_floor;
}

std::size_t CountIn(const GlobalMap& map, const AlignedBox& body, double above_floor = 0.15) {
  std::size_t n = 0;
  for (const Eigen::Vector3d& p : map.points) n += InBody(body, p, above_floor) ? 1 : 0;
  return n;
}

GlobalMap Cleaned(const std::vector<Keyframe>& keyframes) {
  return AssembleGlobalMap(keyframes, 0.3, ModelOf(Vlp16Like()), kKeyframeVoxel, VacatedPointsConfig{});
}

TEST(VacatedPoints, APersonWhoWalkedOffLeavesNoTrailAndTheHallKeepsEveryPoint) {
  const AlignedBox person = Person(2.0, -2.5);
  // Standing there while the first three keyframes were taken, gone for the last four.
  const std::vector<Keyframe> keyframes = Walk(7, person, [](int k) { return k < 3; });
  const GlobalMap all = AssembleGlobalMap(keyframes, 0.3);
  const GlobalMap cleaned = Cleaned(keyframes);
  const std::size_t trail = CountIn(all, person);
  ASSERT_GT(trail, 8u);
  // Gone above the knees. Lower down, the beam below each point meets the floor short of it
  // from every later view (a VLP-16's rings lie 2 deg apart): what a ray did not pass, the
  // test does not clear.
  EXPECT_EQ(CountIn(cleaned, person, 0.6), 0u);
  EXPECT_LE(CountIn(cleaned, person), trail / 2);
  // Nothing else went: every point removed was the person's.
  EXPECT_EQ(all.points.size() - cleaned.points.size(), trail - CountIn(cleaned, person));
  EXPECT_EQ(cleaned.vacated, all.points.size() - cleaned.points.size());
  // Without the cleaning the same keyframes keep the trail.
  VacatedPointsConfig off;
  off.enabled = false;
  EXPECT_EQ(CountIn(AssembleGlobalMap(keyframes, 0.3, ModelOf(Vlp16Like()), kKeyframeVoxel, off), person), trail);
}

TEST(VacatedPoints, WhatTheNewestKeyframesStillSeeStays) {
  const AlignedBox person = Person(2.0, -2.5);
  // Always there (a parked car): kept.
  const GlobalMap stays = Cleaned(Walk(7, person, [](int) { return true; }));
  EXPECT_GT(CountIn(stays, person), 8u);
  EXPECT_EQ(stays.vacated, 0u);
  // Gone for two keyframes, then back where it stood: the newest views see it, so it is kept.
  const GlobalMap back = Cleaned(Walk(7, person, [](int k) { return k < 2 || k > 3; }));
  EXPECT_GT(CountIn(back, person), 8u);
  // Seen through once only (min_views 2 by default): kept too.
  const GlobalMap once = Cleaned(Walk(7, person, [](int k) { return k != 5; }));
  EXPECT_GT(CountIn(once, person), 8u);
}

TEST(VacatedPoints, WhatAMovingThingHidLaterIsNotTakenForGone) {
  // A pillar, mapped from 10-11 m away; from the fourth keyframe on a van stands between it and
  // the walk, and the front end leaves the van out as moving. Seen from 4-6 m, no return around
  // the pillar's foot would mean nothing is there, were the van not kept as an occluder.
  const AlignedBox pillar{{1.8, -4.2, -1.4}, {2.2, -3.8, 2.6}};
  const AlignedBox van{{-0.5, -2.4, -1.4}, {4.5, -1.6, 0.3}};
  std::vector<Keyframe> keyframes;
  for (int k = 0; k < 7; ++k) {
    Scene scene = Hall();
    scene.solids.push_back(pillar);
    if (k >= 3) scene.solids.push_back(van);
    keyframes.push_back(KeyframeIn(scene, k, /*moving_solid=*/1));
  }
  const std::size_t mapped = CountIn(AssembleGlobalMap(keyframes, 0.3), pillar);
  ASSERT_GT(mapped, 8u);
  EXPECT_EQ(CountIn(Cleaned(keyframes), pillar), mapped);
  // Without the occluders the same views would take the pillar's foot.
  for (Keyframe& kf : keyframes) kf.occluders.clear();
  EXPECT_LT(CountIn(Cleaned(keyframes), pillar), mapped);
}

}  // namespace
}  // namespace dammloam::backend
