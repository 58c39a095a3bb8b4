#include "core/preprocess/downsample.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <random>
#include <tsl/robin_set.h>

#include "core/geometry/first_per_cell.hpp"
#include "core/geometry/voxel.hpp"

namespace dammloam {
namespace {

// A room-like cloud: dense floor and walls, a few edge points along a corner, some clutter.
struct LabelledPoints {
  std::vector<Eigen::Vector3d> points;
  std::vector<PointClass> labels;
};

LabelledPoints Cloud(unsigned seed, double shift = 0.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  LabelledPoints c;
  auto add = [&](const Eigen::Vector3d& p, PointClass label) {
    c.points.push_back(p + Eigen::Vector3d(shift, 0, 0));
    c.labels.push_back(label);
  };
  for (int i = 0; i < 40000; ++i)
    add({40 * u(rng) - 20, 40 * u(rng) - 20, -1.5}, PointClass::Ground);
  for (int i = 0; i < 20000; ++i) add({40 * u(rng) - 20, 10.0, 6 * u(rng) - 1.5}, PointClass::Wall);
  for (int i = 0; i < 5000; ++i) add({30 * u(rng) - 15, 30 * u(rng) - 15, 3.0}, PointClass::Roof);
  for (int i = 0; i < 300; ++i) add({20.0, 10.0, 6 * u(rng) - 1.5}, PointClass::Edge);
  for (int i = 0; i < 3000; ++i)
    add({20 * u(rng) - 10, 20 * u(rng) - 10, 3 * u(rng)}, PointClass::Unknown);
  return c;
}

TEST(VoxelDownsample, OnePointPerVoxelFirstComeDeterministic) {
  std::vector<Eigen::Vector3d> points;
  // 4 points per 1 m voxel on a 5 x 5 x 1 grid, then a point in the first voxel again.
  for (int k = 0; k < 4; ++k) {
    for (int x = 0; x < 5; ++x) {
      for (int y = 0; y < 5; ++y) points.push_back({x + 0.1 + 0.2 * k, y + 0.5, 0.5});
    }
  }
  points.push_back({0.95, 0.05, 0.01});
  const auto kept = VoxelDownsample(points, 1.0);
  ASSERT_EQ(kept.size(), 25u);
  for (std::size_t i = 0; i < kept.size(); ++i) EXPECT_EQ(kept[i], i);  // first of each voxel
  EXPECT_EQ(VoxelDownsample(points, 1.0), kept);
  EXPECT_TRUE(VoxelDownsample(points, 0.0).empty());
  // Negative coordinates: floor, not truncation, so -0.5 and 0.5 are different voxels.
  EXPECT_EQ(VoxelDownsample({{-0.5, 0, 0}, {0.5, 0, 0}}, 1.0).size(), 2u);
  EXPECT_EQ(PointToVoxel({-0.5, 0.5, -1.0}, 1.0), Voxel(-1, 0, -1));
}

// The partitioned, parallel selection must keep exactly what one sequential first-come pass
// over the points keeps, scan after scan (the tables are reused), with per-class grids.
TEST(FirstPerCell, EqualsOneSequentialPass) {
  FirstPerCell first_per_cell;
  const std::array<double, kNumPointClasses> sizes{2.0, 0.8, 0.8, 0.5, 1.5, 1.0};
  for (unsigned seed = 1; seed <= 3; ++seed) {
    LabelledPoints cloud = Cloud(seed, 0.1 * seed);
    std::shuffle(cloud.labels.begin(), cloud.labels.begin() + 1000, std::mt19937(seed));
    tsl::robin_set<ClassVoxel, ClassVoxelHash> seen;
    std::vector<std::size_t> expected;
    for (std::size_t i = 0; i < cloud.points.size(); ++i) {
      const ClassVoxel cell{PointToVoxel(cloud.points[i], sizes[Index(cloud.labels[i])]),
                            cloud.labels[i]};
      if (seen.insert(cell).second) expected.push_back(i);
    }
    const std::vector<std::size_t> kept = first_per_cell.Select(cloud.points, cloud.labels, sizes);
    ASSERT_GT(expected.size(), 1000u);
    EXPECT_EQ(kept, expected) << "seed " << seed;
  }
  // Missing labels count as unknown.
  const LabelledPoints cloud = Cloud(4);
  const std::vector<std::size_t> unlabelled = first_per_cell.Select(cloud.points, {}, sizes);
  const std::vector<PointClass> unknown(cloud.points.size(), PointClass::Unknown);
  EXPECT_EQ(unlabelled, first_per_cell.Select(cloud.points, unknown, sizes));
}

TEST(ClassAwareDownsampler, KeepsOnePointPerVoxelPerClass) {
  DownsampleConfig config;
  config.target_points = 1000000;
  config.max_step = 1.0;  // freeze the sizes
  ClassAwareDownsampler sampler(config);
  // Two classes share one voxel: both survive.
  const std::vector<Eigen::Vector3d> points = {{0.1, 0.1, 0.1}, {0.2, 0.1, 0.1}, {0.15, 0.1, 0.1}};
  const std::vector<PointClass> labels = {PointClass::Ground, PointClass::Ground, PointClass::Edge};
  EXPECT_EQ(sampler.Select(points, labels), (std::vector<std::size_t>{0, 2}));
  EXPECT_TRUE(sampler.Select(points, {PointClass::Ground}).empty());  // size mismatch
}

TEST(ClassAwareDownsampler, AdaptsToTheTargetAndKeepsEveryClass) {
  DownsampleConfig config;
  config.target_points = 3000;
  ClassAwareDownsampler sampler(config);
  const double edge_ratio = config.initial_voxel_edge / config.initial_voxel_ground;
  std::size_t kept = 0;
  for (int scan = 0; scan < 8; ++scan) {
    const LabelledPoints cloud = Cloud(100 + scan, 0.37 * scan);
    const auto indices = sampler.Select(cloud.points, cloud.labels);
    kept = indices.size();
    std::array<int, kNumPointClasses> per_class{};
    for (const auto i : indices) ++per_class[Index(cloud.labels[i])];
    // Every class the classifier gives (moving is the odometry's, after the downsampling).
    for (std::size_t c = 0; c < kNumGeometricClasses; ++c) {
      EXPECT_GT(per_class[c], 0) << "class " << c;
    }
    EXPECT_TRUE(std::is_sorted(indices.begin(), indices.end()));
  }
  EXPECT_NEAR(double(kept), 3000.0, 0.15 * 3000.0);
  // One common factor: the class sizes keep their configured proportions (none clamped here).
  EXPECT_NEAR(sampler.voxel_size(PointClass::Edge) / sampler.voxel_size(PointClass::Ground),
              edge_ratio, 1e-9);
  EXPECT_GT(sampler.voxel_size(PointClass::Ground), config.initial_voxel_ground);
}

TEST(ClassAwareDownsampler, ShrinksVoxelsWhenTooFewPointsAndStaysInBounds) {
  DownsampleConfig config;
  config.target_points = 100000;  // more points than the cloud has
  ClassAwareDownsampler sampler(config);
  const LabelledPoints cloud = Cloud(5);
  for (int scan = 0; scan < 20; ++scan) sampler.Select(cloud.points, cloud.labels);
  for (std::size_t c = 0; c < kNumPointClasses; ++c) {
    EXPECT_DOUBLE_EQ(sampler.voxel_size(static_cast<PointClass>(c)), config.min_voxel);
  }
}

TEST(ClassAwareDownsampler, Deterministic) {
  DownsampleConfig config;
  config.target_points = 2500;
  ClassAwareDownsampler a(config), b(config);
  for (int scan = 0; scan < 4; ++scan) {
    const LabelledPoints cloud = Cloud(40 + scan);
    EXPECT_EQ(a.Select(cloud.points, cloud.labels), b.Select(cloud.points, cloud.labels));
  }
  EXPECT_EQ(a.voxel_size(PointClass::Wall), b.voxel_size(PointClass::Wall));
}

}  // namespace
}  // namespace dammloam
