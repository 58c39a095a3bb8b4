#pragma once
#include <Eigen/Core>
#include <tsl/robin_set.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/geometry/point_class.hpp"
#include "core/geometry/voxel.hpp"

namespace dammloam {

// The first point (in input order) of every (voxel, class) cell, each class on a grid of its
// own size: the voxel samplers' shared core. Cells are split between kPartitions hash tables
// by their hash and each partition walks the points in order, so the partitions run in
// parallel and keep exactly the indices of one sequential pass. The tables keep their
// buckets between scans: no allocation once the first scans sized them.
class FirstPerCell {
 public:
  // Indices (ascending) of the kept points; a point without a label counts as unknown.
  std::vector<std::size_t> Select(const std::vector<Eigen::Vector3d>& points,
                                  const std::vector<PointClass>& labels,
                                  const std::array<double, kNumPointClasses>& voxel_sizes);

 private:
  static constexpr std::size_t kPartitions = 4;
  void KeepFirstOfPartition(std::size_t partition);

  std::vector<ClassVoxel> cells_;
  std::vector<std::uint8_t> partition_;
  std::vector<std::uint8_t> kept_;
  std::array<tsl::robin_set<ClassVoxel, ClassVoxelHash>, kPartitions> seen_;
};

}  // namespace dammloam
