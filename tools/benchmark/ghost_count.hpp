#pragma once
// What a map kept of things that have since moved away (issue 52's "ghosts"): its points inside
// the space actors occupied during a run and had left by its end.
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <vector>

#include "core/geometry/point_class.hpp"
#include "tools/simulate/swept_volume.hpp"

namespace dammloam::bench {

struct GhostCount {
  std::size_t points = 0;     // map points judged
  std::size_t ghosts = 0;     // inside space an actor occupied and has left
  std::size_t on_actors = 0;  // inside an actor's body at the end: a parked car, not a ghost
  std::array<std::size_t, kNumPointClasses> ghosts_by_class{};
  std::vector<std::size_t> ghost_indices;  // into the points counted
};

// points_truth: the map in the simulator's world frame; labels: one per point, or empty.
GhostCount CountGhosts(const std::vector<Eigen::Vector3d>& points_truth,
                       const std::vector<PointClass>& labels, const sim::SweptVolume& swept);

}  // namespace dammloam::bench
