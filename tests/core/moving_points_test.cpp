// Moving points: the free-space test of a past scan's DepthView, its spread over objects, and
// the removal of map points that have moved away, on exact ray-cast rooms.
#include <gtest/gtest.h>

#include "core/geometry/depth_view.hpp"
#include "core/map/voxel_hash_map.hpp"
#include "core/odometry/moving_points.hpp"
#include "tests/core/lidar_raycast.hpp"

namespace dammloam {
namespace {

using test::AlignedBox;
using test::CastScan;
using test::Scene;
using test::SyntheticLidar;

constexpr int kPersonSurface = 10;  // the first solid

Scene Room() {
  Scene scene;
  scene.has_room = true;
  scene.room = {{-10, -5, -1.5}, {10, 5, 1.5}};
  return scene;
}

// A 0.45 x 0.3 x 1.7 m person standing on the floor with its centre at (x, y).
AlignedBox Person(double x, double y) { return {{x - 0.15, y - 0.225, -1.5}, {x + 0.15, y + 0.225, 0.2}}; }

Eigen::Isometry3d At(double x, double y) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, y, 0.0);
  return T;
}

// Floor and ceiling are ground and roof, as the classifier would have them.
std::vector<PointClass> Labels(const std::vector<int>& surfaces) {
  std::vector<PointClass> labels;
  for (int s : surfaces) {
    labels.push_back(s == 4 ? PointClass::Ground : s == 5 ? PointClass::Roof : PointClass::Wall);
  }
  return labels;
}

struct Counts {
  int person = 0, person_moving = 0, other = 0, other_moving = 0;
};

Counts Count(const std::vector<int>& surfaces, const std::vector<std::uint8_t>& moving) {
  Counts c;
  for (std::size_t i = 0; i < surfaces.size(); ++i) {
    if (surfaces[i] == kPersonSurface) {
      ++c.person;
      c.person_moving += moving[i];
    } else {
      ++c.other;
      c.other_moving += moving[i];
    }
  }
  return c;
}

TEST(DepthView, PointsShortOfTheReturnsAroundThemWereSeenThrough) {
  const SyntheticLidar lidar;
  const Scan scan = CastScan(lidar, Room(), At(0, 0), nullptr);
  const DepthView view({}, lidar.Model(), scan.points, At(0, 0));
  EXPECT_TRUE(view.SeesThrough({5.0, 0.0, 0.0}, 0.3));     // the x+ wall is at 10 m
  EXPECT_FALSE(view.SeesThrough({9.9, 0.0, 0.0}, 0.3));    // on the wall, within the margin
  EXPECT_FALSE(view.SeesThrough({12.0, 0.0, 0.0}, 0.3));   // behind the wall
  EXPECT_FALSE(view.SeesThrough({0.1, 0.0, 5.0}, 0.3));    // above the beams: never observed
  // From another place: the view keeps its pose.
  const Scan moved = CastScan(lidar, Room(), At(4, 0), nullptr);
  const DepthView from_four({}, lidar.Model(), moved.points, At(4, 0));
  EXPECT_FALSE(from_four.SeesThrough({8.0, 0.0, 0.0}, 6.0));   // the wall is 6 m from it
  EXPECT_TRUE(from_four.SeesThrough({2.0, 0.0, 0.0}, 0.3));    // behind it, 2 m of 14 m
  EXPECT_FALSE(from_four.SeesThrough({-11.0, 0.0, 0.0}, 0.3)); // behind the x- wall
}

TEST(MovingPoints, APersonWhereTheRoomWasSeenThroughMovesAndTheRoomDoesNot) {
  const SyntheticLidar lidar;
  MovingPointsConfig config;
  config.enabled = true;
  MovingPoints detector(config, lidar.Model());
  // The sensor walks along x; one second ago the person was 2 m to the side of where it is now.
  Scene before = Room();
  before.solids.push_back(Person(4.0, -2.5));
  std::vector<int> surfaces_before;
  const Scan earlier = CastScan(lidar, before, At(0, 0), &surfaces_before);
  detector.AddView(earlier.points, Labels(surfaces_before), At(0, 0), 0.0);
  Scene now = Room();
  now.solids.push_back(Person(4.0, 1.5));
  std::vector<int> surfaces;
  const Scan scan = CastScan(lidar, now, At(1.0, 0), &surfaces);
  const Counts c = Count(surfaces, detector.Detect(scan.points, Labels(surfaces), At(1.0, 0), 1.0));
  ASSERT_GT(c.person, 200);
  EXPECT_GE(c.person_moving, 0.95 * c.person);
  EXPECT_EQ(c.other_moving, 0) << "of " << c.other << " static points";
}

TEST(MovingPoints, AStandingPersonAndAStaticRoomSeenFromAMovingSensorDoNotMove) {
  const SyntheticLidar lidar;
  MovingPointsConfig config;
  config.enabled = true;
  MovingPoints detector(config, lidar.Model());
  Scene scene = Room();
  scene.solids.push_back(Person(4.0, 1.5));
  scene.solids.push_back({{-3, 3, -1.5}, {-1, 5, 1.5}});  // a pillar against the wall
  for (int k = 0; k <= 10; ++k) {
    const Eigen::Isometry3d T = At(0.12 * k, 0.02 * k);
    std::vector<int> surfaces;
    const Scan scan = CastScan(lidar, scene, T, &surfaces);
    const Counts c = Count(surfaces, detector.Detect(scan.points, Labels(surfaces), T, 0.1 * k));
    EXPECT_EQ(c.person_moving + c.other_moving, 0) << "scan " << k;
    detector.AddView(scan.points, Labels(surfaces), T, 0.1 * k);
  }
}

