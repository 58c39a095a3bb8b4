#pragma once
#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "core/geometry/point_class.hpp"

namespace dammloam {

// Integer cell of a regular voxel grid; shared by the downsampler and the voxel map.
using Voxel = Eigen::Vector3i;

// Spatial hash of Teschner et al. (large primes, XOR): cheap and spreads neighbouring cells.
struct VoxelHash {
  std::size_t operator()(const Voxel& v) const {
    const auto x = static_cast<std::uint32_t>(v.x());
    const auto y = static_cast<std::uint32_t>(v.y());
    const auto z = static_cast<std::uint32_t>(v.z());
    return static_cast<std::size_t>((x * 73856093u) ^ (y * 19349669u) ^ (z * 83492791u));
  }
};

// A cell of one class's grid: the classes share one hash table without sharing cells.
struct ClassVoxel {
  Voxel voxel;
  PointClass label;
  bool operator==(const ClassVoxel& other) const {
    return label == other.label && voxel == other.voxel;
  }
};

struct ClassVoxelHash {
  std::size_t operator()(const ClassVoxel& key) const {
    return VoxelHash{}(key.voxel) ^ (static_cast<std::size_t>(key.label) * 2654435761u);
  }
};

// floor() (not truncation) so cells are the same size on both sides of zero.
inline Voxel PointToVoxel(const Eigen::Vector3d& p, double voxel_size) {
  return Voxel(static_cast<int>(std::floor(p.x() / voxel_size)),
               static_cast<int>(std::floor(p.y() / voxel_size)),
               static_cast<int>(std::floor(p.z() / voxel_size)));
}

}  // namespace dammloam
