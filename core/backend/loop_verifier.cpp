#include "core/backend/loop_verifier.hpp"

#include <cstdio>

namespace dammloam::backend {

namespace {

std::string Format(const char* fmt, double a, double b) {
  char buffer[128];
  std::snprintf(buffer, sizeof(buffer), fmt, a, b);
  return buffer;
}

}  // namespace

LoopEvent LoopVerifier::Verify(const Keyframe& query, const Keyframe& candidate,
                               const ScanContextMatch& match, double path_length) const {
  LoopEvent event;
  event.query_keyframe = query.id;
  event.candidate_keyframe = candidate.id;
  event.query_scan_index = query.scan_index;
  event.candidate_scan_index = candidate.scan_index;
  event.query_stamp = query.stamp;
  event.candidate_stamp = candidate.stamp;
  event.scan_context_distance = match.distance;
  event.yaw_guess_rad = match.yaw_rad;
  if (query.points.empty() || candidate.points.size() < 10) {
    event.reason = "empty keyframe cloud";
    return event;
  }

  // Two starting guesses: Scan Context's yaw at zero offset (same place), and odometry's
  // relative pose (right when drift is small). Keep whichever registers better.
  const Eigen::Isometry3d T_odom =
      candidate.T_world_sensor_odom.inverse() * query.T_world_sensor_odom;
  Eigen::Isometry3d T_yaw = Eigen::Isometry3d::Identity();
  T_yaw.linear() = Eigen::AngleAxisd(match.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const IcpTarget target(candidate.points, config_.normal_neighbours);
  IcpResult best = AlignPointToPlane(query.points, target, T_yaw, config_.icp);
  const IcpResult from_odom = AlignPointToPlane(query.points, target, T_odom, config_.icp);
  if (from_odom.inlier_ratio > best.inlier_ratio) best = from_odom;

  event.T_candidate_query = best.T_target_source;
  event.inlier_ratio = best.inlier_ratio;
  event.rmse = best.rmse;
  event.translation_observability = best.translation_observability;
  event.odometry_disagreement =
      (best.T_target_source.translation() - T_odom.translation()).norm();
  const double drift_budget = config_.drift_offset + config_.drift_per_metre * path_length;

  if (best.inlier_ratio < config_.min_inlier_ratio) {
    event.reason = Format("inlier ratio %.2f below %.2f", best.inlier_ratio,
                          config_.min_inlier_ratio);
  } else if (best.rmse > config_.max_rmse) {
    event.reason = Format("residual %.3f m above %.3f m", best.rmse, config_.max_rmse);
  } else if (best.translation_observability < config_.min_translation_observability) {
    event.reason = Format("degenerate geometry: translation observability %.4f below %.4f",
                          best.translation_observability,
                          config_.min_translation_observability);
  } else if (event.odometry_disagreement > drift_budget) {
    event.reason = Format("disagrees with odometry by %.2f m (drift budget %.2f m)",
                          event.odometry_disagreement, drift_budget);
  } else {
    event.accepted = true;
    event.reason = "accepted";
  }
  return event;
}

}  // namespace dammloam::backend
