#include "core/odometry/moving_points.hpp"

#include <algorithm>
#include <cmath>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tsl/robin_map.h>

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

CellKey CellOf(const Eigen::Vector3d& p, double spacing) {
  return {static_cast<int>(std::floor(p.x() / spacing)), static_cast<int>(std::floor(p.y() / spacing)),
          static_cast<int>(std::floor(p.z() / spacing))};
}

}  // namespace

MovingPoints::MovingPoints(const MovingPointsConfig& config, const SensorModel& sensor)
    : config_(config), sensor_(sensor) {}

void MovingPoints::AddView(const std::vector<Eigen::Vector3d>& points_sensor,
                           const Eigen::Isometry3d& T_world_sensor, double stamp) {
  views_.push_back({stamp, DepthView(config_.view, sensor_, points_sensor, T_world_sensor)});
  double oldest_age = 0.0;
  for (double age : config_.view_ages) oldest_age = std::max(oldest_age, age);
  // Keep one view older than the oldest age, so that age always finds a view at least as old.
  while (views_.size() > 2 && views_[1].stamp <= stamp - oldest_age) views_.pop_front();
}

std::vector<const DepthView*> MovingPoints::ViewsToTest(double stamp) const {
  std::vector<const DepthView*> out;
  for (double age : config_.view_ages) {
    const DepthView* chosen = nullptr;
    for (const StampedView& v : views_) {
      if (v.stamp <= stamp - age + 1e-6) chosen = &v.view;  // the newest one old enough
    }
    if (chosen && std::find(out.begin(), out.end(), chosen) == out.end()) out.push_back(chosen);
  }
  return out;
}

std::vector<std::uint8_t> MovingPoints::Detect(const std::vector<Eigen::Vector3d>& points_sensor,
                                               const std::vector<PointClass>& labels,
                                               const Eigen::Isometry3d& T_world_sensor,
                                               double stamp) const {
  const std::vector<const DepthView*> views = ViewsToTest(stamp);
  if (views.empty()) return std::vector<std::uint8_t>(points_sensor.size(), 0);
  std::vector<std::uint8_t> moving = Evidence(points_sensor, labels, T_world_sensor, views);
  SpreadOverObjects(points_sensor, labels, moving);
  return moving;
}

std::vector<std::uint8_t> MovingPoints::Evidence(const std::vector<Eigen::Vector3d>& points_sensor,
                                                 const std::vector<PointClass>& labels,
                                                 const Eigen::Isometry3d& T_world_sensor,
                                                 const std::vector<const DepthView*>& views) const {
  std::vector<std::uint8_t> seen_through(points_sensor.size(), 0);
  const double max_sq = config_.max_range * config_.max_range;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, points_sensor.size(), 4096), [&](const auto& r) {
    for (std::size_t i = r.begin(); i < r.end(); ++i) {
      if (i < labels.size() && !CanMove(labels[i])) continue;
      if (points_sensor[i].squaredNorm() > max_sq) continue;
      const Eigen::Vector3d p = T_world_sensor * points_sensor[i];
      for (const DepthView* view : views) {
        const double distance = (p - view->pose().translation()).norm();
        if (view->SeesThrough(p, Margin(distance))) {
          seen_through[i] = 1;
          break;
        }
      }
    }
  });
  return seen_through;
}

// Connected components of the judged points on a grid of cluster_spacing cells (26-neighbours);
// a compact component with enough evidence is moving as a whole.
void MovingPoints::SpreadOverObjects(const std::vector<Eigen::Vector3d>& points_sensor,
                                     const std::vector<PointClass>& labels,
                                     std::vector<std::uint8_t>& moving) const {
  if (std::none_of(moving.begin(), moving.end(), [](std::uint8_t m) { return m != 0; })) return;
  const double spacing = config_.cluster_spacing;
  const double max_sq = config_.max_range * config_.max_range;
  tsl::robin_map<CellKey, std::vector<std::uint32_t>, CellKeyHash> cells;
  for (std::size_t i = 0; i < points_sensor.size(); ++i) {
    if (i < labels.size() && !CanMove(labels[i])) continue;
    if (points_sensor[i].squaredNorm() > max_sq) continue;
    cells[CellOf(points_sensor[i], spacing)].push_back(static_cast<std::uint32_t>(i));
  }
  tsl::robin_map<CellKey, int, CellKeyHash> component_of;
  std::vector<CellKey> stack, members;
  for (const auto& [seed, unused] : cells) {
    if (component_of.count(seed)) continue;
    members.clear();
    stack.assign(1, seed);
    component_of[seed] = 1;
    while (!stack.empty()) {
      const CellKey k = stack.back();
      stack.pop_back();
      members.push_back(k);
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            const CellKey n{k.x + dx, k.y + dy, k.z + dz};
            if (!cells.count(n) || component_of.count(n)) continue;
            component_of[n] = 1;
            stack.push_back(n);
          }
    }
    int points = 0, evidence = 0;
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e30), hi = -lo;
    for (const CellKey& k : members) {
      for (std::uint32_t i : cells.at(k)) {
        ++points;
        evidence += moving[i];
        lo = lo.cwiseMin(points_sensor[i].head<2>());
        hi = hi.cwiseMax(points_sensor[i].head<2>());
      }
    }
    const bool compact = (hi - lo).norm() <= config_.max_object_extent;
    if (!compact || evidence < config_.min_evidence ||
        evidence < config_.min_evidence_share * points) {
      // Too little evidence for an object: single seen-through points of a large or static
      // one are noise at depth edges, unless the object is larger than an actor.
      if (compact) {
        for (const CellKey& k : members) for (std::uint32_t i : cells.at(k)) moving[i] = 0;
      }
      continue;
    }
    for (const CellKey& k : members) for (std::uint32_t i : cells.at(k)) moving[i] = 1;
  }
}

}  // namespace dammloam
