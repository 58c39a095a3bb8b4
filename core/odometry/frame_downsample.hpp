#pragma once
#include <Eigen/Core>
#include <vector>

#include "core/geometry/first_per_cell.hpp"
#include "core/geometry/point_class.hpp"
#include "core/geometry/voxel.hpp"

namespace dammloam {

// One point per (voxel, class), first come: what goes into the map. Keeping classes apart
// means a wall point never hides the floor point sharing its voxel.
class ClassVoxelSampler {
 public:
  // Indices (ascending) of the kept points; a point without a label counts as unknown.
  std::vector<std::size_t> Select(const std::vector<Eigen::Vector3d>& points,
                                  const std::vector<PointClass>& labels, double voxel_size);
  void Select(const std::vector<Eigen::Vector3d>& points, const std::vector<PointClass>& labels,
              double voxel_size, std::vector<std::size_t>& kept);  // the same into `kept`

 private:
  FirstPerCell first_per_cell_;  // scratch, kept between scans
};

}  // namespace dammloam
