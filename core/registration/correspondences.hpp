#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "core/geometry/point_class.hpp"
#include "core/map/voxel_hash_map.hpp"
#include "core/registration/registration_config.hpp"

namespace dammloam {

// A source point (world frame, under the current pose estimate) paired with a map point.
// For planar pairs `normal` is the map point's stored unit normal (paper eq. pt2pl).
struct Correspondence {
  Eigen::Vector3d source;
  Eigen::Vector3d target;
  Eigen::Vector3d normal;
  double time = 0.0;  // the source point's firing time relative to the registered frame's, s
};

// The source points a search pairs: all of them (stride 1); with stride k > 1 every k-th
// (0, k, 2k, ...), or with `complement` all the others.
struct SourceSubset {
  std::size_t stride = 1;
  bool complement = false;
  bool Contains(std::size_t i) const { return stride <= 1 || (i % stride == 0) != complement; }
};

struct CorrespondenceSet {
  std::vector<Correspondence> planar;  // point-to-plane residuals
  std::vector<Correspondence> point;   // point-to-point residuals
  std::size_t searched_points = 0;     // map lookups made (the others were remembered)
  std::size_t size() const { return planar.size() + point.size(); }
};

// Each source point's last answer from the map and where the point was when it was found. A
// point whose answer still holds (VoxelHashMap::StillNearest) keeps it without a search, so the
// pairs are exactly those of a fresh search. Valid for one map and one max_distance, i.e.
// within one registration.
struct SearchMemory {
  SearchMemory() = default;
  explicit SearchMemory(std::size_t n) { Reset(n); }
  // Nothing remembered, for a source of n points (the buffers stay).
  void Reset(std::size_t n) {
    answer.resize(n);
    searched_at.resize(n);
    searched.assign(n, 0);
  }
  std::vector<VoxelHashMap::NearestPoint> answer;
  std::vector<Eigen::Vector3d> searched_at;
  std::vector<std::uint8_t> searched;  // 0: never
};

// Nearest-neighbour pairs within max_distance, in source order (deterministic; TBB parallel).
// Class-wise modes: a source point only matches map points of its own class; ground, roof and
// wall become point-to-plane, edge and unknown point-to-point. With unknown_defers_to_map an
// unknown source point matches any class and is point-to-plane on a planar map point (see
// RegistrationConfig). kPointToPoint ignores classes and normals; kPlaneOnly ignores classes
// and makes every pair with a map normal planar. `subset` says which source points are paired.
// With `memory` (sized to the source), answers still valid are reused and the others stored.
// FindCorrespondences' per-search buffers, kept by a caller that searches again and again.
struct CorrespondenceBuffers {
  std::vector<const MapPoint*> match;
  std::vector<std::uint8_t> kind;
  std::vector<std::array<std::size_t, 3>> counts, starts;  // per block: planar, point, searched
};

CorrespondenceSet FindCorrespondences(const std::vector<Eigen::Vector3d>& source_world,
                                      const std::vector<PointClass>& labels,
                                      const VoxelHashMap& map, double max_distance,
                                      RegistrationMode mode, bool unknown_defers_to_map = true,
                                      const std::vector<float>& times = {},
                                      const SourceSubset& subset = SourceSubset{},
                                      SearchMemory* memory = nullptr);
// The same into `out`, reusing its capacity and `buffers`.
void FindCorrespondences(const std::vector<Eigen::Vector3d>& source_world,
                         const std::vector<PointClass>& labels, const VoxelHashMap& map,
                         double max_distance, RegistrationMode mode, bool unknown_defers_to_map,
                         const std::vector<float>& times, const SourceSubset& subset,
                         SearchMemory* memory, CorrespondenceBuffers& buffers,
                         CorrespondenceSet& out);

}  // namespace dammloam
