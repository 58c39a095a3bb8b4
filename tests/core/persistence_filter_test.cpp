// PersistenceFilter: a place enters the map only once scans kept finding a surface there.
#include <gtest/gtest.h>

#include "core/map/persistence_filter.hpp"

namespace dammloam {
namespace {

PersistenceFilter::Config Config() {
  PersistenceFilter::Config c;
  c.voxel_size = 0.3;
  c.min_age = 0.5;
  c.max_gap = 0.35;
  return c;
}

TEST(PersistenceFilter, AWallPersistsAfterMinAgeAndAWalkerNever) {
  PersistenceFilter filter(Config());
  const Eigen::Vector3d sensor = Eigen::Vector3d::Zero();
  const Eigen::Vector3d wall(5.0, 1.0, 0.5);
  int wall_persistent_from = -1;
  for (int k = 0; k <= 30; ++k) {
    const double t = 0.1 * k;
    // A person walking away along x at 1.2 m/s, 2 m ahead of a sensor that stays put.
    const Eigen::Vector3d walker(2.0 + 1.2 * t, 0.0, 0.2);
    const auto persistent = filter.Observe({wall, walker}, sensor, t);
    if (persistent[0] && wall_persistent_from < 0) wall_persistent_from = k;
    EXPECT_EQ(persistent[1], 0) << "walker at t = " << t;
  }
  EXPECT_EQ(wall_persistent_from, 5);  // 0.5 s after it was first seen
}

TEST(PersistenceFilter, AGapLongerThanMaxGapStartsOverAndAcceptIsImmediate) {
  PersistenceFilter filter(Config());
  const Eigen::Vector3d sensor = Eigen::Vector3d::Zero();
  const Eigen::Vector3d p(3.0, 0.0, 0.0);
  for (int k = 0; k <= 5; ++k) filter.Observe({p}, sensor, 0.1 * k);
  EXPECT_EQ(filter.Observe({p}, sensor, 0.6)[0], 1);
  EXPECT_EQ(filter.Observe({p}, sensor, 1.1)[0], 0);  // unseen for 0.5 s: new again
  const Eigen::Vector3d q(-4.0, 2.0, 0.0);
  filter.Accept({q}, sensor, 2.0);
  EXPECT_EQ(filter.Observe({q}, sensor, 2.1)[0], 1);
}

TEST(PersistenceFilter, FarPointsUseCoarserVoxels) {
  PersistenceFilter filter(Config());
  const Eigen::Vector3d sensor = Eigen::Vector3d::Zero();
  // 40 m away a sparse sensor's samples of one wall land up to ~1 m apart from scan to scan,
  // each 0.3 m cell hit only every 0.4 s: at that range the voxel is 8 x 0.3 = 2.4 m, so the
  // wall still persists.
  int persistent = 0;
  for (int k = 0; k <= 10; ++k) {
    const Eigen::Vector3d p(40.0, 0.1 + 0.35 * (k % 4), 0.0);
    persistent += filter.Observe({p}, sensor, 0.1 * k)[0];
  }
  EXPECT_GT(persistent, 0);
  // Near the sensor the same alternation lands in different voxels and never persists.
  PersistenceFilter near(Config());
  int near_persistent = 0;
  for (int k = 0; k <= 10; ++k) {
    const Eigen::Vector3d p(3.0, 0.1 + 0.35 * (k % 4), 0.0);
    near_persistent += near.Observe({p}, sensor, 0.1 * k)[0];
  }
  EXPECT_EQ(near_persistent, 0);
}

}  // namespace
}  // namespace dammloam
