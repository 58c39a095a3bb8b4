#pragma once
#include <Eigen/Geometry>
#include <optional>

namespace dammloam::backend {

struct KeyframeSelectorConfig {
  double min_distance = 1.0;             // metres travelled since the last keyframe
  double min_rotation_rad = 0.26;        // ~15 degrees turned since the last keyframe

  bool operator==(const KeyframeSelectorConfig&) const = default;
};

// Decides whether a new scan becomes a keyframe: the first scan always does, later ones when
// the sensor moved or turned enough since the last keyframe (so a standing robot adds nothing).
class KeyframeSelector {
 public:
  explicit KeyframeSelector(const KeyframeSelectorConfig& config = {}) : config_(config) {}

  // Returns true (and remembers the pose) when T_world_sensor should become a keyframe.
  bool Consider(const Eigen::Isometry3d& T_world_sensor);
  void Reset() { last_keyframe_.reset(); }

 private:
  KeyframeSelectorConfig config_;
  std::optional<Eigen::Isometry3d> last_keyframe_;
};

}  // namespace dammloam::backend
