#include "core/odometry/frame_downsample.hpp"

namespace dammloam {

std::vector<std::size_t> ClassVoxelSampler::Select(const std::vector<Eigen::Vector3d>& points,
                                                   const std::vector<PointClass>& labels,
                                                   double voxel_size) {
  std::vector<std::size_t> kept;
  Select(points, labels, voxel_size, kept);
  return kept;
}

void ClassVoxelSampler::Select(const std::vector<Eigen::Vector3d>& points,
                               const std::vector<PointClass>& labels, double voxel_size,
                               std::vector<std::size_t>& kept) {
  std::array<double, kNumPointClasses> sizes;
  sizes.fill(voxel_size);
  first_per_cell_.Select(points, labels, sizes, kept);
}

}  // namespace dammloam
