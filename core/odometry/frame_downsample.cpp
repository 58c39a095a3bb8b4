#include "core/odometry/frame_downsample.hpp"

namespace dammloam {

std::vector<std::size_t> ClassVoxelSampler::Select(const std::vector<Eigen::Vector3d>& points,
                                                   const std::vector<PointClass>& labels,
                                                   double voxel_size) {
  std::array<double, kNumPointClasses> sizes;
  sizes.fill(voxel_size);
  return first_per_cell_.Select(points, labels, sizes);
}

}  // namespace dammloam
