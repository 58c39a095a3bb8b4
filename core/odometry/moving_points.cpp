#include "core/odometry/moving_points.hpp"

#include <algorithm>
#include <cmath>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tsl/robin_map.h>
#include <tsl/robin_set.h>

#include <utility>

namespace dammloam {

namespace {

struct CellKey {
  int x, y, z;
  bool operator==(const CellKey& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct CellKeyHash {
  std::size_t operator()(const CellKey& k) const {
    return static_cast<std::size_t>(k.x) * 73856093u ^ static_cast<std::size_t>(k.y) * 19349669u ^
           static_cast<std::size_t>(k.z) * 83492791u;
  }
};

// Cell coordinates within +-2^20 cells (262 km at 0.25 m) in 21 bits each, for sorting.
std::uint64_t Packed(const CellKey& k) {
  constexpr std::int64_t kOffset = 1 << 20;
  constexpr std::uint64_t kMask = (1u << 21) - 1;
  return (static_cast<std::uint64_t>(k.x + kOffset) & kMask) << 42 |
         (static_cast<std::uint64_t>(k.y + kOffset) & kMask) << 21 |
         (static_cast<std::uint64_t>(k.z + kOffset) & kMask);
}
CellKey Unpacked(std::uint64_t v) {
  constexpr int kOffset = 1 << 20;
  constexpr std::uint64_t kMask = (1u << 21) - 1;
  return {static_cast<int>((v >> 42) & kMask) - kOffset, static_cast<int>((v >> 21) & kMask) - kOffset,
          static_cast<int>(v & kMask) - kOffset};
}

CellKey CellOf(const Eigen::Vector3d& p, double spacing) {
  return {static_cast<int>(std::floor(p.x() / spacing)), static_cast<int>(std::floor(p.y() / spacing)),
          static_cast<int>(std::floor(p.z() / spacing))};
}

// Points grouped by cell: a cell's points are order[begin, end).
struct CellGrid {
  struct Range {
    const std::uint32_t* b;
    const std::uint32_t* e;
    const std::uint32_t* begin() const { return b; }
    const std::uint32_t* end() const { return e; }
  };
  tsl::robin_map<CellKey, std::pair<std::uint32_t, std::uint32_t>, CellKeyHash> cells;
  std::vector<std::uint32_t> order;
  bool Has(const CellKey& k) const { return cells.count(k) != 0; }
  Range PointsIn(const CellKey& k) const {
    const auto it = cells.find(k);
    if (it == cells.end()) return {nullptr, nullptr};
    return {order.data() + it->second.first, order.data() + it->second.second};
  }
};

// The points that can move within max_range, grouped by cell of `spacing`.
CellGrid BuildCellGrid(const std::vector<Eigen::Vector3d>& points_sensor,
                       const std::vector<PointClass>& labels, double spacing, double max_range) {
  const double max_sq = max_range * max_range;
  CellGrid grid;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;
  keyed.reserve(points_sensor.size());
  for (std::size_t i = 0; i < points_sensor.size(); ++i) {
    if (i < labels.size() && !CanMove(labels[i])) continue;
    if (points_sensor[i].squaredNorm() > max_sq) continue;
    keyed.emplace_back(Packed(CellOf(points_sensor[i], spacing)),
                       static_cast<std::uint32_t>(i));
  }
  std::sort(keyed.begin(), keyed.end());
  grid.order.reserve(keyed.size());
  for (std::size_t a = 0; a < keyed.size();) {
    std::size_t b = a;
    while (b < keyed.size() && keyed[b].first == keyed[a].first) grid.order.push_back(keyed[b++].second);
    grid.cells.emplace(Unpacked(keyed[a].first), std::pair<std::uint32_t, std::uint32_t>(
                                                     static_cast<std::uint32_t>(a),
                                                     static_cast<std::uint32_t>(b)));
    a = b;
  }
  return grid;
}

}  // namespace

MovingPoints::MovingPoints(const MovingPointsConfig& config, const SensorModel& sensor)
    : config_(config), sensor_(sensor) {}

void MovingPoints::AddView(const std::vector<Eigen::Vector3d>& points_sensor,
                           const std::vector<PointClass>& labels,
                           const Eigen::Isometry3d& T_world_sensor, double stamp) {
  std::vector<Eigen::Vector3d> sample;
  const double max_sq = config_.max_range * config_.max_range;
  tsl::robin_set<CellKey, CellKeyHash> taken;
  for (std::size_t i = 0; i < points_sensor.size(); ++i) {
    if (i < labels.size() && !CanMove(labels[i])) continue;
    if (points_sensor[i].squaredNorm() > max_sq) continue;
    const Eigen::Vector3d p = T_world_sensor * points_sensor[i];
    if (taken.insert(CellOf(p, config_.vacated_sample)).second) sample.push_back(p);
  }
  views_.push_back({stamp, DepthView(config_.view, sensor_, points_sensor, T_world_sensor),
                    std::move(sample)});
  double oldest_age = 0.0;
  for (double age : config_.view_ages) oldest_age = std::max(oldest_age, age);
  // Keep one view older than the oldest age, so that age always finds a view at least as old.
  while (views_.size() > 2 && views_[1].stamp <= stamp - oldest_age) views_.pop_front();
}

std::vector<const MovingPoints::StampedView*> MovingPoints::ViewsToTest(double stamp) const {
  std::vector<const StampedView*> out;
  for (double age : config_.view_ages) {
    const StampedView* chosen = nullptr;
    for (const StampedView& v : views_) {
      if (v.stamp <= stamp - age + 1e-6) chosen = &v;  // the newest one old enough
    }
    if (chosen && std::find(out.begin(), out.end(), chosen) == out.end()) out.push_back(chosen);
  }
  return out;
}

std::vector<std::uint8_t> MovingPoints::Detect(const std::vector<Eigen::Vector3d>& points_sensor,
                                               const std::vector<PointClass>& labels,
                                               const Eigen::Isometry3d& T_world_sensor,
                                               double stamp, const VoxelHashMap* map) const {
  const std::vector<const StampedView*> views = ViewsToTest(stamp);
  if (views.empty()) return std::vector<std::uint8_t>(points_sensor.size(), 0);
  std::vector<std::uint8_t> moving = Evidence(points_sensor, labels, T_world_sensor, views);
  if (map != nullptr) NextToVacated(points_sensor, labels, T_world_sensor, views, *map, moving);
  SpreadOverObjects(points_sensor, labels, moving);
  return moving;
}

std::vector<std::uint8_t> MovingPoints::Evidence(const std::vector<Eigen::Vector3d>& points_sensor,
                                                 const std::vector<PointClass>& labels,
                                                 const Eigen::Isometry3d& T_world_sensor,
                                                 const std::vector<const StampedView*>& views) const {
  std::vector<std::uint8_t> seen_through(points_sensor.size(), 0);
  const double max_sq = config_.max_range * config_.max_range;
  // Each point goes straight from this scan's frame into each view's: one transform per view.
  std::vector<Eigen::Isometry3d> T_view_sensor;
  for (const StampedView* view : views) T_view_sensor.push_back(view->view.pose().inverse() * T_world_sensor);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points_sensor.size(), 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) {
      if (i < labels.size() && !CanMove(labels[i])) continue;
      if (points_sensor[i].squaredNorm() > max_sq) continue;
      for (std::size_t v = 0; v < views.size(); ++v) {
        const Eigen::Vector3d q = T_view_sensor[v] * points_sensor[i];
        if (views[v]->view.SeesThroughInViewFrame(q, Margin(q.norm()))) {
          seen_through[i] = kSeenThrough;
          break;
        }
      }
    }
  });
  return seen_through;
}

