#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <limits>
#include <random>
#include <tuple>

#include "core/map/map_config.hpp"
#include "core/map/voxel_hash_map.hpp"
#include "synthetic_scenes.hpp"

namespace dammloam {
namespace {

TEST(VoxelHashMap, NeighbourSearchIsClassWise) {
  VoxelHashMap map(1.0, 100.0, 20);
  map.AddPoints({{{0.1, 0.0, 0.0}, {0, 0, 1}, PointClass::Ground},
                 {{0.5, 0.0, 0.0}, {0, 1, 0}, PointClass::Wall}});
  const Eigen::Vector3d query(0.0, 0.0, 0.0);
  const MapPoint* any = map.ClosestNeighbour(query, std::nullopt);
  ASSERT_NE(any, nullptr);
  EXPECT_EQ(any->label, PointClass::Ground);
  const MapPoint* wall = map.ClosestNeighbour(query, PointClass::Wall);
  ASSERT_NE(wall, nullptr);
  EXPECT_EQ(wall->label, PointClass::Wall);
  EXPECT_DOUBLE_EQ(wall->position.x(), 0.5);
  EXPECT_EQ(map.ClosestNeighbour(query, PointClass::Edge), nullptr);
}

TEST(VoxelHashMap, SearchCoversExactlyTheNeighbouringVoxels) {
  VoxelHashMap map(1.0, 100.0, 20);
  map.AddPoints({{{1.9, 0.5, 0.5}, {0, 0, 0}, PointClass::Edge}});  // voxel (1,0,0)
  EXPECT_NE(map.ClosestNeighbour({0.5, 0.5, 0.5}, std::nullopt), nullptr);  // voxel (0,0,0)
  EXPECT_EQ(map.ClosestNeighbour({-0.5, 0.5, 0.5}, std::nullopt), nullptr);  // two voxels away
}

// A remembered answer is kept only where a fresh search would give it again: over random
// maps, queries and moves up to 10 cm (class-wise and not, with and without a gate, answers
// with a point and without), every "still nearest" is the point Nearest returns at the new
// place. The check must also say yes often enough to be worth making.
TEST(VoxelHashMap, StillNearestNeverKeepsAnAnswerAFreshSearchWouldChange) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> in_box(-1.5, 1.5);
  std::uniform_real_distribution<double> step(-0.05, 0.05);
  std::uniform_int_distribution<int> class_of(0, 1);
  int kept = 0, kept_without_point = 0, asked = 0;
  for (int trial = 0; trial < 40; ++trial) {
    VoxelHashMap map(0.5, 100.0, 20);
    std::vector<MapPoint> points;
    for (int i = 0; i < 60; ++i) {
      const PointClass label = class_of(rng) == 0 ? PointClass::Wall : PointClass::Edge;
      points.push_back({{in_box(rng), in_box(rng), in_box(rng)}, {0, 0, 0}, label});
    }
    map.AddPoints(points);
    for (int q = 0; q < 50; ++q) {
      const Eigen::Vector3d query(in_box(rng), in_box(rng), in_box(rng));
      const std::optional<PointClass> label =
          q % 3 == 0 ? std::nullopt : std::optional<PointClass>(PointClass::Wall);
      const double gate = q % 2 == 0 ? 0.3 : std::numeric_limits<double>::infinity();
      const VoxelHashMap::NearestPoint answer = map.Nearest(query, label, gate);
      EXPECT_EQ(answer.point, map.ClosestNeighbour(query, label, gate));
      for (int m = 0; m < 10; ++m) {
        const Eigen::Vector3d moved = query + Eigen::Vector3d(step(rng), step(rng), step(rng));
        ++asked;
        if (!map.StillNearest(answer, query, moved, gate)) continue;
        ++kept;
        if (answer.point == nullptr) ++kept_without_point;
        ASSERT_EQ(map.Nearest(moved, label, gate).point, answer.point)
            << "trial " << trial << " query " << q << " move " << m;
      }
    }
  }
  EXPECT_GT(kept, asked / 10) << kept << " of " << asked;  // 24 % here: sparse points, long moves
  EXPECT_GT(kept_without_point, 0);
}

TEST(VoxelHashMap, CapsPointsPerVoxelPerClass) {
  VoxelHashMap map(1.0, 100.0, 3);
  std::vector<MapPoint> points;
  // The eight corners of the voxel: far enough apart that only the cap limits them.
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d corner(i & 1 ? 0.95 : 0.05, i & 2 ? 0.95 : 0.05, i & 4 ? 0.95 : 0.05);
    points.push_back({corner, {0, 0, 1}, PointClass::Ground});
    points.push_back({corner, {0, 1, 0}, PointClass::Wall});
  }
  map.AddPoints(points);
  EXPECT_EQ(map.NumVoxels(), 1u);
  EXPECT_EQ(map.NumPoints(), 6u);  // 3 ground + 3 wall: one class cannot crowd out the other
}

