#pragma once
// The back-end's YAML: deploy/config/backend.yaml (dammloam-odometry --backend-config) and the
// `backend` section of dammloamd's file. Same rules as the odometry's (config_yaml.hpp).
#include <filesystem>
#include <string>

#include "core/backend/backend_config.hpp"
#include "io/config_yaml.hpp"

namespace YAML {
class Node;
}

namespace dammloam::io {

// Keys mirror backend::BackendParameters (loop_closing.scan_context.max_range,
// localizer.track_icp.max_iterations, ...); absent keys keep their defaults, unknown keys, wrong
// types and out-of-range values are ConfigErrors naming the key. `section` prefixes every key
// named in an error ("backend" in dammloamd's file, empty in a file of its own).
backend::BackendParameters ParseBackendConfig(const YAML::Node& root,
                                              const std::string& section = "");
backend::BackendParameters LoadBackendConfig(const std::filesystem::path& file);

// Throws ConfigError naming the first out-of-range field (prefixed by `section`).
void ValidateBackendConfig(const backend::BackendParameters& config,
                           const std::string& section = "");

}  // namespace dammloam::io
