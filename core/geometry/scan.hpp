#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace dammloam {

// What the algorithm needs to know about a spinning LiDAR. Filled from meta.json, a driver's
// metadata or the daemon's config; the core never reads files itself.
struct SensorModel {
  int rings = 64;
  int columns = 1024;
  double scan_period = 0.1;                 // seconds per revolution
  std::vector<double> vertical_angles_deg;  // ring 0 = top beam; empty = unknown (use bins)
  double min_range = 0.3;
  double max_range = 100.0;
};

// One revolution of a spinning LiDAR in the sensor frame (x forward, y left, z up), each point
// measured at its own firing time. Struct of arrays: all vectors have points.size() entries
// (times/rings/intensities may be empty when the source has no such field).
struct Scan {
  double t_start = 0.0;                    // seconds, the scan's start time (times.txt)
  std::vector<Eigen::Vector3d> points;     // metres, sensor frame at the point's firing time
  std::vector<float> intensities;          // any non-negative scale
  std::vector<float> times;                // seconds since t_start, in [0, scan_period)
  std::vector<std::int16_t> rings;         // beam index, 0 = top beam

  std::size_t size() const { return points.size(); }
  bool empty() const { return points.empty(); }
  bool has_times() const { return times.size() == points.size() && !points.empty(); }
  bool has_rings() const { return rings.size() == points.size() && !points.empty(); }
};

}  // namespace dammloam
