#pragma once
#include <filesystem>
#include <stdexcept>
#include <string>

#include "core/odometry/odometry_config.hpp"

namespace YAML {
class Node;
}

namespace dammloam::io {

// A configuration problem; what() names the file (when known) and the key, e.g.
// "odometry.yaml: registration.mode: unknown value 'icp' (expected full, ...)".
class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Keys mirror the structs (preprocess.normals.min_incidence_deg, map.voxel_size, ...); absent
// keys keep their defaults, unknown keys and wrong types are errors naming the key. Both also
// run ValidateOdometryConfig.
OdometryConfig ParseOdometryConfig(const YAML::Node& root);
OdometryConfig LoadOdometryConfig(const std::filesystem::path& file);

// Throws ConfigError naming the first out-of-range field.
void ValidateOdometryConfig(const OdometryConfig& config);

}  // namespace dammloam::io
