#include "core/odometry/frame_downsample.hpp"

namespace dammloam {

std::vector<std::size_t> ClassVoxelSampler::Select(const std::vector<Eigen::Vector3d>& points,
                                                   const std::vector<PointClass>& labels,
                                                   double voxel_size) {
  return first_.Select(points.size(), [&](std::size_t i) {
    const PointClass label = i < labels.size() ? labels[i] : PointClass::Unknown;
    return ClassVoxel{PointToVoxel(points[i], voxel_size), label};
  });
}

}  // namespace dammloam
