// Compact objects: small things standing on the ground are found in ray-cast scenes, and only
// where they would be the main witness of a direction the rest of the scan observes weakly
// (the axis of a featureless corridor) are they set aside.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/odometry/compact_objects.hpp"
#include "core/preprocess/downsample.hpp"
#include "core/preprocess/feature_extractor.hpp"
#include "tests/core/lidar_raycast.hpp"

namespace dammloam {
namespace {

using test::AlignedBox;
using test::CastScan;
using test::Scene;
using test::SyntheticLidar;

constexpr double kFloor = -1.4;  // the sensor is held 1.4 m above the floor
const Eigen::Vector3d kAxis = Eigen::Vector3d::UnitX();  // the corridor's

// A corridor 2.4 m wide and 2.8 m high along x, no end in sight (infinite planes: floor 20,
// ceiling 21, walls 22 and 23).
Scene Corridor() {
  Scene scene;
  scene.planes = {{0, 0, 1, -kFloor}, {0, 0, 1, -1.4}, {0, 1, 0, 1.2}, {0, 1, 0, -1.2}};
  return scene;
}

// A person 0.45 m wide, 0.3 m deep, 1.75 m tall, standing on the floor at (x, y).
AlignedBox Person(double x, double y) {
  return {{x - 0.15, y - 0.225, kFloor}, {x + 0.15, y + 0.225, kFloor + 1.75}};
}

struct Extracted {
  ClassifiedScan scan;
  std::vector<int> surfaces;  // per kept point
};

// The scan as the pipeline sees it: cast, then labelled and given normals by the feature stage.
Extracted Observe(const Scene& scene, double max_range = 40.0) {
  const SyntheticLidar lidar;
  const Scan cast = CastScan(lidar, scene, Eigen::Isometry3d::Identity(), nullptr, max_range);
  const FeatureExtractor extractor(PreprocessConfig{}, lidar.Model());
  Extracted out{extractor.Extract(cast, Eigen::Matrix3d::Identity()), {}};
  for (float surface : out.scan.scan.intensities) out.surfaces.push_back(static_cast<int>(surface));
  return out;
}

// The registration source, as the odometry downsamples it.
std::vector<std::size_t> Source(const ClassifiedScan& scan) {
  ClassAwareDownsampler downsampler(DownsampleConfig{});
  return downsampler.Select(scan.scan.points, scan.labels);
}

struct Share {
  int on = 0, marked = 0;
};

Share Marked(const Extracted& e, const std::vector<std::uint8_t>& mask, int surface) {
  Share s;
  for (std::size_t i = 0; i < e.surfaces.size(); ++i) {
    if (e.surfaces[i] != surface) continue;
    ++s.on;
    s.marked += mask[i];
  }
  return s;
}

// Walking 0.175 m from the wall: grouped with the wall they would be part of a long structure;
// only what faces the axis is grouped (the wall does not), and the body around it is taken.
TEST(CompactObjects, APersonBesideTheWallIsCompactAndTheCorridorIsNot) {
  Scene scene = Corridor();
  scene.solids.push_back(Person(2.5, 0.8));
  const Extracted e = Observe(scene);
  CompactObjects objects({});
  const std::vector<std::uint8_t>& mask =
      objects.Find(e.scan.scan.points, e.scan.labels, e.scan.normals, kAxis, Eigen::Matrix3d::Identity());
  ASSERT_EQ(mask.size(), e.scan.scan.points.size()) << "the ground height was not found";
  // Grouped by what faces the axis, then the whole body: front, sides and shoulders.
  const Share person = Marked(e, mask, 10);
  ASSERT_GT(person.on, 200);
  EXPECT_GE(person.marked, 0.95 * person.on);
  for (int surface : {20, 21}) EXPECT_EQ(Marked(e, mask, surface).marked, 0) << surface;
  // At the edges of the person's shadow a few wall normals mix both surfaces, face the axis
  // and join the person; the body then reaches the wall there. Nothing of the walls farther
  // than 2 m along the corridor from the person is taken.
  for (int wall : {22, 23}) {
    int far_marked = 0, wall_points = 0;
    for (std::size_t i = 0; i < mask.size(); ++i) {
      if (e.surfaces[i] != wall) continue;
      ++wall_points;
      far_marked += mask[i] && std::abs(e.scan.scan.points[i].x() - 2.5) > 2.0;
    }
    ASSERT_GT(wall_points, 1000);
    EXPECT_EQ(far_marked, 0) << "wall " << wall;
  }
}

TEST(CompactObjects, PillarsAndLampsUnderTheCeilingAreNotCompact) {
  Scene scene = Corridor();
  scene.solids.push_back({{3.0, -0.2, kFloor}, {3.4, 0.2, 1.4}});    // a pillar, floor to ceiling
  scene.solids.push_back({{-3.2, -0.3, 1.1}, {-2.8, 0.3, 1.4}});     // a lamp under the ceiling
  const Extracted e = Observe(scene);
  CompactObjects objects({});
  const std::vector<std::uint8_t>& mask =
      objects.Find(e.scan.scan.points, e.scan.labels, e.scan.normals, kAxis, Eigen::Matrix3d::Identity());
  ASSERT_FALSE(mask.empty());
  const Share pillar = Marked(e, mask, 10), lamp = Marked(e, mask, 11);
  ASSERT_GT(pillar.on, 100);
  ASSERT_GT(lamp.on, 20);
  EXPECT_EQ(pillar.marked, 0);
  EXPECT_EQ(lamp.marked, 0);
}

TEST(CompactObjects, WithoutGroundNothingIsJudged) {
  Scene scene = Corridor();
  scene.solids.push_back(Person(2.5, 0.5));
  Extracted e = Observe(scene);
  std::vector<PointClass> walls(e.scan.labels.size(), PointClass::Wall);
  CompactObjects objects({});
  EXPECT_TRUE(objects.Find(e.scan.scan.points, walls, e.scan.normals, kAxis, Eigen::Matrix3d::Identity()).empty());
}

TEST(CompactObjects, APersonIsSetAsideOnlyWhereTheyAloneObserveTheCorridorAxis) {
  // No end in range: the person's front and back are all that faces the axis.
  Scene open = Corridor();
  open.solids.push_back(Person(2.5, 0.5));
  const Extracted e = Observe(open);
  CompactObjects objects({});
  const std::vector<std::uint8_t> mask =
      objects.Find(e.scan.scan.points, e.scan.labels, e.scan.normals, kAxis, Eigen::Matrix3d::Identity());
  EXPECT_TRUE(ObjectsWitnessTheWeakAxis(e.scan.normals, Source(e.scan), mask, {}));

  // In a room 8 x 6 m the walls observe every direction: the person stays in.
  Scene room;
  room.has_room = true;
  room.room = {{-4.0, -3.0, kFloor}, {4.0, 3.0, 1.4}};
  room.solids.push_back(Person(2.5, 0.5));
  const Extracted r = Observe(room);
  const std::vector<std::uint8_t> room_mask =
      objects.Find(r.scan.scan.points, r.scan.labels, r.scan.normals, kAxis, Eigen::Matrix3d::Identity());
  ASSERT_GT(Marked(r, room_mask, 10).marked, 200);
  EXPECT_FALSE(ObjectsWitnessTheWeakAxis(r.scan.normals, Source(r.scan), room_mask, {}));

  // Nobody there: nothing to set aside, however weak the axis.
  const Extracted empty = Observe(Corridor());
  const std::vector<std::uint8_t> none =
      objects.Find(empty.scan.scan.points, empty.scan.labels, empty.scan.normals, kAxis, Eigen::Matrix3d::Identity());
  EXPECT_FALSE(ObjectsWitnessTheWeakAxis(empty.scan.normals, Source(empty.scan), none, {}));
}

// A partition 1.2 m ahead reaches the ceiling, but the highest beam meets it 1.9 m above the
// floor: seen, it is as short as a person. It goes on above the view, so it is not compact,
// while a person as near, whose head is below the view's top, still is.
TEST(CompactObjects, AWallFacetThatGoesOnAboveTheViewIsNotCompact) {
  Scene scene = Corridor();
  scene.solids.push_back({{1.2, -1.2, kFloor}, {1.3, 0.3, 1.4}});  // floor to ceiling
  scene.solids.push_back(Person(-2.5, 0.5));
  const Extracted e = Observe(scene);
  CompactObjects objects({});
  const std::vector<std::uint8_t>& mask =
      objects.Find(e.scan.scan.points, e.scan.labels, e.scan.normals, kAxis, Eigen::Matrix3d::Identity());
  ASSERT_FALSE(mask.empty());
  const Share facet = Marked(e, mask, 10), person = Marked(e, mask, 11);
  ASSERT_GT(facet.on, 500);
  double facet_top = -1e9;
  for (std::size_t i = 0; i < e.surfaces.size(); ++i) {
    if (e.surfaces[i] == 10) facet_top = std::max(facet_top, e.scan.scan.points[i].z() - kFloor);
  }
  ASSERT_LT(facet_top, CompactObjectsConfig{}.max_height) << "seen as short as a person";
  EXPECT_EQ(facet.marked, 0);
  ASSERT_GT(person.on, 200);
  EXPECT_GE(person.marked, 0.95 * person.on);
}

// A group walking beside the sensor is seen side-on: little of it faces the corridor's axis and
// none of it is a compact object facing it, yet its corners and what does face the axis would
// hold the axis once mapped. In the open corridor those points wait (MapLater), the walls and
// floor do not; in a room, whose walls observe the axis, only compact objects would wait.
TEST(CompactObjects, WhatWouldWitnessAWeakAxisIsMappedLater) {
  Scene open = Corridor();
  for (double x : {-0.6, 0.0, 0.6}) open.solids.push_back(Person(x, 0.8));
  const Extracted e = Observe(open);
  const WeakestAxis weakest = WeakestAxisOf(e.scan.normals, Source(e.scan));
  EXPECT_GT(std::abs(weakest.direction.x()), 0.9);
  ASSERT_LT(weakest.share, CompactObjectsConfig{}.weak_axis_ratio);
  const std::vector<std::uint8_t> later = MapLater(e.scan.labels, e.scan.normals, weakest, {}, {});
  ASSERT_EQ(later.size(), e.scan.scan.points.size());
  int group_on = 0, group_later = 0;
  for (int person : {10, 11, 12}) {
    const Share share = Marked(e, later, person);
    group_on += share.on;
    group_later += share.marked;
  }
  ASSERT_GT(group_on, 500);
  EXPECT_GT(group_later, 0.2 * group_on) << "fronts, backs and corners";
  // The open wall waits for a few stray normals only; floor and ceiling within 10 m only where
  // they meet the walls or the group's feet (corner lines, labelled edges like every corner;
  // farther, the rings' sparse ends are edges too).
  const Share open_wall = Marked(e, later, 22);
  ASSERT_GT(open_wall.on, 1000);
  EXPECT_LT(open_wall.marked, 0.03 * open_wall.on);
  for (int surface : {20, 21}) {
    int away_from_walls = 0;
    for (std::size_t i = 0; i < later.size(); ++i) {
      const Eigen::Vector3d& p = e.scan.scan.points[i];
      const bool at_feet = std::abs(p.x()) < 1.2 && std::abs(p.y() - 0.8) < 0.5;
      away_from_walls += e.surfaces[i] == surface && later[i] && std::abs(p.x()) < 10.0 &&
                         std::abs(p.y()) < 0.85 && !at_feet;
    }
    EXPECT_EQ(away_from_walls, 0) << surface << " of " << Marked(e, later, surface).marked;
  }

  Scene room;
  room.has_room = true;
  room.room = {{-4.0, -3.0, kFloor}, {4.0, 3.0, 1.4}};
  for (double x : {-0.6, 0.0, 0.6}) room.solids.push_back(Person(x, 0.8));
  const Extracted r = Observe(room);
  const WeakestAxis observed = WeakestAxisOf(r.scan.normals, Source(r.scan));
  ASSERT_GE(observed.share, CompactObjectsConfig{}.weak_axis_ratio);
  std::vector<std::uint8_t> objects(r.scan.scan.points.size(), 0);
  objects[0] = 1;
  const std::vector<std::uint8_t> room_later = MapLater(r.scan.labels, r.scan.normals, observed, objects, {});
  EXPECT_EQ(std::count(room_later.begin(), room_later.end(), 1), 1) << "the object mask alone";
}

}  // namespace
}  // namespace dammloam
