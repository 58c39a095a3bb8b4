#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <tsl/robin_map.h>
#include <vector>

#include "core/geometry/voxel.hpp"

namespace dammloam {

// Which places have held a surface long enough to be part of the map. A voxel is persistent
// once scans have kept finding points in it for `min_age` seconds without a gap longer than
// `max_gap`: a wall is, from its second second on; a person walking at 1 m/s fills a 0.3 m voxel
// for well under a second, and one who walks ahead of the sensor never fills the same place
// twice. Keeping the rest out of the map is what stops a crowd, or someone walking ahead, from
// being matched against their own trail. Far surfaces are sampled sparsely (a VLP-16's rings lie
// 3.5 % of the range apart), so the voxel grows with the range: base, 2x, 4x, 8x the base size,
// each a grid of its own.
class PersistenceFilter {
 public:
  struct Config {
    double voxel_size = 0.3;  // metres, the finest grid (near the sensor)
    double voxel_per_metre = 0.04;  // a point at range r uses the grid nearest this * r
    double min_age = 1.0;     // seconds of continuous observation
    double max_gap = 0.35;    // seconds; a longer gap starts the voxel over
  };
  explicit PersistenceFilter(const Config& config) : config_(config) {}

  // Records that the world points were observed at `stamp` and returns, per point, 1 where its
  // voxel is persistent. Stamps must not decrease.
  std::vector<std::uint8_t> Observe(const std::vector<Eigen::Vector3d>& points_world,
                                    const Eigen::Vector3d& sensor_world, double stamp);
  // As Observe, but per point the seconds its voxel has been observed without a lapse, for
  // callers that ask some points to wait longer than min_age.
  std::vector<double> ObservedFor(const std::vector<Eigen::Vector3d>& points_world,
                                 const Eigen::Vector3d& sensor_world, double stamp);
  // The points' voxels count as persistent from now on (the first scan: there is nothing to
  // wait for, and registration needs a map).
  void Accept(const std::vector<Eigen::Vector3d>& points_world, const Eigen::Vector3d& sensor_world,
              double stamp);
  std::size_t NumVoxels() const;
  void Clear() {
    for (auto& grid : grids_) grid.clear();
  }

 private:
  struct Seen {
    double first = 0.0;
    double last = 0.0;
  };
  using Grid = tsl::robin_map<Voxel, Seen, VoxelHash>;
  static constexpr int kLevels = 4;
  int LevelOf(double range) const;
  void Forget(double stamp);

  Config config_;
  std::array<Grid, kLevels> grids_;
  double last_forget_ = -1e300;
};

}  // namespace dammloam
