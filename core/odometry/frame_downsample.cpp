#include "core/odometry/frame_downsample.hpp"

namespace dammloam {

std::vector<std::size_t> ClassVoxelSampler::Select(const std::vector<Eigen::Vector3d>& points,
                                                   const std::vector<PointClass>& labels,
                                                   double voxel_size) {
  seen_.clear();  // keeps the buckets, which settle at the size a scan needs
  std::vector<std::size_t> kept;
  kept.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const PointClass label = i < labels.size() ? labels[i] : PointClass::Unknown;
    if (seen_.insert({PointToVoxel(points[i], voxel_size), label}).second) kept.push_back(i);
  }
  return kept;
}

}  // namespace dammloam
