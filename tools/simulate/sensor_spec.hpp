#pragma once
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/geometry/scan.hpp"

namespace dammloam::sim {

// A simulated spinning LiDAR: one beam per ring, all rings of a column fire together, the head
// turns clockwise seen from above starting behind the sensor (column 0 looks along -x).
struct SensorSpec {
  std::string name = "os1-64";
  int columns = 1024;
  double scan_period = 0.1;                 // seconds per revolution
  std::vector<double> vertical_angles_deg;  // ring 0 = top beam, strictly decreasing
  double min_range = 0.3;
  double max_range = 120.0;

  int rings() const { return static_cast<int>(vertical_angles_deg.size()); }
};

// Ouster OS1-64-like: 64 rings uniform over +-22.5 deg, 1024 columns, 10 Hz, 0.3-120 m.
SensorSpec Os1_64();
// Velodyne VLP-16-like: 16 rings -15..+15 deg every 2 deg, 1800 columns at 10 Hz, 0.4-100 m.
SensorSpec Vlp16();
// "os1-64" or "vlp-16"; nullopt for any other name.
std::optional<SensorSpec> MakeSensorSpec(std::string_view name);
std::vector<std::string> SensorNames();

// `rings` elevations spread uniformly from up_deg (ring 0) down to down_deg (last ring).
std::vector<double> UniformVerticalAngles(int rings, double up_deg, double down_deg);

// Empty when the spec is usable, otherwise what is wrong with it.
std::string Validate(const SensorSpec& spec);

SensorModel ToSensorModel(const SensorSpec& spec);

// Azimuth (rad, counter-clockwise from +x) of a column; see SensorSpec for the convention.
double ColumnAzimuth(const SensorSpec& spec, int column);

}  // namespace dammloam::sim
