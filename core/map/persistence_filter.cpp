#include "core/map/persistence_filter.hpp"

#include <cmath>

namespace dammloam {

int PersistenceFilter::LevelOf(double range) const {
  const double wanted = config_.voxel_per_metre * range / config_.voxel_size;
  if (!(wanted > 1.0)) return 0;
  return std::min(kLevels - 1, static_cast<int>(std::lround(std::log2(wanted))));
}

std::size_t PersistenceFilter::NumVoxels() const {
  std::size_t n = 0;
  for (const Grid& grid : grids_) n += grid.size();
  return n;
}

std::vector<std::uint8_t> PersistenceFilter::Observe(const std::vector<Eigen::Vector3d>& points_world,
                                                     const Eigen::Vector3d& sensor_world,
                                                     double stamp) {
  const std::vector<double> age = ObservedFor(points_world, sensor_world, stamp);
  std::vector<std::uint8_t> persistent(age.size(), 0);
  for (std::size_t i = 0; i < age.size(); ++i) persistent[i] = age[i] >= config_.min_age - 1e-9 ? 1 : 0;
  return persistent;
}

std::vector<double> PersistenceFilter::ObservedFor(const std::vector<Eigen::Vector3d>& points_world,
                                                  const Eigen::Vector3d& sensor_world, double stamp) {
  Forget(stamp);
  std::vector<double> age(points_world.size(), 0.0);
  for (std::size_t i = 0; i < points_world.size(); ++i) {
    const int level = LevelOf((points_world[i] - sensor_world).norm());
    const double size = std::ldexp(config_.voxel_size, level);
    const auto it = grids_[level].try_emplace(PointToVoxel(points_world[i], size), Seen{stamp, stamp}).first;
    Seen& seen = it.value();
    if (stamp - seen.last > config_.max_gap) seen.first = stamp;  // lapsed: starts over
    seen.last = stamp;
    age[i] = stamp - seen.first;
  }
  return age;
}

void PersistenceFilter::Accept(const std::vector<Eigen::Vector3d>& points_world,
                               const Eigen::Vector3d& sensor_world, double stamp) {
  for (const Eigen::Vector3d& p : points_world) {
    const int level = LevelOf((p - sensor_world).norm());
    grids_[level].insert_or_assign(PointToVoxel(p, std::ldexp(config_.voxel_size, level)),
                                   Seen{stamp - config_.min_age, stamp});
  }
}

// Voxels not seen for longer than max_gap start over anyway: dropped, about once per max_gap,
// so the tables hold only what recent scans saw.
void PersistenceFilter::Forget(double stamp) {
  if (stamp - last_forget_ < config_.max_gap) return;
  last_forget_ = stamp;
  for (Grid& grid : grids_) {
    for (auto it = grid.begin(); it != grid.end();) {
      if (stamp - it->second.last > config_.max_gap) {
        it = grid.erase(it);
      } else {
        ++it;
      }
    }
  }
}

}  // namespace dammloam
