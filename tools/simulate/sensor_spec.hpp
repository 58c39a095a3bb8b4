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
// Ouster OS1-128-like: 128 rings uniform over +-22.5 deg, `columns` (512, 1024 or 2048) at 10 Hz,
// 0.3-120 m; named "os1-128" at 1024 columns, else "os1-128x<columns>".
SensorSpec Os1_128(int columns);
// Velodyne VLS-128-like (Alpha Prime): 128 rings over +15..-25 deg, 56 of them 0.11 deg apart
// from +2 deg down, the rest about 0.47 deg apart; 1800 columns at 10 Hz, 0.5-200 m.
SensorSpec Vls128();
// A name of SensorNames(); nullopt for any other name.
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
