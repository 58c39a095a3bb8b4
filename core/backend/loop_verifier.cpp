#include "core/backend/loop_verifier.hpp"

#include <algorithm>
#include <cmath>

#include "core/backend/reason_text.hpp"

namespace dammloam::backend {

namespace {

// Covariance of the registered T_target_source in the pose graph's edge tangent, with no
// information along unobserved translation directions. The ICP information is for a left
// perturbation dx = [rho; phi] (t' = t + rho - [t]x phi, R' = R Exp(R^T phi)); the pose
// graph's edge error is e = [t' - t; log(R^T R')] = A dx.
Matrix6d EdgeCovariance(const IcpResult& icp, const Eigen::Matrix3d& observed,
                        const LoopVerifierConfig& config) {
  Matrix6d P = Matrix6d::Identity();
  P.topLeftCorner<3, 3>() = observed;
  const double sigma = std::max(icp.rmse, config.min_noise_sigma);
  Matrix6d information = P.transpose() * icp.hessian * P / (sigma * sigma);
  information.diagonal().head<3>().array() +=
      1.0 / (config.free_translation_sigma * config.free_translation_sigma);
  information.diagonal().tail<3>().array() +=
      1.0 / (config.free_rotation_sigma * config.free_rotation_sigma);
  const Matrix6d covariance_dx = information.ldlt().solve(Matrix6d::Identity());
  Matrix6d A = Matrix6d::Identity();
  A.topRightCorner<3, 3>() = -Hat(icp.T_target_source.translation());
  A.bottomRightCorner<3, 3>() = icp.T_target_source.rotation().transpose();
  return A * covariance_dx * A.transpose();
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

  // Two starting guesses: odometry's relative pose (right when drift is small) and Scan
  // Context's yaw at zero offset (same place). Odometry's goes first: in a corridor, which
  // looks the same from both ends, the other guess finds a perfect fit at the wrong heading.
  const Eigen::Isometry3d T_odom =
      candidate.T_world_sensor_odom.inverse() * query.T_world_sensor_odom;
  Eigen::Isometry3d T_yaw = Eigen::Isometry3d::Identity();
  T_yaw.linear() = Eigen::AngleAxisd(match.yaw_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const IcpTarget target(candidate.points, config_.normal_neighbours);
  IcpConfig icp_config = config_.icp;
  icp_config.min_direction_support = config_.min_direction_support;
  bool first = true;
  for (const Eigen::Isometry3d& guess : {T_odom, T_yaw}) {
    IcpResult icp = AlignPointToPlane(query.points, target, guess, icp_config);
    // Along directions the final alignment does not observe it may still have drifted (a few
    // far points cut by one ring pose as planes while it iterates): keep the guess's value.
    const Eigen::Matrix3d observed =
        SupportedDirections(icp.hessian.topLeftCorner<3, 3>(), config_.min_direction_support);
    icp.T_target_source.translation() -= (Eigen::Matrix3d::Identity() - observed) *
                                         (icp.T_target_source.translation() - guess.translation());
    LoopEvent judged = event;
    Judge(icp, observed, T_odom, candidate.T_world_sensor.linear(), path_length,
          first ? config_.min_inlier_ratio_from_odometry : config_.min_inlier_ratio, judged);
    // Report the first acceptable hypothesis, else the one that fits best.
    if (judged.accepted || first || judged.inlier_ratio > event.inlier_ratio) event = judged;
    if (event.accepted) break;
    first = false;
  }
  return event;
}

void LoopVerifier::Judge(const IcpResult& icp, const Eigen::Matrix3d& observed,
                         const Eigen::Isometry3d& T_odom, const Eigen::Matrix3d& R_map_candidate,
                         double path_length, double min_inlier_ratio, LoopEvent& event) const {
  event.T_candidate_query = icp.T_target_source;
  event.inlier_ratio = icp.inlier_ratio;
  event.rmse = icp.rmse;
  event.translation_observability = icp.translation_observability;
  event.observed_translation_directions = static_cast<int>(std::lround(observed.trace()));
  event.covariance = EdgeCovariance(icp, observed, config_);
  // Judged in every direction, the free ones included: the registration keeps odometry's value
  // there, so a loop that ends far from it along a corridor's axis has slid to a look-alike
  // place, and even its cross-corridor claim is then off by the axis' small tilt times the slide.
  event.odometry_disagreement = (icp.T_target_source.translation() - T_odom.translation()).norm();
  const double rotation_disagreement =
      Eigen::AngleAxisd(T_odom.rotation().transpose() * icp.T_target_source.rotation()).angle();
  const double drift_budget = config_.drift_offset + config_.drift_per_metre * path_length;
  const double rotation_budget =
      config_.rotation_drift_offset + config_.rotation_drift_per_metre * path_length;
  // How far up the query is: the registration's word along what it observes, odometry's along
  // the rest (a guess at zero offset is no evidence of being on the same floor).
  const Eigen::Vector3d t_registered = icp.T_target_source.translation();
  const Eigen::Vector3d t_evidence =
      t_registered + (Eigen::Matrix3d::Identity() - observed) * (T_odom.translation() - t_registered);
  const double rise = (R_map_candidate * t_evidence).z();

  event.accepted = false;
  if (icp.inlier_ratio < min_inlier_ratio) {
    event.reason = ReasonText("inlier ratio %.2f below %.2f", icp.inlier_ratio, min_inlier_ratio);
  } else if (icp.rmse > config_.max_rmse) {
    event.reason = ReasonText("residual %.3f m above %.3f m", icp.rmse, config_.max_rmse);
  } else if (event.observed_translation_directions < config_.min_observed_directions) {
    event.reason = ReasonText("degenerate geometry: %.0f of 3 translation directions observed, "
                          "%.0f needed",
                          event.observed_translation_directions,
                          config_.min_observed_directions);
  } else if (event.odometry_disagreement > drift_budget) {
    event.reason = ReasonText("disagrees with odometry by %.2f m (drift budget %.2f m)",
                          event.odometry_disagreement, drift_budget);
  } else if (rotation_disagreement > rotation_budget) {
    event.reason = ReasonText("disagrees with odometry by %.2f rad (drift budget %.2f rad)",
                          rotation_disagreement, rotation_budget);
  } else if (config_.max_level_difference > 0.0 && std::abs(rise) > config_.max_level_difference) {
    event.reason = ReasonText("another level: %+.2f m vertically from the candidate (more than "
                              "%.2f m either way)",
                              rise, config_.max_level_difference);
  } else {
    event.accepted = true;
    event.reason = event.observed_translation_directions == 3
                       ? "accepted"
                       : ReasonText("accepted: constrains %.0f of %.0f translation directions",
                                event.observed_translation_directions, 3);
  }
}

}  // namespace dammloam::backend
