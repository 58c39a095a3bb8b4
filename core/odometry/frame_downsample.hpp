#pragma once
#include <Eigen/Core>
#include <tsl/robin_set.h>
#include <vector>

#include "core/geometry/point_class.hpp"
#include "core/geometry/voxel.hpp"

namespace dammloam {

// One point per (voxel, class), first come: what goes into the map. Keeping classes apart
// means a wall point never hides the floor point sharing its voxel. The hash table is kept
// between scans: sized for a whole scan, allocating it anew cost more than the sampling.
class ClassVoxelSampler {
 public:
  // Indices (ascending) of the kept points; a point without a label counts as unknown.
  std::vector<std::size_t> Select(const std::vector<Eigen::Vector3d>& points,
                                  const std::vector<PointClass>& labels, double voxel_size);

 private:
  tsl::robin_set<ClassVoxel, ClassVoxelHash> seen_;
};

}  // namespace dammloam