// A surface seen again adds nothing where it is already sampled: a point closer than
// voxel / sqrt(max points) to one of its class in the voxel is dropped, so revisits do not
// grow the map.
TEST(VoxelHashMap, RevisitsDoNotAddNearDuplicates) {
  VoxelHashMap map(1.0, 100.0, 4);  // spacing 0.5 m
  map.AddPoints({{{0.1, 0.1, 0.1}, {0, 0, 1}, PointClass::Ground}});
  map.AddPoints({{{0.3, 0.1, 0.1}, {0, 0, 1}, PointClass::Ground},    // 0.2 m away: dropped
                 {{0.3, 0.1, 0.1}, {0, 1, 0}, PointClass::Wall},      // other class: kept
                 {{0.7, 0.1, 0.1}, {0, 0, 1}, PointClass::Ground}});  // 0.6 m away: kept
  EXPECT_EQ(map.NumPoints(), 3u);
  for (int revisit = 0; revisit < 10; ++revisit) {
    map.AddPoints({{{0.1 + 0.01 * revisit, 0.1, 0.1}, {0, 0, 1}, PointClass::Ground}});
  }
  EXPECT_EQ(map.NumPoints(), 3u);
}

TEST(VoxelHashMap, UpdateTransformsPointsAndNormalsAndDropsFarVoxels) {
  VoxelHashMap map(0.5, 10.0, 20);
  const Eigen::Isometry3d T = test::MakePose(5.0, 0.0, 0.0, 0.0, 0.0, M_PI / 2);
  map.Update({{1.0, 0.0, 0.0}}, {PointClass::Wall}, {Eigen::Vector3f(-1, 0, 0)}, T);
  const auto points = map.Points();
  ASSERT_EQ(points.size(), 1u);
  EXPECT_NEAR((points[0].position - Eigen::Vector3d(5.0, 1.0, 0.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((points[0].normal - Eigen::Vector3f(0, -1, 0)).norm(), 0.0, 1e-6);
  // Sensor moves 20 m away: the voxel is beyond max_distance and must go.
  map.Update({}, {}, {}, test::MakePose(25.0, 0.0, 0.0, 0, 0, 0));
  EXPECT_TRUE(map.empty());
}

// The 27-voxel neighbourhood of a tilted plane, all classes together: its covariance's smallest
// eigenvector is the plane's normal and carries no variance; one voxel farther is outside it.
TEST(VoxelHashMap, NeighbourhoodOfAPlaneGivesItsNormal) {
  VoxelHashMap map(0.5, 100.0, 20);
  const Eigen::Vector3d normal = Eigen::Vector3d(0.0, 1.0, 1.0).normalized();
  const Eigen::Vector3d u(1.0, 0.0, 0.0), w = normal.cross(u);
  std::vector<MapPoint> points;
  for (double a = -3.0; a <= 3.0; a += 0.1) {
    for (double b = -3.0; b <= 3.0; b += 0.1) {
      const auto label = (a + b > 0.0) ? PointClass::Wall : PointClass::Edge;
      points.push_back({a * u + b * w, Eigen::Vector3f::Zero(), label});
    }
  }
  map.AddPoints(points);
  const VoxelHashMap::Neighbourhood hood = map.NeighbourhoodOf({0.1, 0.0, 0.0});
  ASSERT_GT(hood.count, 50);
  EXPECT_NEAR(hood.mean.dot(normal), 0.0, 1e-9);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(hood.covariance);
  EXPECT_LT(eig.eigenvalues()(0), 1e-12);
  EXPECT_GT(eig.eigenvalues()(1), 0.05);
  EXPECT_NEAR(std::abs(eig.eigenvectors().col(0).dot(normal)), 1.0, 1e-9);
  // Points beyond the 27 voxels do not count: the neighbourhood spans at most 1.5 m per axis.
  EXPECT_LT(hood.covariance.trace(), 3 * 0.75 * 0.75);
  EXPECT_EQ(map.NeighbourhoodOf({0.0, 10.0, 10.0}).count, 0);
}

std::vector<Voxel> Sorted(std::vector<Voxel> voxels) {
  std::sort(voxels.begin(), voxels.end(), [](const Voxel& a, const Voxel& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  });
  return voxels;
}

// What a cache of neighbourhood answers must forget: every voxel that gained a point or was
// cropped, once per list, and nothing that only refused a point; a new, copied, moved or
// cleared map may have changed anywhere.
TEST(VoxelHashMap, TakeChangesListsEveryChangedVoxelOnce) {
  VoxelHashMap map(1.0, 10.0, 2);
  EXPECT_TRUE(map.TakeChanges().all);  // nothing known about it yet
  map.AddPoints({{{0.1, 0.1, 0.1}, {0, 0, 1}, PointClass::Ground},
                 {{0.9, 0.9, 0.1}, {0, 0, 1}, PointClass::Ground},    // same voxel again
                 {{2.5, 0.5, 0.5}, {0, 1, 0}, PointClass::Wall}});
  VoxelHashMap::Changes changes = map.TakeChanges();
  EXPECT_FALSE(changes.all);
  EXPECT_EQ(Sorted(changes.voxels), (std::vector<Voxel>{{0, 0, 0}, {2, 0, 0}}));
  EXPECT_TRUE(map.TakeChanges().voxels.empty());  // taken: the next list starts empty
  // The ground voxel is full (2 per class): a third ground point changes nothing.
  map.AddPoints({{{0.5, 0.5, 0.9}, {0, 0, 1}, PointClass::Ground}});
  EXPECT_TRUE(map.TakeChanges().voxels.empty());
  map.AddPoints({{{0.5, 0.5, 0.9}, {0, 1, 0}, PointClass::Wall}});  // another class: added
  EXPECT_EQ(map.TakeChanges().voxels, (std::vector<Voxel>{{0, 0, 0}}));
  // The sensor at x = 11.5 m: the voxel at the origin lies beyond 10 m and is cropped.
  map.Update({}, {}, {}, test::MakePose(11.5, 0.0, 0.0, 0, 0, 0));
  changes = map.TakeChanges();
  EXPECT_FALSE(changes.all);
  EXPECT_EQ(changes.voxels, (std::vector<Voxel>{{0, 0, 0}}));
  EXPECT_EQ(map.NumVoxels(), 1u);
  VoxelHashMap copy = map;
  EXPECT_TRUE(copy.TakeChanges().all);
  VoxelHashMap moved = std::move(copy);
  EXPECT_TRUE(moved.TakeChanges().all);
  map = moved;
  EXPECT_TRUE(map.TakeChanges().all);
  // A block copied in carries the copy's list numbers: it is still listed when it changes.
  map.AddPoints({{{2.05, 0.05, 0.95}, {0, 1, 0}, PointClass::Wall}});
  EXPECT_EQ(map.TakeChanges().voxels, (std::vector<Voxel>{{2, 0, 0}}));
  map.Clear();
  EXPECT_TRUE(map.TakeChanges().all);
}

// Voxels grow a point at a time over many revisits, move within the map's storage when they
// outgrow their room, and the storage closes the holes they leave: whatever the order of
// additions and removals, the map holds exactly the points added and not removed, each found
// where it is, with its class and normal.
TEST(VoxelHashMap, KeepsEveryPointThroughGrowthRemovalAndCompaction) {
  // Points on a 0.25 m lattice in 1 m voxels with room for 100 per class: none is refused (64
  // lattice sites per voxel, spacing above the 0.1 m sampling distance), so the truth is simple.
  VoxelHashMap map(1.0, 1000.0, 100);
  std::mt19937 rng(5);
  std::vector<Eigen::Vector3i> sites;
  for (int x = 0; x < 40; ++x) {
    for (int y = 0; y < 40; ++y) {
      for (int z = 0; z < 12; ++z) sites.emplace_back(x, y, z);
    }
  }
  std::shuffle(sites.begin(), sites.end(), rng);
  auto point_at = [](const Eigen::Vector3i& site) {
    const PointClass label = site.sum() % 3 == 0 ? PointClass::Wall : PointClass::Ground;
    const Eigen::Vector3f normal = Eigen::Vector3f::Unit(site.x() % 3);
    return MapPoint{site.cast<double>() * 0.25, normal, label};
  };
  std::vector<MapPoint> truth;
  auto key = [](const MapPoint& p) {
    return std::make_tuple(p.position.x(), p.position.y(), p.position.z());
  };
  std::size_t next_site = 0;
  for (int round = 0; round < 60; ++round) {
    std::vector<MapPoint> batch;
    for (int i = 0; i < 250 && next_site < sites.size(); ++i) {
      batch.push_back(point_at(sites[next_site++]));
    }
    map.AddPoints(batch);
    truth.insert(truth.end(), batch.begin(), batch.end());
    if (round % 4 == 3) {  // people leaving: a ball's walls go
      const Eigen::Vector3d centre(std::uniform_real_distribution<double>(0.0, 10.0)(rng),
                                   std::uniform_real_distribution<double>(0.0, 10.0)(rng), 1.5);
      auto gone = [&](const MapPoint& p) {
        return p.label == PointClass::Wall && (p.position - centre).norm() < 2.5;
      };
      const std::size_t removed = map.RemovePointsIf(centre, 2.5, gone);
      const std::size_t before = truth.size();
      truth.erase(std::remove_if(truth.begin(), truth.end(), gone), truth.end());
      ASSERT_EQ(removed, before - truth.size()) << "round " << round;
    }
    ASSERT_EQ(map.NumPoints(), truth.size()) << "round " << round;
  }
  std::vector<MapPoint> stored = map.Points();
  ASSERT_EQ(stored.size(), truth.size());
  auto by_position = [&](const MapPoint& a, const MapPoint& b) { return key(a) < key(b); };
  std::sort(stored.begin(), stored.end(), by_position);
  std::sort(truth.begin(), truth.end(), by_position);
  for (std::size_t i = 0; i < truth.size(); ++i) {
    ASSERT_EQ(stored[i].position, truth[i].position) << i;
    ASSERT_EQ(stored[i].label, truth[i].label) << i;
    ASSERT_EQ(stored[i].normal, truth[i].normal) << i;
    const MapPoint* found = map.ClosestNeighbour(truth[i].position, truth[i].label);
    ASSERT_NE(found, nullptr) << i;
    ASSERT_EQ(found->position, truth[i].position) << i;
  }
  // Cropping drops whole voxels far from the sensor and keeps every point of the rest.
  VoxelHashMap cropped(1.0, 3.0, 100);
  cropped.AddPoints(truth);
  cropped.RemoveFarVoxels(Eigen::Vector3d(5.0, 5.0, 1.5));
  std::size_t near = 0;
  for (const MapPoint& p : truth) {
    const double d = (p.position - Eigen::Vector3d(5.0, 5.0, 1.5)).norm();
    if (d >= 3.0 - std::sqrt(3.0)) continue;  // closer: every point of its voxel is within 3 m
    ++near;
    ASSERT_NE(cropped.ClosestNeighbour(p.position, p.label), nullptr);
  }
  EXPECT_GT(near, 100u);
  for (const MapPoint& p : cropped.Points()) {
    EXPECT_LT((p.position - Eigen::Vector3d(5.0, 5.0, 1.5)).norm(), 3.0 + std::sqrt(3.0));
  }
  cropped.AddPoints({point_at({0, 0, 0})});  // the storage takes points again after the crop
  EXPECT_NE(cropped.ClosestNeighbour(Eigen::Vector3d::Zero(), std::nullopt), nullptr);
}

TEST(MapConfig, AutoVoxelSizeFollowsTheScene) {
  MapConfig config;
  EXPECT_DOUBLE_EQ(AutoVoxelSize(config, 2.0), config.auto_voxel_min);   // corridor
  EXPECT_DOUBLE_EQ(AutoVoxelSize(config, 60.0), config.auto_voxel_max);  // open field
  EXPECT_NEAR(AutoVoxelSize(config, 12.0), 0.6, 1e-12);
  config.voxel_size = 0.7;
  EXPECT_DOUBLE_EQ(AutoVoxelSize(config, 2.0), 0.7);  // explicit wins
}

}  // namespace
}  // namespace dammloam