void MovingPoints::NextToVacated(const std::vector<Eigen::Vector3d>& points_sensor,
                                 const std::vector<PointClass>& labels,
                                 const Eigen::Isometry3d& T_world_sensor,
                                 const std::vector<const StampedView*>& views,
                                 const VoxelHashMap& map, std::vector<std::uint8_t>& evidence) const {
  // Space vacated since the views: their sampled points that this scan sees through.
  const DepthView now(config_.view, sensor_, points_sensor, T_world_sensor);
  const Eigen::Vector3d origin = T_world_sensor.translation();
  const double cell = 0.5 * config_.vacated_reach;  // 27 cells around reach at least this far
  tsl::robin_set<CellKey, CellKeyHash> vacated;
  for (const StampedView* view : views) {
    for (const Eigen::Vector3d& w : view->sample_world) {
      const double distance = (w - origin).norm();
      if (distance > config_.max_range) continue;
      if (now.SeesThrough(w, Margin(distance))) vacated.insert(CellOf(w, cell));
    }
  }
  if (vacated.empty()) return;
  // Vacated cells and their 26 neighbours, so that each point asks once instead of 27 times
  // (a few dozen vacated cells against tens of thousands of points).
  tsl::robin_set<CellKey, CellKeyHash> near;
  for (const CellKey& k : vacated) {
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) near.insert(CellKey{k.x + dx, k.y + dy, k.z + dz});
  }
  const auto near_vacated = [&](const Eigen::Vector3d& p) { return near.count(CellOf(p, cell)) != 0; };
  const double max_sq = config_.max_range * config_.max_range;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points_sensor.size(), 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) {
      if (evidence[i] != 0 || (i < labels.size() && !CanMove(labels[i]))) continue;
      if (points_sensor[i].squaredNorm() > max_sq) continue;
      const Eigen::Vector3d p = T_world_sensor * points_sensor[i];
      if (!near_vacated(p)) continue;
      const bool hidden = std::any_of(views.begin(), views.end(), [&](const StampedView* view) {
        return view->view.Hides(p, Margin((p - view->view.pose().translation()).norm()));
      });
      if (!hidden) continue;
      if (map.ClosestNeighbour(p, std::nullopt, config_.unmapped_distance) != nullptr) continue;
      evidence[i] = kNextToVacated;
    }
  });
}

