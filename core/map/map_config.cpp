#include "core/map/map_config.hpp"

#include <algorithm>

namespace dammloam {

double AutoVoxelSize(const MapConfig& config, double median_range) {
  if (config.voxel_size > 0.0) return config.voxel_size;
  return std::clamp(config.auto_voxel_range_factor * median_range, config.auto_voxel_min,
                    config.auto_voxel_max);
}

}  // namespace dammloam
