#include "core/backend/global_map.hpp"

#include "core/backend/point_to_plane_icp.hpp"

namespace dammloam::backend {

namespace {

// One point per voxel of the keyframes' union, with the keyframe each came from.
GlobalMap Union(const std::vector<Keyframe>& keyframes, double voxel_size,
                std::vector<std::uint32_t>* source) {
  std::vector<Eigen::Vector3d> points;
  std::vector<PointClass> labels;
  std::vector<std::uint32_t> from;
  for (std::uint32_t k = 0; k < keyframes.size(); ++k) {
    const Keyframe& kf = keyframes[k];
    const bool labelled = kf.labels.size() == kf.points.size();
    for (std::size_t i = 0; i < kf.points.size(); ++i) {
      points.push_back(kf.T_world_sensor * kf.points[i]);
      labels.push_back(labelled ? kf.labels[i] : PointClass::Unknown);
      if (source != nullptr) from.push_back(k);
    }
  }
  GlobalMap map;
  for (std::size_t i : VoxelDownsampleIndices(points, voxel_size)) {
    map.points.push_back(points[i]);
    map.labels.push_back(labels[i]);
    if (source != nullptr) source->push_back(from[i]);
  }
  return map;
}

}  // namespace

GlobalMap AssembleGlobalMap(const std::vector<Keyframe>& keyframes, double voxel_size) {
  return Union(keyframes, voxel_size, nullptr);
}

GlobalMap AssembleGlobalMap(const std::vector<Keyframe>& keyframes, double voxel_size,
                            const SensorModel& sensor, double keyframe_voxel_size,
                            const VacatedPointsConfig& vacated) {
  std::vector<std::uint32_t> source;
  GlobalMap all = Union(keyframes, voxel_size, &source);
  if (!vacated.enabled) return all;
  const std::vector<std::uint8_t> gone =
      FindVacatedPoints(all.points, source, keyframes, sensor, keyframe_voxel_size, vacated);
  GlobalMap kept;
  for (std::size_t i = 0; i < all.points.size(); ++i) {
    if (gone[i] != 0) {
      ++kept.vacated;
      continue;
    }
    kept.points.push_back(all.points[i]);
    kept.labels.push_back(all.labels[i]);
  }
  return kept;
}

}  // namespace dammloam::backend
