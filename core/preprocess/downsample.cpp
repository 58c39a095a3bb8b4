#include "core/preprocess/downsample.hpp"

#include <tsl/robin_map.h>

#include <algorithm>
#include <cmath>

#include "core/geometry/voxel.hpp"

namespace dammloam {

std::vector<std::size_t> VoxelDownsample(const std::vector<Eigen::Vector3d>& points,
                                         double voxel_size) {
  std::vector<std::size_t> kept;
  if (!(voxel_size > 0.0)) return kept;
  tsl::robin_map<Voxel, std::size_t, VoxelHash> grid;
  grid.reserve(points.size() / 4 + 1);
  kept.reserve(points.size() / 4 + 1);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (grid.emplace(PointToVoxel(points[i], voxel_size), i).second) kept.push_back(i);
  }
  return kept;
}

ClassAwareDownsampler::ClassAwareDownsampler(const DownsampleConfig& config) : config_(config) {
  voxel_sizes_[Index(PointClass::Unknown)] = config.initial_voxel_unknown;
  voxel_sizes_[Index(PointClass::Ground)] = config.initial_voxel_ground;
  voxel_sizes_[Index(PointClass::Roof)] = config.initial_voxel_roof;
  voxel_sizes_[Index(PointClass::Wall)] = config.initial_voxel_wall;
  voxel_sizes_[Index(PointClass::Edge)] = config.initial_voxel_edge;
  // The classifier gives no moving points; should a caller pass some, they sample as unknown.
  voxel_sizes_[Index(PointClass::Moving)] = config.initial_voxel_unknown;
  for (double& size : voxel_sizes_) size = std::clamp(size, config.min_voxel, config.max_voxel);
}

std::vector<std::size_t> ClassAwareDownsampler::Select(const std::vector<Eigen::Vector3d>& points,
                                                       const std::vector<PointClass>& labels) {
  std::vector<std::size_t> kept;
  Select(points, labels, kept);
  return kept;
}

void ClassAwareDownsampler::Select(const std::vector<Eigen::Vector3d>& points,
                                   const std::vector<PointClass>& labels,
                                   std::vector<std::size_t>& kept) {
  kept.clear();
  if (labels.size() != points.size()) return;
  first_per_cell_.Select(points, labels, voxel_sizes_, kept);
  Adapt(kept.size());
}

void ClassAwareDownsampler::Adapt(std::size_t kept) {
  if (kept == 0 || config_.target_points == 0) return;
  const double ratio = static_cast<double>(kept) / static_cast<double>(config_.target_points);
  if (std::abs(ratio - 1.0) <= config_.tolerance) return;
  const double step = std::max(1.0, config_.max_step);
  const double factor = std::clamp(std::sqrt(ratio), 1.0 / step, step);
  for (double& size : voxel_sizes_) {
    size = std::clamp(size * factor, config_.min_voxel, config_.max_voxel);
  }
}

}  // namespace dammloam
