#pragma once
#include <Eigen/Geometry>
#include <cstdint>
#include <string>

#include "core/geometry/se3.hpp"

namespace dammloam::backend {

// One loop candidate and what verification decided about it (accepted or not, and why).
struct LoopEvent {
  std::uint32_t query_keyframe = 0;      // the newer keyframe
  std::uint32_t candidate_keyframe = 0;  // the older keyframe it may revisit
  std::uint64_t query_scan_index = 0;
  std::uint64_t candidate_scan_index = 0;
  double query_stamp = 0.0;
  double candidate_stamp = 0.0;
  Eigen::Isometry3d T_candidate_query = Eigen::Isometry3d::Identity();  // registered
  double scan_context_distance = 1.0;    // 0 = identical descriptors
  double yaw_guess_rad = 0.0;            // from the column shift
  double inlier_ratio = 0.0;             // registration overlap
  double rmse = 0.0;                     // registration residual, metres
  double translation_observability = 0.0;  // see IcpResult; ~0 in a featureless corridor
  double odometry_disagreement = 0.0;    // metres between registered and odometry relative pose
  // Translation directions the registration fixes (0..3): 2 in a featureless corridor, whose
  // axis the loop leaves to odometry.
  int observed_translation_directions = 0;
  // Uncertainty of T_candidate_query in the pose graph's edge tangent (translation in the
  // candidate frame, then rotation): large along the directions the scene leaves free.
  Matrix6d covariance = Matrix6d::Identity();
  // Squared Mahalanobis distance of the registered relative pose from odometry's under both
  // uncertainties (the loop's and the odometry chain's between the keyframes), and the bound
  // above which the loop is refused as inconsistent (BackendConfig::odometry_consistency_chi2).
  // 0 for candidates the registration already refused.
  double odometry_chi2 = 0.0;
  double odometry_chi2_bound = 0.0;
  bool accepted = false;
  std::string reason;                    // "accepted" or why it was rejected
  // Accepted loops only. Squared whitened residual of the loop's edge at the corrected poses
  // when it was added, and the bound above which it starts a pose-graph solve
  // (BackendConfig::loop_optimize_residual squared).
  double map_chi2 = 0.0;
  double map_chi2_bound = 0.0;
  bool started_optimization = false;
  // How far the solve this loop started moved its query keyframe (0 when it started none).
  double correction_m = 0.0;
  double correction_rad = 0.0;
  // The solve this loop started (0 when it started none): its wall time and the graph's size,
  // so that a long run shows whether solving stays bounded as the graph grows.
  double solve_ms = 0.0;
  std::uint32_t graph_nodes = 0;
};

}  // namespace dammloam::backend
