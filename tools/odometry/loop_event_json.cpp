#include "tools/odometry/loop_event_json.hpp"

#include <nlohmann/json.hpp>

namespace dammloam::tools {

std::string LoopEventJsonLine(const backend::LoopEvent& event) {
  const Eigen::Vector3d t = event.T_candidate_query.translation();
  const Eigen::Quaterniond q(event.T_candidate_query.rotation());
  const nlohmann::json json = {
      {"query_keyframe", event.query_keyframe},
      {"candidate_keyframe", event.candidate_keyframe},
      {"query_scan_index", event.query_scan_index},
      {"candidate_scan_index", event.candidate_scan_index},
      {"query_stamp", event.query_stamp},
      {"candidate_stamp", event.candidate_stamp},
      {"scan_context_distance", event.scan_context_distance},
      {"yaw_guess_rad", event.yaw_guess_rad},
      {"inlier_ratio", event.inlier_ratio},
      {"rmse", event.rmse},
      {"translation_observability", event.translation_observability},
      {"odometry_disagreement", event.odometry_disagreement},
      {"observed_translation_directions", event.observed_translation_directions},
      {"T_candidate_query", {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}},
      {"accepted", event.accepted},
      {"reason", event.reason},
      {"odometry_chi2", event.odometry_chi2},
      {"odometry_chi2_bound", event.odometry_chi2_bound},
      {"map_chi2", event.map_chi2},
      {"map_chi2_bound", event.map_chi2_bound},
      {"started_optimization", event.started_optimization},
      {"correction_m", event.correction_m},
      {"correction_rad", event.correction_rad},
      {"solve_ms", event.solve_ms},
      {"graph_nodes", event.graph_nodes},
  };
  return json.dump();
}

}  // namespace dammloam::tools
