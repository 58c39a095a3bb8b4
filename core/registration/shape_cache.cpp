#include "core/registration/shape_cache.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace dammloam {

namespace {

// A line keeps a normal only where its points face it (see line_normal_support): one ring's
// arc across a plane is a line of points that all face the plane's normal.
void KeepFacedLineNormals(const VoxelHashMap& map, const Eigen::Vector3d& target,
                          double min_support, LocalShape& shape) {
  if (shape.planes != 2 || !(min_support > 0.0)) return;
  int with_normal = 0;
  const Eigen::Matrix3d faces = map.NormalScatterOf(target, with_normal);
  if (with_normal < 3) return;  // nothing to judge by
  const bool faced0 = shape.n[0].dot(faces * shape.n[0]) >= min_support;
  const bool faced1 = shape.n[1].dot(faces * shape.n[1]) >= min_support;
  if (faced0 == faced1) return;
  shape.planes = 1;
  if (faced1) shape.n[0] = shape.n[1];
}

bool SameShapeSettings(const RegistrationConfig& a, const RegistrationConfig& b) {
  return a.point_shape_min_points == b.point_shape_min_points &&
         a.point_flatness == b.point_flatness && a.line_normal_support == b.line_normal_support;
}

}  // namespace

LocalShape ShapeAround(const VoxelHashMap& map, const Eigen::Vector3d& target,
                       const RegistrationConfig& config) {
  LocalShape shape;
  const VoxelHashMap::Neighbourhood hood = map.NeighbourhoodOf(target);
  if (hood.count < std::max(config.point_shape_min_points, 3)) return shape;
  shape.judged = true;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(hood.covariance);
  const Eigen::Vector3d& lambda = eig.eigenvalues();  // ascending
  const double sum = lambda.sum();
  if (!(sum > 0.0)) return shape;
  shape.n = {eig.eigenvectors().col(0), eig.eigenvectors().col(1)};
  if (lambda(1) / sum < config.point_flatness) {
    shape.planes = 2;
  } else if (lambda(0) / sum < config.point_flatness) {
    shape.planes = 1;
  }
  KeepFacedLineNormals(map, target, config.line_normal_support, shape);
  return shape;
}

void ShapeCache::Bind(const VoxelHashMap& map, const RegistrationConfig& config) {
  if (map_ != &map || voxel_size_ != map.voxel_size() || !SameShapeSettings(config_, config)) {
    Clear();
  }
  map_ = &map;
  config_ = config;
  voxel_size_ = map.voxel_size();
}

void ShapeCache::Forget(const VoxelHashMap::Changes& changes) {
  if (changes.all) {
    Clear();
    return;
  }
  // A voxel's shape reads its 27 neighbours: a change anywhere among them stales it.
  for (const Voxel& changed : changes.voxels) {
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = index_.find(changed + Voxel(dx, dy, dz));
          if (it == index_.end()) continue;
          free_slots_.push_back(it->second);
          index_.erase(it);
        }
      }
    }
  }
}

std::uint32_t ShapeCache::NewSlot() {
  if (!free_slots_.empty()) {
    const std::uint32_t slot = free_slots_.back();
    free_slots_.pop_back();
    return slot;
  }
  shapes_.emplace_back();
  return static_cast<std::uint32_t>(shapes_.size() - 1);
}

void ShapeCache::Compute(const std::vector<std::pair<Voxel, std::uint32_t>>& missing) {
  const double size = map_->voxel_size();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, missing.size(), 16),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i) {
                        const Voxel& v = missing[i].first;
                        const Eigen::Vector3d centre = (v.cast<double>().array() + 0.5).matrix() * size;
                        shapes_[missing[i].second] = ShapeAround(*map_, centre, config_);
                      }
                    });
}

void ShapeCache::Clear() {
  index_.clear();
  shapes_.clear();
  free_slots_.clear();
}

}  // namespace dammloam
