#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <tsl/robin_map.h>
#include <vector>

#include "core/geometry/point_class.hpp"
#include "core/geometry/voxel.hpp"
#include "core/map/map_point.hpp"
#include "core/map/point_pool.hpp"

namespace dammloam {

// Sparse voxel grid of labelled points with normals (KISS-ICP's map, plus class and normal).
// Neighbour search looks at the 27 voxels around a query and, when asked for a class, only at
// points of that class: the paper's class-wise correspondences.
class VoxelHashMap {
 public:
  VoxelHashMap(double voxel_size, double max_distance, int max_points_per_voxel);

  // Adds sensor-frame points (with labels and sensor-frame normals) seen from T_world_sensor,
  // then drops voxels farther than max_distance from the sensor (once the sensor has moved 5%
  // of max_distance since the last crop). Normals may be empty.
  void Update(const std::vector<Eigen::Vector3d>& points, const std::vector<PointClass>& labels,
              const std::vector<Eigen::Vector3f>& normals, const Eigen::Isometry3d& T_world_sensor);
  // World-frame insertion; a voxel keeps at most max_points_per_voxel points of each class.
  void AddPoints(const std::vector<MapPoint>& points);
  void RemoveFarVoxels(const Eigen::Vector3d& origin);
  // Removes every point within `radius` of `origin` for which remove(point) is true (what has
  // moved away since it was mapped); voxels left empty are dropped. Returns how many went.
  template <typename Predicate>
  std::size_t RemovePointsIf(const Eigen::Vector3d& origin, double radius, Predicate remove);

  // Nearest map point to `query` in the 27-voxel neighbourhood, restricted to `label` when
  // given and closer than max_distance. nullptr when there is none.
  const MapPoint* ClosestNeighbour(
      const Eigen::Vector3d& query, std::optional<PointClass> label,
      double max_distance = std::numeric_limits<double>::infinity()) const {
    return Nearest(query, label, max_distance).point;
  }
  // The same answer, with what it takes to know, for a query that has moved since, that the
  // call would give it again: a lower bound on the distance of every other point the search
  // could return (the second-nearest point seen, the boxes it skipped, the 27-voxel block's
  // edge). A registration moving its source points by millimetres keeps such answers instead
  // of searching again (StillNearest).
  struct NearestPoint {
    const MapPoint* point = nullptr;  // nullptr: none within max_distance
    double others = 0.0;  // every other candidate (all of them if none) lies at least this far
  };
  NearestPoint Nearest(const Eigen::Vector3d& query, std::optional<PointClass> label,
                       double max_distance = std::numeric_limits<double>::infinity()) const;
  // Whether Nearest(query, same label, max_distance) would return `answer` again, `answer`
  // having been found for a query at `searched_at`. Exact (no false yes) by the triangle
  // inequality: the answer stays strictly nearest, within max_distance and within one voxel
  // (so inside the new block), while its distance plus the query's move stays below `others`.
  bool StillNearest(const NearestPoint& answer, const Eigen::Vector3d& searched_at,
                    const Eigen::Vector3d& query, double max_distance) const;

  // Mean and covariance of every map point in the 27 voxels around the voxel holding `point`,
  // all classes: the shape of the surface a point pair lands on. The same for every point of
  // one voxel.
  struct Neighbourhood {
    int count = 0;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  };
  Neighbourhood NeighbourhoodOf(const Eigen::Vector3d& point) const;
  // Over the same 27 voxels, the mean of n n^T of the stored normals: which ways the surface
  // there faces. Points without a normal are left out; `count` says how many had one.
  Eigen::Matrix3d NormalScatterOf(const Eigen::Vector3d& point, int& count) const;

  // Where the map changed (points added, voxels cropped) since the last call: what a cache of
  // answers about neighbourhoods must forget. `all`: everything may have changed (the first
  // call, a Clear, a copy or a move, or more changes than are worth listing). Only maps asked
  // keep the list.
  struct Changes {
    bool all = true;
    std::vector<Voxel> voxels;  // each voxel changed at most once per list
  };
  Changes TakeChanges();
  void TakeChanges(Changes& into);  // the same, reusing into's buffer

  std::vector<MapPoint> Points() const;
  std::size_t NumPoints() const { return num_points_; }
  std::size_t NumVoxels() const { return map_.size(); }
  bool empty() const { return map_.empty(); }
  void Clear() {
    map_.clear();
    pool_.Clear();
    owned_ = 0;
    num_points_ = 0;
    last_crop_origin_.reset();
    changes_.Reset();
  }
  double voxel_size() const { return voxel_size_; }
  double max_distance() const { return max_distance_; }