TEST(MovingPoints, NothingMovesWithoutAViewOldEnough) {
  const SyntheticLidar lidar;
  MovingPointsConfig config;
  config.view_ages = {0.5};
  MovingPoints detector(config, lidar.Model());
  std::vector<int> room_surfaces;
  const Scan empty_room = CastScan(lidar, Room(), At(0, 0), &room_surfaces);
  detector.AddView(empty_room.points, Labels(room_surfaces), At(0, 0), 0.0);
  Scene now = Room();
  now.solids.push_back(Person(3.0, 0.0));
  std::vector<int> surfaces;
  const Scan scan = CastScan(lidar, now, At(0, 0), &surfaces);
  const auto young = detector.Detect(scan.points, Labels(surfaces), At(0, 0), 0.3);
  EXPECT_EQ(Count(surfaces, young).person_moving, 0);
  const auto old_enough = detector.Detect(scan.points, Labels(surfaces), At(0, 0), 0.6);
  EXPECT_GT(Count(surfaces, old_enough).person_moving, 0);
}

// A person walking away along the line of sight stands where the last views could not look: its
// own earlier body hid the place. The space it vacated, now seen through, is the evidence. The
// wall behind, revealed only now, is explained by the map and does not move.
TEST(MovingPoints, APersonWalkingAwayAlongTheLineOfSightMovesAndTheRoomDoesNot) {
  const SyntheticLidar lidar;
  MovingPointsConfig config;
  config.enabled = true;
  MovingPoints detector(config, lidar.Model());
  std::vector<int> room_surfaces;
  const Scan room = CastScan(lidar, Room(), At(0, 0), &room_surfaces);
  VoxelHashMap map(0.3, 100.0, 3);
  map.Update(room.points, Labels(room_surfaces), {}, At(0, 0));
  for (int k = 0; k <= 10; ++k) {  // one second of walking away at 1.2 m/s, 10 scans
    Scene scene = Room();
    scene.solids.push_back(Person(2.0 + 0.12 * k, 0.0));
    std::vector<int> surfaces;
    const Scan scan = CastScan(lidar, scene, At(0, 0), &surfaces);
    const std::vector<std::uint8_t> moving =
        detector.Detect(scan.points, Labels(surfaces), At(0, 0), 0.1 * k, &map);
    const Counts c = Count(surfaces, moving);
    if (k >= 5) {  // a view half a second old
      ASSERT_GT(c.person, 100) << "scan " << k;
      EXPECT_GE(c.person_moving, 0.9 * c.person) << "scan " << k;
    }
    EXPECT_EQ(c.other_moving, 0) << "scan " << k << ", of " << c.other << " static points";
    // Without the map nothing says the place behind is not a wall just revealed.
    if (k == 10) {
      EXPECT_EQ(Count(surfaces, detector.Detect(scan.points, Labels(surfaces), At(0, 0), 1.0))
                    .person_moving,
                0);
    }
    detector.AddView(scan.points, Labels(surfaces), At(0, 0), 0.1 * k);
  }
}

TEST(VoxelHashMapRemoval, APersonMappedThenSeenThroughIsRemovedAndTheRoomStays) {
  const SyntheticLidar lidar;
  Scene with_person = Room();
  with_person.solids.push_back(Person(3.0, 0.0));
  std::vector<int> surfaces;
  const Scan mapped = CastScan(lidar, with_person, At(0, 0), &surfaces);
  VoxelHashMap map(0.3, 100.0, 3);
  map.Update(mapped.points, Labels(surfaces), {}, At(0, 0));
  const std::size_t before = map.NumPoints();
  // The person has left: a later scan sees the wall through where it stood.
  const Scan later = CastScan(lidar, Room(), At(0.5, 0), nullptr);
  const DepthView view({}, lidar.Model(), later.points, At(0.5, 0));
  const std::size_t removed = map.RemovePointsIf({0.5, 0, 0}, 40.0, [&](const MapPoint& p) {
    return CanMove(p.label) && view.SeesThrough(p.position, 0.3);
  });
  EXPECT_EQ(map.NumPoints(), before - removed);
  // Within the later scan's view: below about -0.9 m its lowest beams (-22.5 deg, 2.5 m
  // ahead) no longer have a row beneath them, and an unobserved place is never judged.
  int person_left = 0;
  for (const MapPoint& p : map.Points()) {
    if (p.position.x() > 2.8 && p.position.x() < 3.2 && std::abs(p.position.y()) < 0.3 &&
        p.position.z() > -0.9) {
      ++person_left;
      ADD_FAILURE() << "left at " << p.position.transpose();
    }
  }
  EXPECT_GT(removed, 20u);
  EXPECT_EQ(person_left, 0);
  // The room: everything but the person's points is still there.
  const auto points = map.Points();
  EXPECT_TRUE(std::any_of(points.begin(), points.end(),
                          [](const MapPoint& p) { return p.position.x() > 9.8; }));
  EXPECT_LT(removed, before / 10);
}

}  // namespace
}  // namespace dammloam
