#pragma once
#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <vector>

#include "core/geometry/first_per_cell.hpp"
#include "core/geometry/point_class.hpp"
#include "core/geometry/voxel.hpp"
#include "core/preprocess/preprocess_config.hpp"

namespace dammloam {

// One point per voxel, the first in input order (deterministic). Returns ascending indices.
std::vector<std::size_t> VoxelDownsample(const std::vector<Eigen::Vector3d>& points,
                                         double voxel_size);

// Class-aware adaptive voxel downsampling (paper Sec. III): each class has its own grid, so a
// rare class (edges) is never swallowed by an abundant one (ground) sharing its voxels. After
// every scan all voxel sizes are scaled by the same factor towards the target point count
// (kept points of a surface scale with 1/voxel^2, hence the square root), limited to
// max_step per scan and clamped to [min_voxel, max_voxel]; inside the tolerance band the sizes
// stay put so they do not dither.
class ClassAwareDownsampler {
 public:
  explicit ClassAwareDownsampler(const DownsampleConfig& config);

  // Indices (ascending) of the kept points: one per voxel per class, the first in input order.
  // labels must have one entry per point (else nothing is kept). Updates the voxel sizes.
  void Select(const std::vector<Eigen::Vector3d>& points, const std::vector<PointClass>& labels,
              std::vector<std::size_t>& kept);  // the same into `kept`
  std::vector<std::size_t> Select(const std::vector<Eigen::Vector3d>& points,
                                  const std::vector<PointClass>& labels);

  double voxel_size(PointClass c) const { return voxel_sizes_[Index(c)]; }

 private:
  void Adapt(std::size_t kept);

  DownsampleConfig config_;
  std::array<double, kNumPointClasses> voxel_sizes_;
  FirstPerCell first_per_cell_;  // scratch, kept between scans
};

}  // namespace dammloam
