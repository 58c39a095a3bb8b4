#include "core/odometry/frame_downsample.hpp"

#include <tsl/robin_set.h>

#include "core/geometry/voxel.hpp"

namespace dammloam {

namespace {
struct ClassVoxel {
  Voxel voxel;
  int label;
  bool operator==(const ClassVoxel& o) const { return label == o.label && voxel == o.voxel; }
};
struct ClassVoxelHash {
  std::size_t operator()(const ClassVoxel& k) const {
    return VoxelHash{}(k.voxel) ^ (static_cast<std::size_t>(k.label) * 2654435761u);
  }
};
}  // namespace

std::vector<std::size_t> ClassVoxelDownsample(const std::vector<Eigen::Vector3d>& points,
                                              const std::vector<PointClass>& labels,
                                              double voxel_size) {
  tsl::robin_set<ClassVoxel, ClassVoxelHash> seen;
  seen.reserve(points.size());
  std::vector<std::size_t> kept;
  kept.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const int label = i < labels.size() ? static_cast<int>(labels[i]) : 0;
    if (seen.insert({PointToVoxel(points[i], voxel_size), label}).second) kept.push_back(i);
  }
  return kept;
}

}  // namespace dammloam
