#include "core/backend/vacated_points.hpp"

#include <cmath>
#include <tsl/robin_map.h>

#include "core/geometry/depth_view.hpp"

namespace dammloam::backend {

namespace {

constexpr double kTile = 8.0;  // metres; points are visited by 2-D tiles around each keyframe

std::int64_t TileKey(int x, int y) {
  return (static_cast<std::int64_t>(x) << 32) ^ static_cast<std::uint32_t>(y);
}

int TileOf(double v) { return static_cast<int>(std::floor(v / kTile)); }

using Tiles = tsl::robin_map<std::int64_t, std::vector<std::uint32_t>>;

Tiles TilePoints(const std::vector<Eigen::Vector3d>& points) {
  Tiles tiles;
  for (std::uint32_t i = 0; i < points.size(); ++i) {
    tiles[TileKey(TileOf(points[i].x()), TileOf(points[i].y()))].push_back(i);
  }
  return tiles;
}

}  // namespace

std::vector<std::uint8_t> FindVacatedPoints(const std::vector<Eigen::Vector3d>& points_world,
                                            const std::vector<std::uint32_t>& source,
                                            const std::vector<Keyframe>& keyframes,
                                            const SensorModel& sensor, double voxel_size,
                                            const VacatedPointsConfig& config) {
  std::vector<std::uint8_t> vacated(points_world.size(), 0);
  if (!config.enabled || points_world.empty() || source.size() != points_world.size()) return vacated;
  // Views through since the last one that saw a surface (or the point's own keyframe).
  std::vector<std::uint16_t> through(points_world.size(), 0);
  const Tiles tiles = TilePoints(points_world);
  std::vector<float> mapped_range(points_world.size(), 0.0f);  // from the keyframe that mapped it
  for (std::size_t i = 0; i < points_world.size(); ++i) {
    if (source[i] < keyframes.size()) {
      mapped_range[i] = static_cast<float>((points_world[i] - keyframes[source[i]].T_world_sensor.translation()).norm());
    }
  }
  DepthView::Config view_config;
  view_config.point_radius = voxel_size;
  const int reach = static_cast<int>(std::ceil(config.max_range / kTile));
  for (std::uint32_t k = 0; k < keyframes.size(); ++k) {
    const Keyframe& kf = keyframes[k];
    if (kf.points.empty()) continue;
    std::vector<Eigen::Vector3d> returns = kf.points;
    returns.insert(returns.end(), kf.occluders.begin(), kf.occluders.end());
    const DepthView view(view_config, sensor, returns, kf.T_world_sensor);
    const Eigen::Matrix3d R_sensor_world = kf.T_world_sensor.rotation().transpose();
    const Eigen::Vector3d origin = kf.T_world_sensor.translation();
    const int tx = TileOf(origin.x()), ty = TileOf(origin.y());
    for (int y = ty - reach; y <= ty + reach; ++y) {
      for (int x = tx - reach; x <= tx + reach; ++x) {
        const auto tile = tiles.find(TileKey(x, y));
        if (tile == tiles.end()) continue;
        for (const std::uint32_t i : tile->second) {
          if (source[i] > k) continue;  // not mapped yet
          if (source[i] == k) {
            through[i] = 0;
            continue;
          }
          const Eigen::Vector3d q = R_sensor_world * (points_world[i] - origin);
          const double range = q.norm();
          if (range < config.min_range || range > config.max_range) continue;
          const double margin = config.margin + config.margin_per_metre * range;
          // No return around a point this view is nearer to than the keyframe that mapped it:
          // nothing there (sky behind a car's roof). From farther, a faint surface may just
          // not return.
          const bool nearer_than_mapped = range <= mapped_range[i];
          if (nearer_than_mapped ? view.SeesThroughOrNothingInViewFrame(q, margin)
                                 : view.SeesThroughInViewFrame(q, margin)) {
            if (through[i] < UINT16_MAX) ++through[i];
          } else if (view.SeesSurfaceInViewFrame(q, margin)) {
            through[i] = 0;
          }
        }
      }
    }
  }
  for (std::size_t i = 0; i < vacated.size(); ++i) vacated[i] = through[i] >= config.min_views ? 1 : 0;
  return vacated;
}

}  // namespace dammloam::backend
