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
// by their hash and each partition walks its own points in order, so the partitions run in
// parallel and keep exactly the indices of one sequential pass. The tables keep their
// buckets between scans: no allocation once the first scans sized them.
class FirstPerCell {
 public:
  // Indices (ascending) of the kept points; a point without a label counts as unknown.
  std::vector<std::size_t> Select(const std::vector<Eigen::Vector3d>& points,
                                  const std::vector<PointClass>& labels,
                                  const std::array<double, kNumPointClasses>& voxel_sizes);
  // The same into `kept` (its capacity reused).
  void Select(const std::vector<Eigen::Vector3d>& points, const std::vector<PointClass>& labels,
              const std::array<double, kNumPointClasses>& voxel_sizes,
              std::vector<std::size_t>& kept);

 private:
  static constexpr std::size_t kPartitions = 4;
  struct OrderedCell {
    ClassVoxel cell;
    std::uint32_t index;  // of the point
  };
  void KeepFirstOfPartition(std::size_t partition);
  void GatherKept(std::vector<std::size_t>& kept);

  std::vector<ClassVoxel> cells_;
  std::vector<std::uint8_t> partition_;
  // The points grouped by partition, in input order within each: partition p holds
  // ordered_[partition_start_[p], partition_start_[p + 1]). A partition walking all points and
  // skipping the others' mispredicted three branches in four.
  std::vector<OrderedCell> ordered_;
  std::array<std::size_t, kPartitions + 1> partition_start_{};
  std::vector<std::uint8_t> kept_;
  std::vector<std::array<std::size_t, kPartitions>> block_counts_;  // Select's, per block
  std::vector<std::size_t> block_starts_;                             // GatherKept's
  std::array<tsl::robin_set<ClassVoxel, ClassVoxelHash>, kPartitions> seen_;
};

}  // namespace dammloam
