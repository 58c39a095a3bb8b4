#include "core/backend/global_map.hpp"

#include "core/backend/point_to_plane_icp.hpp"

namespace dammloam::backend {

GlobalMap AssembleGlobalMap(const std::vector<Keyframe>& keyframes, double voxel_size) {
  std::vector<Eigen::Vector3d> points;
  std::vector<PointClass> labels;
  for (const Keyframe& kf : keyframes) {
    const bool labelled = kf.labels.size() == kf.points.size();
    for (std::size_t i = 0; i < kf.points.size(); ++i) {
      points.push_back(kf.T_world_sensor * kf.points[i]);
      labels.push_back(labelled ? kf.labels[i] : PointClass::Unknown);
    }
  }
  GlobalMap map;
  for (std::size_t i : VoxelDownsampleIndices(points, voxel_size)) {
    map.points.push_back(points[i]);
    map.labels.push_back(labels[i]);
  }
  return map;
}

}  // namespace dammloam::backend
