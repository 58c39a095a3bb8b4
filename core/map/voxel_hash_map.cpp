#include "core/map/voxel_hash_map.hpp"

#include "core/map/map_config.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

namespace dammloam {
namespace {

constexpr std::size_t kPointsPerGrowth = 2;

}  // namespace

VoxelHashMap::VoxelHashMap(double voxel_size, double max_distance, int max_points_per_voxel)
    : voxel_size_(voxel_size),
      max_distance_(max_distance),
      max_points_per_voxel_(std::min(max_points_per_voxel, kMaxPointsPerVoxel)) {}

void VoxelHashMap::Update(const std::vector<Eigen::Vector3d>& points,
                          const std::vector<PointClass>& labels,
                          const std::vector<Eigen::Vector3f>& normals,
                          const Eigen::Isometry3d& T_world_sensor) {
  const bool has_normals = normals.size() == points.size();
  const Eigen::Matrix3f R = T_world_sensor.linear().cast<float>();
  std::vector<MapPoint>& world = update_points_;
  world.resize(points.size());
  // The voxels too, here in parallel: insertion is serial, and it needed each point's voxel
  // twice (the lookup and the change log), three divisions and floors each time.
  std::vector<Voxel>& voxels = update_voxels_;
  voxels.resize(points.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points.size(), 4096), [&](const auto& range) {
    for (std::size_t i = range.begin(); i < range.end(); ++i) {
      const PointClass label = i < labels.size() ? labels[i] : PointClass::Unknown;
      const Eigen::Vector3f n = has_normals ? Eigen::Vector3f(R * normals[i])
                                            : Eigen::Vector3f::Zero();
      world[i] = {T_world_sensor * points[i], n, label};
      voxels[i] = PointToVoxel(world[i].position, voxel_size_);
    }
  });
  AddPoints(world, voxels);
  // Cropping walks the whole map; the map only outgrows its radius by the distance travelled
  // since the last crop, so cropping after every 5% of the radius bounds memory just as well.
  constexpr double kCropAfterShareOfRadius = 0.05;
  const Eigen::Vector3d origin = T_world_sensor.translation();
  if (!last_crop_origin_ ||
      (origin - *last_crop_origin_).norm() > kCropAfterShareOfRadius * max_distance_) {
    RemoveFarVoxels(origin);
    last_crop_origin_ = origin;
  }
}

void VoxelHashMap::AddPoints(const std::vector<MapPoint>& points) {
  std::vector<Voxel> voxels(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    voxels[i] = PointToVoxel(points[i].position, voxel_size_);
  }
  AddPoints(points, voxels);
}

void VoxelHashMap::AddPoints(const std::vector<MapPoint>& points,
                             const std::vector<Voxel>& voxels) {
  if (max_points_per_voxel_ < 1) return;  // would leave empty voxels behind
  // A point closer than voxel / sqrt(max points) to one of its class already in the voxel
  // adds nothing (as in KISS-ICP): the surface there is sampled. Without this, every revisit
  // adds near-duplicates until the voxel is full, and the map of a scene the sensor keeps
  // seeing grows for thousands of scans.
  const double min_spacing_sq = voxel_size_ * voxel_size_ / max_points_per_voxel_;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const MapPoint& p = points[i];
    // One lookup; a new voxel always receives the point, so no block is left empty.
    VoxelBlock& block = map_[voxels[i]];
    const std::size_t c = Index(p.label);
    if (block.size() > 0) {  // a new voxel has no run in the pool yet
      if (ClassEnd(block, c) - ClassBegin(block, c) >= max_points_per_voxel_) continue;
      const bool sampled =
          std::any_of(ClassBegin(block, c), ClassEnd(block, c), [&](const MapPoint& q) {
            return (q.position - p.position).squaredNorm() < min_spacing_sq;
          });
      if (sampled) continue;
    }
    if (block.size() == block.capacity) Grow(block);
    changes_.Add(voxels[i], block);
    MapPoint* range = pool_.At(block.first);
    std::copy_backward(range + block.begin[c + 1], range + block.size(), range + block.size() + 1);
    range[block.begin[c + 1]] = p;
    for (std::size_t k = c + 1; k <= kNumPointClasses; ++k) ++block.begin[k];
    ++num_points_;
  }
  CompactIfSparse();
}

void VoxelHashMap::Grow(VoxelBlock& block) {
  // A voxel fills one point at a time over many revisits; room for a few more, not doubling,
  // or a third of the map's memory would be slack.
  const std::size_t wanted = std::size_t{block.capacity} + kPointsPerGrowth;
  if (block.capacity > 0 && pool_.CanExtend(block.first, block.capacity, kPointsPerGrowth)) {
    pool_.Append(kPointsPerGrowth);
  } else {
    // The voxel is full (size == capacity): it moves to the end, its old run becomes a hole.
    const std::uint32_t first = pool_.Append(wanted);
    std::copy_n(pool_.At(block.first), block.size(), pool_.At(first));
    block.first = first;
  }
  owned_ += kPointsPerGrowth;
  block.capacity = static_cast<std::uint16_t>(wanted);
}

