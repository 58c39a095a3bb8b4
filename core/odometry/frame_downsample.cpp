#include "core/odometry/frame_downsample.hpp"

#include <optional>

namespace dammloam {

std::vector<std::size_t> ClassVoxelSampler::Select(const std::vector<Eigen::Vector3d>& points,
                                                   const std::vector<PointClass>& labels,
                                                   double voxel_size) {
  seen_.clear();  // keeps the buckets, which settle at the size a scan needs
  std::vector<std::size_t> kept;
  kept.reserve(points.size());
  std::optional<ClassVoxel> previous;  // a repeat of the previous cell is never kept
  for (std::size_t i = 0; i < points.size(); ++i) {
    const PointClass label = i < labels.size() ? labels[i] : PointClass::Unknown;
    const ClassVoxel key{PointToVoxel(points[i], voxel_size), label};
    if (previous == key) continue;
    previous = key;
    if (seen_.insert(key).second) kept.push_back(i);
  }
  return kept;
}

}  // namespace dammloam
