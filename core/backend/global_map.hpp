#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "core/backend/keyframe.hpp"
#include "core/backend/vacated_points.hpp"
#include "core/geometry/scan.hpp"

namespace dammloam::backend {

struct GlobalMap {
  std::vector<Eigen::Vector3d> points;  // world frame
  std::vector<PointClass> labels;       // one per point (Unknown where the keyframe had none)
  std::size_t vacated = 0;              // points left out because later keyframes saw through them
};

// Union of all keyframe clouds at their corrected poses, one point per voxel.
GlobalMap AssembleGlobalMap(const std::vector<Keyframe>& keyframes, double voxel_size);
// The same without the points that later keyframes saw through (vacated_points.hpp): what
// entered the map and then moved away. Keyframes in time order, their clouds thinned to
// `keyframe_voxel_size`, taken by `sensor`.
GlobalMap AssembleGlobalMap(const std::vector<Keyframe>& keyframes, double voxel_size,
                            const SensorModel& sensor, double keyframe_voxel_size,
                            const VacatedPointsConfig& vacated);

}  // namespace dammloam::backend
