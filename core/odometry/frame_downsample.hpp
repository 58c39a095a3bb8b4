#pragma once
#include <Eigen/Core>
#include <vector>

#include "core/geometry/point_class.hpp"

namespace dammloam {

// One point per (voxel, class), first come: what goes into the map. Keeping classes apart
// means a wall point never hides the floor point sharing its voxel.
std::vector<std::size_t> ClassVoxelDownsample(const std::vector<Eigen::Vector3d>& points,
                                              const std::vector<PointClass>& labels,
                                              double voxel_size);

}  // namespace dammloam