// Connected components of the judged points on a grid of cluster_spacing cells (26-neighbours);
// a compact component with enough evidence is moving as a whole. Only components holding
// evidence are walked, and a walk stops once the component is wider than an actor: the scan's
// large structures (walls, hedges) are never walked whole, which was most of this stage's time.
void MovingPoints::SpreadOverObjects(const std::vector<Eigen::Vector3d>& points_sensor,
                                     const std::vector<PointClass>& labels,
                                     std::vector<std::uint8_t>& moving) const {
  if (std::none_of(moving.begin(), moving.end(), [](std::uint8_t m) { return m != 0; })) return;
  const CellGrid grid =
      BuildCellGrid(points_sensor, labels, config_.cluster_spacing, config_.max_range);
  // Cells walked so far: kWalked, or kLarge once their walk found a structure wider than an
  // actor (a later walk that meets one belongs to that structure too).
  constexpr std::uint8_t kWalked = 1, kLarge = 2;
  std::vector<std::uint8_t> decided(moving.size(), 0);  // by a compact object's verdict
  tsl::robin_map<CellKey, std::uint8_t, CellKeyHash> visited;
  std::vector<CellKey> stack, members;
  for (std::size_t i = 0; i < moving.size(); ++i) {
    if (moving[i] == 0) continue;
    const CellKey seed = CellOf(points_sensor[i], config_.cluster_spacing);
    if (!visited.emplace(seed, kWalked).second) continue;
    members.clear();
    stack.assign(1, seed);
    bool compact = true;
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e30), hi = -lo;
    while (!stack.empty() && compact) {
      const CellKey k = stack.back();
      stack.pop_back();
      members.push_back(k);
      for (std::uint32_t j : grid.PointsIn(k)) {
        lo = lo.cwiseMin(points_sensor[j].head<2>());
        hi = hi.cwiseMax(points_sensor[j].head<2>());
      }
      compact = (hi - lo).norm() <= config_.max_object_extent;
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            const CellKey n{k.x + dx, k.y + dy, k.z + dz};
            if (!grid.Has(n)) continue;
            const auto [it, added] = visited.emplace(n, kWalked);
            if (added) stack.push_back(n);
            else if (it->second == kLarge) compact = false;
          }
    }
    if (!compact) {
      // Larger than an actor (a wall someone stands against): its points move one by one, on
      // their own evidence of being seen through (see below).
      for (const CellKey& k : members) visited[k] = kLarge;
      for (const CellKey& k : stack) visited[k] = kLarge;
      continue;
    }
    int points = 0, evidence = 0;
    for (const CellKey& k : members) {
      for (std::uint32_t j : grid.PointsIn(k)) {
        ++points;
        evidence += moving[j] != 0;
      }
    }
    // Too little evidence for an object: single seen-through points are noise at depth edges.
    const std::uint8_t verdict = evidence >= config_.min_evidence &&
                                 evidence >= config_.min_evidence_share * points;
    for (const CellKey& k : members) {
      for (std::uint32_t j : grid.PointsIn(k)) {
        moving[j] = verdict;
        decided[j] = 1;
      }
    }
  }
  // Points of large structures keep only the evidence of being seen through: next to vacated
  // space a wall is only revealed, not moving.
  for (std::size_t i = 0; i < moving.size(); ++i) {
    if (!decided[i]) moving[i] = (moving[i] & kSeenThrough) ? 1 : 0;
  }
}

}  // namespace dammloam
