#include "tools/simulate/sensor_spec.hpp"

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>

namespace dammloam::sim {

namespace {

// The OS1's 45 deg vertical field, its rings spread uniformly.
SensorSpec Os1(std::string name, int rings, int columns) {
  SensorSpec spec;
  spec.name = std::move(name);
  spec.columns = columns;
  spec.vertical_angles_deg = UniformVerticalAngles(rings, 22.5, -22.5);
  spec.min_range = 0.3;
  spec.max_range = 120.0;
  return spec;
}

}  // namespace

SensorSpec Os1_64() { return Os1("os1-64", 64, 1024); }

SensorSpec Vlp16() {
  SensorSpec spec;
  spec.name = "vlp-16";
  spec.columns = 1800;
  spec.vertical_angles_deg = UniformVerticalAngles(16, 15.0, -15.0);
  spec.min_range = 0.4;
  spec.max_range = 100.0;
  return spec;
}

SensorSpec Os1_128(int columns) {
  return Os1(columns == 1024 ? "os1-128" : "os1-128x" + std::to_string(columns), 128, columns);
}

SensorSpec Vls128() {
  SensorSpec spec;
  spec.name = "vls-128";
  spec.columns = 1800;
  // Velodyne packs its finest spacing around the horizon, where a car's distant targets are;
  // the band's edges and the coarse spacing above and below are an approximation of that shape.
  const double band_top = 2.0, band_step = 0.11;
  const int band_rings = 56, upper_rings = 28, lower_rings = 44;
  const double band_bottom = band_top - (band_rings - 1) * band_step;
  const double upper_step = (15.0 - band_top) / upper_rings;
  const double lower_step = (band_bottom - (-25.0)) / lower_rings;
  for (int r = 0; r < upper_rings; ++r) spec.vertical_angles_deg.push_back(15.0 - r * upper_step);
  for (int r = 0; r < band_rings; ++r) spec.vertical_angles_deg.push_back(band_top - r * band_step);
  for (int r = 1; r <= lower_rings; ++r) {
    spec.vertical_angles_deg.push_back(band_bottom - r * lower_step);
  }
  spec.min_range = 0.5;
  spec.max_range = 200.0;
  return spec;
}

std::optional<SensorSpec> MakeSensorSpec(std::string_view name) {
  if (name == "os1-64") return Os1_64();
  if (name == "vlp-16") return Vlp16();
  if (name == "os1-128") return Os1_128(1024);
  if (name == "os1-128x2048") return Os1_128(2048);
  if (name == "vls-128") return Vls128();
  return std::nullopt;
}

std::vector<std::string> SensorNames() {
  return {"os1-64", "vlp-16", "os1-128", "os1-128x2048", "vls-128"};
}

std::vector<double> UniformVerticalAngles(int rings, double up_deg, double down_deg) {
  if (rings <= 0) return {};
  if (rings == 1) return {up_deg};
  std::vector<double> angles(static_cast<std::size_t>(rings));
  const double step = (up_deg - down_deg) / (rings - 1);
  for (int r = 0; r < rings; ++r) angles[static_cast<std::size_t>(r)] = up_deg - r * step;
  return angles;
}

std::string Validate(const SensorSpec& spec) {
  std::ostringstream why;
  if (spec.rings() < 1 || spec.rings() > 256) {
    why << "rings must be in [1, 256], got " << spec.rings();
  } else if (spec.columns < 1 || spec.columns > 16384) {
    why << "columns must be in [1, 16384], got " << spec.columns;
  } else if (!(spec.scan_period > 0.0)) {
    why << "scan period must be positive, got " << spec.scan_period;
  } else if (!(spec.min_range >= 0.0 && spec.max_range > spec.min_range)) {
    why << "range limits must satisfy 0 <= min < max, got " << spec.min_range << ".."
        << spec.max_range;
  } else {
    for (std::size_t r = 0; r < spec.vertical_angles_deg.size(); ++r) {
      const double a = spec.vertical_angles_deg[r];
      if (!(std::abs(a) < 90.0)) {
        why << "vertical angle of ring " << r << " must be within (-90, 90) deg, got " << a;
        break;
      }
      if (r > 0 && !(a < spec.vertical_angles_deg[r - 1])) {
        why << "vertical angles must decrease from ring 0 (top) down; ring " << r << " has " << a
            << " after " << spec.vertical_angles_deg[r - 1];
        break;
      }
    }
  }
  return why.str();
}

SensorModel ToSensorModel(const SensorSpec& spec) {
  SensorModel model;
  model.rings = spec.rings();
  model.columns = spec.columns;
  model.scan_period = spec.scan_period;
  model.vertical_angles_deg = spec.vertical_angles_deg;
  model.min_range = spec.min_range;
  model.max_range = spec.max_range;
  return model;
}

double ColumnAzimuth(const SensorSpec& spec, int column) {
  return std::numbers::pi - 2.0 * std::numbers::pi * column / spec.columns;
}

}  // namespace dammloam::sim
