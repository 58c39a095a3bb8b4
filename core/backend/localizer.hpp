#pragma once
#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <vector>

#include "core/backend/keyframe.hpp"
#include "core/backend/point_to_plane_icp.hpp"
#include "core/backend/scan_context_database.hpp"

namespace dammloam::backend {

struct LocalizerConfig {
  int num_candidates = 10;          // ring-key neighbours re-ranked by Scan Context distance
  int max_registrations = 5;        // best-ranked candidates verified by ICP in Relocalize
  double max_scan_context_distance = 0.45;
  double scan_voxel_size = 0.5;     // query scans are downsampled to this before ICP
  int normal_neighbours = 10;
  IcpConfig relocalize_icp{40, 3.0, 0.6, 0.3, 1e-4};
  IcpConfig track_icp{20, 1.0, 0.5, 0.3, 1e-4};
  // Relocalization has no prior, so it demands a near-complete, tight overlap: a look-alike
  // place registers with ~50% overlap and ~0.1 m residual in the simulated outdoor scene.
  double relocalize_min_inlier_ratio = 0.75;
  double relocalize_max_rmse = 0.08;  // metres
  double track_min_inlier_ratio = 0.5;
  double track_max_rmse = 0.15;       // metres

  bool operator==(const LocalizerConfig&) const = default;
};

struct LocalizationResult {
  Eigen::Isometry3d T_map_sensor = Eigen::Isometry3d::Identity();
  double inlier_ratio = 0.0;
  double rmse = 0.0;
  std::uint32_t keyframe = 0;            // Relocalize: the keyframe whose place matched
  double scan_context_distance = 0.0;    // Relocalize only
};

// Localization in a saved map: Relocalize() finds the pose of a scan from an unknown place
// (Scan Context retrieval + ICP against the global map), Track() follows the sensor from a
// predicted pose. The map is never modified. Not thread-safe; one instance per thread.
class Localizer {
 public:
  explicit Localizer(const MapData& map, const LocalizerConfig& config = {});

  // points: one scan in the sensor frame (deskewed if possible).
  std::optional<LocalizationResult> Relocalize(const std::vector<Eigen::Vector3d>& points) const;
  std::optional<LocalizationResult> Track(const std::vector<Eigen::Vector3d>& points,
                                          const Eigen::Isometry3d& T_map_sensor_predicted) const;

  // Stateful convenience for localization mode: relocalize until found, then track with a
  // constant-velocity prediction; relocalizes again after tracking is lost.
  std::optional<LocalizationResult> Localize(const std::vector<Eigen::Vector3d>& points);
  void Reset() { last_.reset(); velocity_ = Eigen::Isometry3d::Identity(); }

  std::size_t NumMapPoints() const { return target_.size(); }

 private:

  LocalizerConfig config_;
  ScanContextConfig scan_context_;
  std::vector<Eigen::Isometry3d> keyframe_poses_;
  ScanContextDatabase database_;
  IcpTarget target_;
  std::optional<Eigen::Isometry3d> last_;
  Eigen::Isometry3d velocity_ = Eigen::Isometry3d::Identity();
};

}  // namespace dammloam::backend
