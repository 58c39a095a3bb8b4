#pragma once
#include <Eigen/Geometry>
#include <cstdint>
#include <mutex>
#include <optional>
#include <vector>

#include "core/backend/keyframe.hpp"
#include "core/backend/keyframe_selector.hpp"
#include "core/backend/loop_event.hpp"
#include "core/backend/loop_verifier.hpp"
#include "core/backend/pose_graph.hpp"
#include "core/backend/scan_context.hpp"
#include "core/backend/scan_context_database.hpp"
#include "core/backend/vacated_points.hpp"
#include "core/geometry/scan.hpp"
#include "core/odometry/odometry_result.hpp"

namespace dammloam::backend {

struct BackendConfig {
  KeyframeSelectorConfig keyframes;
  ScanContextConfig scan_context;
  ScanContextDatabaseConfig database;
  LoopVerifierConfig verifier;
  PoseGraphConfig pose_graph;
  double keyframe_voxel_size = 0.4;     // keyframe clouds are stored at this resolution
  double global_map_voxel_size = 0.3;
  // The global map leaves out what later keyframes saw through (people, cars that left). Needs
  // the sensor's model (SetSensor).
  VacatedPointsConfig vacated;
  int max_verifications_per_keyframe = 2;
  // The nearest keyframe within this distance in the corrected map is verified first.
  double proximity_radius = 3.0;        // metres
  // A new keyframe whose verified loop puts it this close to an older keyframe (one with a cloud,
  // in the corrected map around the loop's partner) adds nothing the map lacks: it keeps its
  // pose (graph node, scan corrections) and drops its cloud and descriptor. So memory grows
  // with the area mapped, not with the time spent in it. 0: keep all.
  double revisit_drop_distance = 2.0;   // metres
  // Only an accepted loop whose edge disagrees with the corrected map by more than this
  // (whitened residual norm, with the sigmas below) joins the pose graph and starts a solve. A
  // loop that agrees this well has nothing to correct, and many of them solved together carry
  // their registrations' common bias into a good trajectory (hand-held corridor VLP-16: 72
  // agreeing loops solved at the end moved APE +6.5 %). It is still reported, and kept among
  // the saved map's loops. Going round mapped ground thus costs no solves and no edges, which
  // grow with the graph. 0: every accepted loop joins the graph and starts a solve.
  double loop_optimize_residual = 1.0;
  // A loop whose registered relative position lies further than this (squared Mahalanobis
  // distance, 3 degrees of freedom) from the corrected map's, under the loop's covariance plus
  // the odometry chain's between its keyframes, is refused: a look-alike place (the floor
  // below, the next aisle) that no drift odometry can have explains. 0: no such test.
  double odometry_consistency_chi2 = 16.3;  // chi-square, 3 dof, 99.9 %
  // Odometry edges' covariances (with the pose graph's floors) are multiplied by this in that
  // test: the registration's covariance ignores correlated errors, and drift outgrows it.
  double odometry_covariance_scale = 1.0;
  // One sigma of a heading-rate bias of the odometry in that test (radians per metre, about the
  // vertical): the part of heading drift that the scans' own covariances, summed as independent,
  // leave out (1e-4: 0.57 deg per 100 m; a 1.5 km vehicle route drifted 0.38 deg per 100 m).
  double odometry_heading_drift = 1e-4;
  // Added to every loop edge's registration covariance: what ICP's own does not model.
  double loop_translation_sigma = 0.05; // metres
  double loop_rotation_sigma = 0.01;    // radians

  bool operator==(const BackendConfig&) const = default;
};

// The back-end facade used by dammloam-odometry and dammloamd.
//
// Threading: AddScan() is cheap and meant for the odometry thread; Process() does all heavy
// work (descriptors, retrieval, verification, Ceres) and is meant for ONE back-end thread owned
// by the caller. They share only a mutex-protected inbox and the table of pose corrections, each
// locked briefly, so the odometry thread never waits for an optimisation. CorrectedPoseOf() may be
// called from any thread. ExportMap()/NumKeyframes() wait for a
// running Process() to finish.
class LoopClosingBackend {
 public:
  explicit LoopClosingBackend(const BackendConfig& config = {});

  // The sensor the keyframes come from: the exported global map is cleaned of vacated points
  // (BackendConfig::vacated) only once it is known.
  void SetSensor(const SensorModel& sensor);

  // Records the scan's odometry pose; copies its cloud when it becomes a keyframe.
  void AddScan(const OdometryResult& result);
  // Integrates queued keyframes, detects and verifies loops, optimises when an accepted loop
  // disagrees with the map (loop_optimize_residual).
  // Returns every loop candidate examined (accepted or rejected); an accepted loop's reason
  // says whether it agreed with the map or started a solve, and how far that moved its query.
  std::vector<LoopEvent> Process();