void VoxelHashMap::CompactIfSparse() {
  constexpr std::size_t kMinSlots = 4096;  // below this, holes cost nothing worth a pass
  const std::size_t holes = pool_.end() - owned_;
  if (pool_.end() >= kMinSlots && 3 * holes >= pool_.end()) Compact();
}

void VoxelHashMap::Compact() {
  // Runs in pool order only ever move towards the front (a run that would cross a page goes to
  // the next page's start, where its old place was too), so no second buffer is needed.
  std::vector<VoxelBlock*> order;
  order.reserve(map_.size());
  for (auto it = map_.begin(); it != map_.end(); ++it) order.push_back(&it.value());
  std::sort(order.begin(), order.end(),
            [](const VoxelBlock* a, const VoxelBlock* b) { return a->first < b->first; });
  std::size_t next = 0;
  owned_ = 0;
  for (VoxelBlock* block : order) {
    const std::uint32_t first = PointPool::Place(next, block->size());
    if (block->first != first) std::copy_n(pool_.At(block->first), block->size(), pool_.At(first));
    block->first = first;
    block->capacity = static_cast<std::uint16_t>(block->size());
    next = first + block->size();
    owned_ += block->size();
  }
  pool_.Truncate(next);
}

void VoxelHashMap::RemoveFarVoxels(const Eigen::Vector3d& origin) {
  const double max_sq = max_distance_ * max_distance_;
  for (auto it = map_.begin(); it != map_.end();) {
    const Eigen::Vector3d& p = pool_.At(it->second.first)->position;
    if ((p - origin).squaredNorm() > max_sq) {
      changes_.Add(it->first, it.value());
      num_points_ -= it->second.size();
      Release(it->second);
      it = map_.erase(it);
    } else {
      ++it;
    }
  }
  CompactIfSparse();
}

void VoxelHashMap::ChangeLog::Add(const Voxel& voxel, VoxelBlock& block) {
  // Past this many, forgetting voxel by voxel costs more than starting over.
  constexpr std::size_t kMaxListed = 1 << 16;
  if (!listing || all || block.listed_in == list) return;
  if (voxels.size() >= kMaxListed) {
    Reset();
    return;
  }
  block.listed_in = list;
  voxels.push_back(voxel);
}

VoxelHashMap::Changes VoxelHashMap::TakeChanges() {
  Changes out;
  TakeChanges(out);
  return out;
}

void VoxelHashMap::TakeChanges(Changes& into) {
  into.all = changes_.all;
  into.voxels.swap(changes_.voxels);  // the two lists' buffers take turns
  changes_.voxels.clear();
  changes_.all = false;
  changes_.listing = true;
  ++changes_.list;
}

namespace {

// The 27 neighbour offsets, the query's own voxel first, then faces, edges and corners: the
// nearer boxes come first so the farther ones are mostly pruned by the best distance so far.
constexpr std::array<std::array<int, 3>, 27> NeighbourOffsets() {
  std::array<std::array<int, 3>, 27> offsets{};
  std::size_t n = 0;
  for (int order = 0; order <= 3; ++order) {
    for (int dx = -1; dx <= 1; ++dx) {
      for (int dy = -1; dy <= 1; ++dy) {
        for (int dz = -1; dz <= 1; ++dz) {
          if ((dx != 0) + (dy != 0) + (dz != 0) == order) offsets[n++] = {dx, dy, dz};
        }
      }
    }
  }
  return offsets;
}
constexpr std::array<std::array<int, 3>, 27> kNeighbourOffsets = NeighbourOffsets();

// Squared distances from a point at `local` (voxel units, in [0, 1)^3 of its own voxel) to the
// neighbour boxes, per axis and offset -1 / 0 / +1: a box's squared distance is the sum over
// its three offsets, so the 27 boxes cost three additions each.
struct BoxGaps {
  explicit BoxGaps(const Eigen::Vector3d& local) {
    for (int axis = 0; axis < 3; ++axis) {
      const double below = local[axis], above = 1.0 - local[axis];
      sq[axis] = {below * below, 0.0, above * above};
    }
  }
  double DistanceSq(const std::array<int, 3>& offset) const {
    return sq[0][offset[0] + 1] + sq[1][offset[1] + 1] + sq[2][offset[2] + 1];
  }
  std::array<std::array<double, 3>, 3> sq;
};

// Distance from `local` (voxel units) to the nearest face of the 27-voxel block around its
// voxel, in voxel units: every point outside the block is at least this far away.
double BlockEdgeDistance(const Eigen::Vector3d& local) {
  double d = std::numeric_limits<double>::max();
  for (int axis = 0; axis < 3; ++axis) d = std::min({d, local[axis] + 1.0, 2.0 - local[axis]});
  return d;
}

}  // namespace

