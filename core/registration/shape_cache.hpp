#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <deque>
#include <tsl/robin_map.h>
#include <utility>
#include <vector>

#include "core/geometry/voxel.hpp"
#include "core/map/voxel_hash_map.hpp"
#include "core/registration/registration_config.hpp"

namespace dammloam {

// The shape of the map around a point pair's target: what full mode counts the pair as.
struct LocalShape {
  bool judged = false;  // the neighbourhood held enough map points to tell its shape
  int planes = 0;  // 0: a structure; 1: a plane with normal n[0]; 2: a line, normal to n[0], n[1]
  std::array<Eigen::Vector3d, 2> n;
};

LocalShape ShapeAround(const VoxelHashMap& map, const Eigen::Vector3d& target,
                       const RegistrationConfig& config);

// The shape around a target depends only on its map voxel and the points of the 27 voxels
// around it. Within one registration the map does not change; between scans it changes only
// where the last scan added points or the crop removed voxels. A cache kept across scans
// (Forget the map's changes before each registration) computes a shape once per change of its
// neighbourhood instead of once per scan: the same answers, bit for bit.
class ShapeCache {
 public:
  // Drops every shape whose neighbourhood the map changed since its last TakeChanges().
  void Forget(const VoxelHashMap::Changes& changes);
  // Use with `map` and `config` until the next Bind; a different voxel size or shape setting
  // drops everything.
  void Bind(const VoxelHashMap& map, const RegistrationConfig& config);

  // The shapes around target_of(0), ..., target_of(n - 1), in this order, into `out`. The
  // pointers stay valid until the next Forget or Bind.
  template <typename TargetOf>
  void Lookup(std::size_t n, TargetOf target_of, std::vector<const LocalShape*>& out) {
    std::vector<std::uint32_t>& slot_of = slot_of_;
    std::vector<std::pair<Voxel, std::uint32_t>>& missing = missing_;
    slot_of.resize(n);
    missing.clear();
    for (std::size_t i = 0; i < n; ++i) {
      const Voxel voxel = PointToVoxel(target_of(i), map_->voxel_size());
      const auto it = index_.find(voxel);
      if (it != index_.end()) {
        slot_of[i] = it->second;
        continue;
      }
      const std::uint32_t slot = NewSlot();
      index_.emplace(voxel, slot);
      missing.emplace_back(voxel, slot);
      slot_of[i] = slot;
    }
    Compute(missing);
    out.resize(n);
    for (std::size_t i = 0; i < n; ++i) out[i] = &shapes_[slot_of[i]];
  }

  template <typename TargetOf>
  std::vector<const LocalShape*> Lookup(std::size_t n, TargetOf target_of) {
    std::vector<const LocalShape*> out;
    Lookup(n, target_of, out);
    return out;
  }

  std::size_t size() const { return index_.size(); }

 private:
  std::uint32_t NewSlot();
  void Compute(const std::vector<std::pair<Voxel, std::uint32_t>>& missing);
  void Clear();

  const VoxelHashMap* map_ = nullptr;
  RegistrationConfig config_;  // the shape settings of the cached shapes
  double voxel_size_ = 0.0;    // and the map's voxel size
  tsl::robin_map<Voxel, std::uint32_t, VoxelHash> index_;  // into shapes_
  // A deque: pointers handed out stay valid while later lookups append; slots of forgotten
  // shapes are reused, only after a Forget.
  std::deque<LocalShape> shapes_;
  std::vector<std::uint32_t> free_slots_;
  // Lookup's buffers, kept between calls.
  std::vector<std::uint32_t> slot_of_;
  std::vector<std::pair<Voxel, std::uint32_t>> missing_;
};

}  // namespace dammloam