  // The odometry pose of a scan corrected by the latest optimisation (the correction of the
  // keyframe at or before it); nullopt outside the scans added so far. The caller keeps its
  // odometry poses: the back-end keeps nothing per scan, so a daemon's memory does not grow
  // with its uptime.
  std::optional<Eigen::Isometry3d> CorrectedPoseOf(
      std::uint64_t scan_index, const Eigen::Isometry3d& T_world_sensor_odom) const;

  // map -> odom for the newest scans: the correction of the newest keyframe the last
  // optimisation placed (identity before any), T_map_sensor = MapFromOdom() * T_odom_sensor. What
  // REP 105's map -> odom transform carries when loops correct the map.
  Eigen::Isometry3d MapFromOdom() const;

  std::size_t NumKeyframes() const;
  // Keyframes that still hold a cloud (the others were revisits, see revisit_drop_distance).
  std::size_t NumStoredKeyframes() const;
  std::size_t NumAcceptedLoops() const;
  // Pose graph optimisations run so far (see loop_optimize_residual).
  std::size_t NumOptimizations() const;
  // Keyframes that hold a cloud (renumbered densely), the loops between them and the global
  // labelled map, for saving or localization.
  MapData ExportMap() const;

 private:
  struct PendingKeyframe {
    Keyframe keyframe;       // cloud not yet downsampled, no descriptor
    double path_length;      // odometry distance from the first scan
  };

  void IntegrateKeyframe(PendingKeyframe pending);
  // Keyframes with a cloud and the loops between them, without the global map; under
  // process_mutex_.
  MapData ExportGraph() const;
  // `disagrees`: set when an accepted loop disagrees with the map (loop_optimize_residual).
  std::vector<LoopEvent> DetectLoops(std::uint32_t query_id, bool& disagrees);
  // Refuses (with the reason) an accepted loop too far from odometry's relative pose for both
  // uncertainties (odometry_consistency_chi2); fills its odometry_chi2 either way.
  bool ConsistentWithOdometry(LoopEvent& event, const Matrix6d& loop_covariance) const;
  // Judges an accepted loop just added to the graph against the corrected map; true when it
  // should start a solve.
  bool DisagreesWithMap(LoopEvent& event) const;
  // Tells the loops in `events` that started this solve how far it moved their query keyframe
  // and what the solve cost.
  void ReportCorrections(std::vector<LoopEvent>& events,
                         const std::vector<Eigen::Isometry3d>& before,
                         const PoseGraphSummary& solve) const;
  // Oldest-excluded nearest keyframe within proximity_radius of the query, if any.
  std::optional<ScanContextCandidate> NearestOldKeyframe(std::uint32_t query_id) const;
  // Publishes the corrections of keyframes `first` onwards.
  void PublishCorrections(std::size_t first);
  PoseGraphSummary Optimize();
  // Corrected-map distance from `position` to the nearest older keyframe that holds a cloud.
  double DistanceToStoredKeyframe(const Eigen::Vector3d& position, std::uint32_t query_id) const;
  void DropCloud(std::uint32_t id);
  bool HasCloud(std::uint32_t id) const { return !dropped_[id]; }

  BackendConfig config_;
  std::optional<SensorModel> sensor_;  // guarded by process_mutex_
  LoopVerifier verifier_;

  // Shared between AddScan (odometry thread), Process and the pose getters.
  mutable std::mutex shared_mutex_;
  KeyframeSelector selector_;
  std::vector<PendingKeyframe> inbox_;
  std::optional<std::uint64_t> first_scan_, last_scan_;
  Eigen::Vector3d last_position_ = Eigen::Vector3d::Zero();
  std::vector<std::uint64_t> keyframe_scans_;   // per keyframe: its scan index, ascending
  std::vector<Eigen::Isometry3d> corrections_;  // per keyframe: T_corrected * T_odom^-1
  std::uint32_t next_keyframe_id_ = 0;
  double path_length_ = 0.0;
  // Front-end covariances of the scans since the last keyframe, in its frame (the edge's).
  Matrix6d covariance_since_keyframe_ = Matrix6d::Zero();
  Eigen::Isometry3d last_keyframe_odom_ = Eigen::Isometry3d::Identity();

  // Owned by the Process() thread.
  mutable std::mutex process_mutex_;
  std::vector<Keyframe> keyframes_;
  std::vector<double> keyframe_path_;
  std::vector<char> dropped_;  // per keyframe: cloud and descriptor dropped (a revisit)
  std::vector<std::uint32_t> stored_;  // keyframes with a cloud, ascending
  std::vector<LoopConstraint> loops_;
  ScanContextDatabase database_;
  PoseGraph graph_;
  std::size_t optimizations_ = 0;
};

}  // namespace dammloam::backend