 private:
  // AddPoints with each point's voxel already known (voxels[i] holds points[i]).
  void AddPoints(const std::vector<MapPoint>& points, const std::vector<Voxel>& voxels);
  // A voxel's points are a run of the map's PointPool, grouped by class so that a class-wise
  // query scans only its own class: class c is slots [first + begin[c], first + begin[c + 1]).
  // The hash bucket holds only this 24-byte handle (40 bytes with its key; 72 with a
  // std::vector per voxel), and a search's 27 voxels lie in a few pages, not 27 heap blocks.
  struct VoxelBlock {
    std::uint32_t first = 0;     // the pool slot of the voxel's first point
    std::uint16_t capacity = 0;  // slots owned from `first` (holds size() points)
    std::array<std::uint16_t, kNumPointClasses + 1> begin{};
    std::uint32_t listed_in = 0;  // the ChangeLog::list this voxel was last put on
    std::size_t size() const { return begin[kNumPointClasses]; }
  };
  const MapPoint* ClassBegin(const VoxelBlock& block, std::size_t c) const {
    return pool_.At(block.first) + block.begin[c];
  }
  const MapPoint* ClassEnd(const VoxelBlock& block, std::size_t c) const {
    return pool_.At(block.first) + block.begin[c + 1];
  }
  const MapPoint* PointsBegin(const VoxelBlock& block) const { return pool_.At(block.first); }
  const MapPoint* PointsEnd(const VoxelBlock& block) const {
    return pool_.At(block.first) + block.size();
  }
  // Gives a full voxel room for kPointsPerGrowth more points: in place when it ends the pool,
  // else in a new run at the end (the old one becomes a hole).
  void Grow(VoxelBlock& block);
  // The voxel's run is a hole from now on.
  void Release(const VoxelBlock& block) { owned_ -= block.capacity; }
  // Compact() once holes are a third of the slots handed out: they would spread a search over
  // more memory and keep growing the pool.
  void CompactIfSparse();
  // Closes the holes in place; voxels keep their order in the pool and are left without spare
  // slots.
  void Compact();
  // Calls visit(point) for every map point in the 27 voxels around the one holding `point`.
  template <typename Visit>
  void ForEachPointAround(const Eigen::Vector3d& point, Visit visit) const;

  // A copy or a move is another map to whoever cached answers about this one: it starts with
  // `all`, and numbers its lists past every number its blocks may carry. Listing starts with
  // the first TakeChanges.
  struct ChangeLog {
    ChangeLog() = default;
    ChangeLog(const ChangeLog& other) : list(other.list + 1) {}
    ChangeLog(ChangeLog&& other) noexcept : list(other.list + 1) {}
    ChangeLog& operator=(const ChangeLog& other) { return Follow(other); }
    ChangeLog& operator=(ChangeLog&& other) noexcept { return Follow(other); }
    ChangeLog& Follow(const ChangeLog& other) {
      Reset();
      list = std::max(list, other.list) + 1;
      return *this;
    }
    void Reset() {
      all = true;
      voxels.clear();
    }
    void Add(const Voxel& voxel, VoxelBlock& block);
    bool listing = false;
    bool all = true;
    std::uint32_t list = 1;  // numbers the lists handed out, so a voxel is listed once per list
    std::vector<Voxel> voxels;
  };

  double voxel_size_;
  double max_distance_;
  int max_points_per_voxel_;
  tsl::robin_map<Voxel, VoxelBlock, VoxelHash> map_;
  PointPool pool_;
  std::size_t owned_ = 0;  // pool slots owned by voxels; the rest of pool_.end() are holes
  std::size_t num_points_ = 0;
  std::optional<Eigen::Vector3d> last_crop_origin_;
  ChangeLog changes_;
  // Update's buffers, kept between scans.
  std::vector<MapPoint> update_points_;
  std::vector<Voxel> update_voxels_;
};

template <typename Predicate>
std::size_t VoxelHashMap::RemovePointsIf(const Eigen::Vector3d& origin, double radius,
                                         Predicate remove) {
  const double reach = radius + 2.0 * voxel_size_;  // a voxel's points lie within its diagonal
  const double reach_sq = reach * reach;
  std::size_t removed = 0;
  for (auto it = map_.begin(); it != map_.end();) {
    VoxelBlock& block = it.value();
    MapPoint* points = pool_.At(block.first);
    if ((points[0].position - origin).squaredNorm() > reach_sq) {
      ++it;
      continue;
    }
    std::array<std::uint16_t, kNumPointClasses + 1> begin{};
    std::size_t kept = 0;
    for (std::size_t c = 0; c < kNumPointClasses; ++c) {
      begin[c] = static_cast<std::uint16_t>(kept);
      for (std::size_t k = block.begin[c]; k < block.begin[c + 1]; ++k) {
        if (!remove(static_cast<const MapPoint&>(points[k]))) points[kept++] = points[k];
      }
    }
    begin[kNumPointClasses] = static_cast<std::uint16_t>(kept);
    const std::size_t gone = block.size() - kept;
    if (gone == 0) {
      ++it;
      continue;
    }
    changes_.Add(it->first, block);
    removed += gone;
    num_points_ -= gone;
    if (kept == 0) {
      Release(block);
      it = map_.erase(it);
      continue;
    }
    block.begin = begin;
    ++it;
  }
  CompactIfSparse();
  return removed;
}

}  // namespace dammloam
