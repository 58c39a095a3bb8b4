#pragma once
// Exact synthetic LiDAR scans for the preprocess suites: a spinning sensor (uniform beams,
// pixel-centre azimuths in the RangeImage column convention) ray-cast analytically against a
// box room seen from inside and solid boxes seen from outside.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include "core/geometry/scan.hpp"

namespace dammloam::test {

// Surface hit by a ray. Room faces: 0..5 = x-, x+, y-, y+, floor (z-), ceiling (z+);
// solid box k: 10 + k.
struct Hit {
  double t = std::numeric_limits<double>::infinity();
  int surface = -1;
};

struct AlignedBox {
  Eigen::Vector3d min, max;
};

struct Scene {
  bool has_room = false;
  AlignedBox room;                      // seen from inside
  std::vector<AlignedBox> solids;       // seen from outside
  std::vector<Eigen::Vector4d> planes;  // infinite planes n.x + d = 0, surface 20 + k

  Hit Cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) const {
    Hit best;
    auto consider = [&](double t, int surface) {
      if (t > 1e-9 && t < best.t) best = Hit{t, surface};
    };
    if (has_room) {
      for (int a = 0; a < 3; ++a) {
        if (dir[a] < 0) consider((room.min[a] - origin[a]) / dir[a], 2 * a);
        if (dir[a] > 0) consider((room.max[a] - origin[a]) / dir[a], 2 * a + 1);
      }
    }
    for (std::size_t k = 0; k < solids.size(); ++k) {
      double t_near = -std::numeric_limits<double>::infinity();
      double t_far = std::numeric_limits<double>::infinity();
      for (int a = 0; a < 3; ++a) {
        const double t1 = (solids[k].min[a] - origin[a]) / dir[a];
        const double t2 = (solids[k].max[a] - origin[a]) / dir[a];
        t_near = std::max(t_near, std::min(t1, t2));
        t_far = std::min(t_far, std::max(t1, t2));
      }
      if (t_near <= t_far) consider(t_near, 10 + static_cast<int>(k));
    }
    for (std::size_t k = 0; k < planes.size(); ++k) {
      const double denom = planes[k].head<3>().dot(dir);
      if (std::abs(denom) > 1e-12) {
        consider(-(planes[k].head<3>().dot(origin) + planes[k].w()) / denom,
                 20 + static_cast<int>(k));
      }
    }
    return best;
  }
};

struct SyntheticLidar {
  int rings = 64;
  int cols = 1024;
  double top_deg = 22.5;
  double bottom_deg = -22.5;

  double ElevationDeg(int ring) const {
    return top_deg + (bottom_deg - top_deg) * ring / (rings - 1);
  }
  // Centre of column c in the RangeImage convention: column 0 starts at azimuth -pi.
  double Azimuth(int col) const {
    return -std::numbers::pi + (col + 0.5) * 2 * std::numbers::pi / cols;
  }
  Eigen::Vector3d Direction(int ring, int col) const {
    const double el = ElevationDeg(ring) * std::numbers::pi / 180.0;
    const double az = Azimuth(col);
    return {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
  }
  SensorModel Model() const {
    SensorModel m;
    m.rings = rings;
    m.columns = cols;
    m.min_range = 0.3;
    m.max_range = 200.0;
    return m;
  }
};

// A scan in firing order (column by column), sensor frame, with rings; `surfaces` gets the
// surface id of every point.
inline Scan CastScan(const SyntheticLidar& lidar, const Scene& scene,
                     const Eigen::Isometry3d& T_world_sensor, std::vector<int>* surfaces,
                     double max_range = 150.0) {
  Scan scan;
  for (int c = 0; c < lidar.cols; ++c) {
    for (int r = 0; r < lidar.rings; ++r) {
      const Eigen::Vector3d dir = lidar.Direction(r, c);
      const Hit hit = scene.Cast(T_world_sensor.translation(), T_world_sensor.linear() * dir);
      if (hit.surface < 0 || hit.t > max_range) continue;
      scan.points.push_back(hit.t * dir);
      scan.rings.push_back(static_cast<std::int16_t>(r));
      scan.intensities.push_back(static_cast<float>(hit.surface));
      if (surfaces) surfaces->push_back(hit.surface);
    }
  }
  return scan;
}

}  // namespace dammloam::test
