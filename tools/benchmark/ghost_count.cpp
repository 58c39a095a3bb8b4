#include "tools/benchmark/ghost_count.hpp"

namespace dammloam::bench {

GhostCount CountGhosts(const std::vector<Eigen::Vector3d>& points_truth,
                       const std::vector<PointClass>& labels, const sim::SweptVolume& swept) {
  GhostCount count;
  count.points = points_truth.size();
  const bool labelled = labels.size() == points_truth.size();
  for (std::size_t i = 0; i < points_truth.size(); ++i) {
    const Eigen::Vector3d& p = points_truth[i];
    if (!swept.Occupied(p)) continue;
    if (swept.OccupiedAtEnd(p)) {
      ++count.on_actors;
      continue;
    }
    ++count.ghosts;
    count.ghost_indices.push_back(i);
    ++count.ghosts_by_class[Index(labelled ? labels[i] : PointClass::Unknown)];
  }
  return count;
}

}  // namespace dammloam::bench
