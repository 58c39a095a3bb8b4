#pragma once
#include <Eigen/Core>
#include <vector>

#include "core/backend/keyframe.hpp"

namespace dammloam::backend {

struct GlobalMap {
  std::vector<Eigen::Vector3d> points;  // world frame
  std::vector<PointClass> labels;       // one per point (Unknown where the keyframe had none)
};

// Union of all keyframe clouds at their corrected poses, one point per voxel.
GlobalMap AssembleGlobalMap(const std::vector<Keyframe>& keyframes, double voxel_size);

}  // namespace dammloam::backend
