#include "drivers/velodyne/calibration.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <numeric>
#include <sstream>

#include "drivers/diagnostics.hpp"

namespace dammloam::drivers::velodyne {

std::optional<Model> ParseModel(std::string_view n) {
  if (n == "vlp16") return Model::kVLP16;
  if (n == "vlp32c") return Model::kVLP32C;
  if (n == "hdl32e") return Model::kHDL32E;
  if (n == "vls128") return Model::kVLS128;
  return std::nullopt;
}

std::string_view Name(Model m) {
  switch (m) {
    case Model::kVLP16: return "vlp16";
    case Model::kVLP32C: return "vlp32c";
    case Model::kHDL32E: return "hdl32e";
    case Model::kVLS128: return "vls128";
  }
  return "?";
}

int LaserCount(Model m) {
  switch (m) {
    case Model::kVLP16: return 16;
    case Model::kVLP32C:
    case Model::kHDL32E: return 32;
    case Model::kVLS128: return 128;
  }
  return 0;
}

Calibration ParseCalibration(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw DriverError(source + ": not valid YAML: " + e.what());
  }
  if (!root.IsMap() || !root["lasers"] || !root["lasers"].IsSequence()) {
    throw DriverError(source + ": needs a 'lasers' list");
  }
  Calibration cal;
  cal.source = source;
  const YAML::Node lasers = root["lasers"];
  cal.lasers.resize(lasers.size());
  std::vector<bool> seen(lasers.size(), false);
  for (std::size_t i = 0; i < lasers.size(); ++i) {
    const YAML::Node l = lasers[i];
    const std::string where = source + ": lasers[" + std::to_string(i) + "]";
    // l[key] on a scalar or list throws YAML::BadSubscript, not a DriverError.
    if (!l.IsMap()) throw DriverError(where + " must be a mapping of laser fields");
    auto number = [&](const char* key, bool required) {
      if (!l[key]) {
        if (required) throw DriverError(where + " has no '" + key + "'");
        return 0.0;
      }
      double v = 0.0;
      try {
        v = l[key].as<double>();
      } catch (const YAML::Exception&) {
        throw DriverError(where + " field '" + key + "' is not a number");
      }
      // .nan/.inf parse as doubles; a NaN laser_id would also pass the range check below.
      if (!std::isfinite(v)) throw DriverError(where + " field '" + key + "' is not finite");
      return v;
    };
    const double id = number("laser_id", true);
    if (id < 0 || id >= static_cast<double>(lasers.size()) || id != static_cast<int>(id)) {
      throw DriverError(where + " has laser_id " + std::to_string(id) + " outside 0.." +
                        std::to_string(lasers.size() - 1));
    }
    const auto k = static_cast<std::size_t>(id);
    if (seen[k]) throw DriverError(where + " repeats laser_id " + std::to_string(k));
    seen[k] = true;
    Laser& laser = cal.lasers[k];
    laser.id = static_cast<int>(k);
    laser.rot_correction = number("rot_correction", false);
    laser.vert_correction = number("vert_correction", true);
    laser.dist_correction = number("dist_correction", false);
    laser.horiz_offset_correction = number("horiz_offset_correction", false);
    laser.vert_offset_correction = number("vert_offset_correction", false);
  }
  if (root["num_lasers"] && root["num_lasers"].as<std::size_t>(0) != lasers.size()) {
    // as<std::string>() throws for a list or mapping: name it without converting.
    const YAML::Node n = root["num_lasers"];
    throw DriverError(source + ": num_lasers says " + (n.IsScalar() ? n.Scalar() : "a non-number") +
                      " but " + std::to_string(lasers.size()) + " lasers are listed");
  }
  if (root["distance_resolution"]) {
    try {
      cal.distance_resolution = root["distance_resolution"].as<double>();
    } catch (const YAML::Exception&) {
      throw DriverError(source + ": distance_resolution is not a number");
    }
    if (!(cal.distance_resolution > 0.0 && cal.distance_resolution <= 0.1)) {  // NaN too
      throw DriverError(source + ": distance_resolution must be in (0, 0.1] metres");
    }
  }
  // Ring 0 is the top beam: rank lasers by elevation, highest first.
  std::vector<std::size_t> order(cal.lasers.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return cal.lasers[a].vert_correction > cal.lasers[b].vert_correction;
  });
  for (std::size_t r = 0; r < order.size(); ++r) cal.lasers[order[r]].ring = static_cast<int>(r);
  return cal;
}

Calibration LoadCalibration(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw DriverError("cannot open Velodyne calibration " + file.string());
  std::stringstream ss;
  ss << in.rdbuf();
  return ParseCalibration(ss.str(), file.string());
}

}  // namespace dammloam::drivers::velodyne
