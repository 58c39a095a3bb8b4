#include "tools/evaluate/trajectory_metrics.hpp"

#include <Eigen/Geometry>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace dammloam::eval {
namespace {

std::vector<Eigen::Vector3d> Positions(const std::vector<StampedPose>& poses,
                                       const Eigen::Isometry3d& T = Eigen::Isometry3d::Identity()) {
  std::vector<Eigen::Vector3d> positions;
  positions.reserve(poses.size());
  for (const auto& pose : poses) positions.push_back(T * pose.T.translation());
  return positions;
}

double PathLength(const std::vector<Eigen::Vector3d>& positions) {
  double length = 0.0;
  for (std::size_t i = 1; i < positions.size(); ++i) {
    length += (positions[i] - positions[i - 1]).norm();
  }
  return length;
}

// Distance between the last poses once the estimate starts where the ground truth starts.
double EndDrift(const MatchedTrajectories& matched) {
  const Eigen::Isometry3d T_gt_est = matched.gt.front().T * matched.est.front().T.inverse();
  const Eigen::Vector3d est_end = T_gt_est * matched.est.back().T.translation();
  return (matched.gt.back().T.translation() - est_end).norm();
}

std::vector<double> Norms(const std::vector<Eigen::Vector3d>& vectors) {
  std::vector<double> norms;
  norms.reserve(vectors.size());
  for (const Eigen::Vector3d& v : vectors) norms.push_back(v.norm());
  return norms;
}

}  // namespace

Eigen::Isometry3d AlignUmeyama(const std::vector<Eigen::Vector3d>& est,
                               const std::vector<Eigen::Vector3d>& gt) {
  const auto n = static_cast<Eigen::Index>(est.size());
  Eigen::Matrix3Xd src(3, n), dst(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    src.col(i) = est[static_cast<std::size_t>(i)];
    dst.col(i) = gt[static_cast<std::size_t>(i)];
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.matrix() = Eigen::umeyama(src, dst, /*with_scaling=*/false);
  return T;
}

std::vector<double> ApeTranslationErrors(const MatchedTrajectories& matched,
                                         const Eigen::Isometry3d& T_gt_est) {
  std::vector<double> errors;
  errors.reserve(matched.gt.size());
  for (std::size_t i = 0; i < matched.gt.size(); ++i) {
    errors.push_back((matched.gt[i].T.translation() - T_gt_est * matched.est[i].T.translation()).norm());
  }
  return errors;
}

std::vector<Eigen::Vector3d> RpeTranslationVectors(const MatchedTrajectories& matched) {
  std::vector<Eigen::Vector3d> errors;
  for (std::size_t i = 0; i + 1 < matched.gt.size(); ++i) {
    const Eigen::Isometry3d gt_delta = matched.gt[i].T.inverse() * matched.gt[i + 1].T;
    const Eigen::Isometry3d est_delta = matched.est[i].T.inverse() * matched.est[i + 1].T;
    errors.push_back((gt_delta.inverse() * est_delta).translation());
  }
  return errors;
}

std::vector<double> RpeTranslationErrors(const MatchedTrajectories& matched) {
  return Norms(RpeTranslationVectors(matched));
}

std::size_t TrackedSteps(const MatchedTrajectories& matched) {
  std::size_t tracked = 0;
  const double max_angle = kTrackedStepDegrees * std::numbers::pi / 180.0;
  for (std::size_t i = 0; i + 1 < matched.gt.size(); ++i) {
    const Eigen::Isometry3d gt_delta = matched.gt[i].T.inverse() * matched.gt[i + 1].T;
    const Eigen::Isometry3d est_delta = matched.est[i].T.inverse() * matched.est[i + 1].T;
    const Eigen::Isometry3d error = gt_delta.inverse() * est_delta;
    const double angle = Eigen::AngleAxisd(error.rotation()).angle();
    tracked += error.translation().norm() < kTrackedStepMetres && angle < max_angle;
  }
  return tracked;
}

TrajectoryMetrics EvaluateTrajectories(const std::vector<io::StampedPose>& gt,
                                       const std::vector<io::StampedPose>& est,
                                       const EvaluateOptions& options) {
  const MatchedTrajectories matched = AssociateByTime(gt, est, options.max_time_diff);
  if (matched.gt.size() < 2) {
    throw std::invalid_argument("only " + std::to_string(matched.gt.size()) +
                                " poses could be paired by timestamp (max time difference " +
                                std::to_string(options.max_time_diff) + " s); need at least 2");
  }
  TrajectoryMetrics metrics;
  metrics.pairs = matched.gt.size();
  metrics.unmatched_gt = gt.size() - metrics.pairs;
  metrics.unmatched_est = est.size() - metrics.pairs;
  metrics.gt_positions = Positions(matched.gt);
  metrics.alignment = AlignUmeyama(Positions(matched.est), metrics.gt_positions);
  metrics.est_positions_aligned = Positions(matched.est, metrics.alignment);
  metrics.ape = ComputeStats(ApeTranslationErrors(matched, metrics.alignment));
  const std::vector<Eigen::Vector3d> frame_errors = RpeTranslationVectors(matched);
  metrics.rpe = ComputeStats(Norms(frame_errors));
  metrics.rpe_tail = AnalyseFrameTail(frame_errors);
  metrics.steps = matched.gt.size() - 1;
  metrics.tracked_steps = TrackedSteps(matched);
  metrics.path_length_m = PathLength(metrics.gt_positions);
  metrics.end_drift_m = EndDrift(matched);
  metrics.drift_percent = metrics.path_length_m > 0.0
                              ? 100.0 * metrics.end_drift_m / metrics.path_length_m
                              : std::numeric_limits<double>::quiet_NaN();
  return metrics;
}

}  // namespace dammloam::eval
