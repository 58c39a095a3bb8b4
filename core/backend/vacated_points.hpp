#pragma once
#include <cstdint>
#include <vector>

#include "core/backend/keyframe.hpp"
#include "core/geometry/scan.hpp"

namespace dammloam::backend {

// Map points whose place later keyframes saw through: a person who walked by, a car that has
// left its parking place. The keyframes' own returns are the evidence (Removert's visibility
// test, against every later keyframe instead of a volumetric map), judged in time order so the
// newest view wins: a place seen through and then seen holding a surface again is kept.
struct VacatedPointsConfig {
  bool enabled = true;
  double max_range = 30.0;  // metres from a keyframe; its rays are judged no farther
  double min_range = 1.0;   // metres; nearer, the sensor's carrier may be in the way
  // A return must lie this far beyond the point, in every cell around its direction.
  double margin = 0.15;           // metres
  double margin_per_metre = 0.01;  // plus this share of its range
  // Keyframes that saw through the point after the last one that saw a surface at it.
  int min_views = 2;

  bool operator==(const VacatedPointsConfig&) const = default;
};

// Per point (world frame; source[i]: index in `keyframes` of the keyframe it came from, which
// saw it), 1 where it is vacated. Keyframes in time order, at their corrected poses, clouds
// thinned to `voxel_size` (each point then spreads over its voxel in the views).
std::vector<std::uint8_t> FindVacatedPoints(const std::vector<Eigen::Vector3d>& points_world,
                                            const std::vector<std::uint32_t>& source,
                                            const std::vector<Keyframe>& keyframes,
                                            const SensorModel& sensor, double voxel_size,
                                            const VacatedPointsConfig& config);

}  // namespace dammloam::backend
