#pragma once
// Every tunable of the back-end in one place: loop closing while mapping, localization in a saved
// map. Plain structs with defaults (no files here); the `backend` YAML section mirrors them key
// for key (io/backend_config_yaml.hpp, documented in deploy/config/backend.yaml).
#include "core/backend/localizer.hpp"
#include "core/backend/loop_closing_backend.hpp"

namespace dammloam::backend {

struct BackendParameters {
  BackendConfig loop_closing;  // keyframes, Scan Context, loop verification, pose graph
  // Relocalization and tracking in a saved map. The Scan Context parameters come with the map
  // (descriptors are only comparable under the ones they were made with).
  LocalizerConfig localizer;

  bool operator==(const BackendParameters&) const = default;
};

}  // namespace dammloam::backend