VoxelHashMap::NearestPoint VoxelHashMap::Nearest(const Eigen::Vector3d& query,
                                                 std::optional<PointClass> label,
                                                 double max_distance) const {
  const Voxel centre = PointToVoxel(query, voxel_size_);
  const Eigen::Vector3d local = query / voxel_size_ - centre.cast<double>();
  const double inv_voxel_sq = 1.0 / (voxel_size_ * voxel_size_);
  const BoxGaps gaps(local);
  const double gate_sq = std::isfinite(max_distance) ? max_distance * max_distance
                                                     : std::numeric_limits<double>::max();
  const MapPoint* nearest = nullptr;
  double nearest_sq = std::numeric_limits<double>::max();  // of any point seen, gate or not
  double second_sq = std::numeric_limits<double>::max();
  double skipped_box_sq = std::numeric_limits<double>::max();  // voxel units, nearest skipped
  for (const auto& offset : kNeighbourOffsets) {
    // A box farther than the best match cannot hold a better one: skip its hash lookup.
    const double box_sq = gaps.DistanceSq(offset);
    if (box_sq >= std::min(gate_sq, nearest_sq) * inv_voxel_sq) {
      skipped_box_sq = std::min(skipped_box_sq, box_sq);
      continue;
    }
    const auto it = map_.find(centre + Voxel(offset[0], offset[1], offset[2]));
    if (it == map_.end()) continue;
    const VoxelBlock& block = it->second;
    const MapPoint* first = label ? ClassBegin(block, Index(*label)) : PointsBegin(block);
    const MapPoint* last = label ? ClassEnd(block, Index(*label)) : PointsEnd(block);
    for (const MapPoint* p = first; p != last; ++p) {
      const double d_sq = (p->position - query).squaredNorm();
      if (d_sq < nearest_sq) {
        second_sq = nearest_sq;
        nearest_sq = d_sq;
        nearest = p;
      } else if (d_sq < second_sq) {
        second_sq = d_sq;
      }
    }
  }
  // Below this every unseen point lies: skipped boxes, and everything outside the block.
  const double unseen =
      std::min(std::sqrt(skipped_box_sq), BlockEdgeDistance(local)) * voxel_size_;
  NearestPoint out;
  if (nearest != nullptr && nearest_sq < gate_sq) {
    out.point = nearest;
    out.others = std::min(std::sqrt(second_sq), unseen);
  } else {
    out.others = std::min(std::sqrt(nearest_sq), unseen);
  }
  return out;
}

bool VoxelHashMap::StillNearest(const NearestPoint& answer, const Eigen::Vector3d& searched_at,
                                const Eigen::Vector3d& query, double max_distance) const {
  // Rounding of the squared distances is ~1e-13 m at a kilometre; stay well clear of it.
  constexpr double kRoundingMargin = 1e-9;
  const double moved = (query - searched_at).norm();
  if (answer.point == nullptr) {
    // Every point was at least `others` away: none comes within the gate.
    return moved + max_distance < answer.others - kRoundingMargin;
  }
  const double d = (answer.point->position - query).norm();
  return d + moved < answer.others - kRoundingMargin && d < max_distance - kRoundingMargin &&
         d < voxel_size_ - kRoundingMargin;
}

template <typename Visit>
void VoxelHashMap::ForEachPointAround(const Eigen::Vector3d& point, Visit visit) const {
  const Voxel voxel = PointToVoxel(point, voxel_size_);
  for (const auto& offset : kNeighbourOffsets) {
    const auto it = map_.find(voxel + Voxel(offset[0], offset[1], offset[2]));
    if (it == map_.end()) continue;
    std::for_each(PointsBegin(it->second), PointsEnd(it->second), visit);
  }
}

VoxelHashMap::Neighbourhood VoxelHashMap::NeighbourhoodOf(const Eigen::Vector3d& point) const {
  const Voxel voxel = PointToVoxel(point, voxel_size_);
  // Centred on the voxel's centre, not on `point`: every point of a voxel gets the same
  // (bit-identical) answer, so callers may cache it per voxel.
  const Eigen::Vector3d centre = (voxel.cast<double>().array() + 0.5).matrix() * voxel_size_;
  Neighbourhood out;
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  ForEachPointAround(point, [&](const MapPoint& p) {
    const Eigen::Vector3d d = p.position - centre;  // centred for precision far from origin
    out.mean += d;
    second.noalias() += d * d.transpose();
    ++out.count;
  });
  if (out.count == 0) return out;
  out.mean /= out.count;
  out.covariance = second / out.count - out.mean * out.mean.transpose();
  out.mean += centre;
  return out;
}

Eigen::Matrix3d VoxelHashMap::NormalScatterOf(const Eigen::Vector3d& point, int& count) const {
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  count = 0;
  ForEachPointAround(point, [&](const MapPoint& p) {
    if (p.normal.squaredNorm() < 0.5f) return;  // zero: no normal
    const Eigen::Vector3d n = p.normal.cast<double>();
    scatter.noalias() += n * n.transpose();
    ++count;
  });
  if (count > 0) scatter /= count;
  return scatter;
}

std::vector<MapPoint> VoxelHashMap::Points() const {
  std::vector<MapPoint> out;
  out.reserve(NumPoints());
  for (const auto& [voxel, block] : map_) out.insert(out.end(), PointsBegin(block), PointsEnd(block));
  return out;
}

}  // namespace dammloam
