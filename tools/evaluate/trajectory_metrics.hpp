#pragma once
#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

#include "io/tum.hpp"
#include "tools/evaluate/associate.hpp"
#include "tools/evaluate/error_stats.hpp"
#include "tools/evaluate/frame_tail.hpp"

// Trajectory accuracy as evo reports it: APE after SE(3) Umeyama alignment
// (`evo_ape tum gt est -a`), RPE over consecutive frames (`evo_rpe tum gt est`), plus the end
// drift in percent of the path length that odometry papers quote.
namespace dammloam::eval {

struct EvaluateOptions {
  double max_time_diff = 0.01;  // seconds, for pairing poses by timestamp
};

struct TrajectoryMetrics {
  ErrorStats ape;  // translation, metres, after alignment
  ErrorStats rpe;  // translation, metres, delta 1 frame, not aligned
  FrameTail rpe_tail;  // the worst 1-frame error over the median, against Gaussian frame noise
  // T_gt_est: maps estimated poses into the ground-truth frame (Umeyama, no scale).
  Eigen::Isometry3d alignment = Eigen::Isometry3d::Identity();
  double path_length_m = 0.0;  // of the matched ground-truth poses
  double end_drift_m = 0.0;    // |t_gt_end - t_est_end| with the first poses made equal
  double drift_percent = 0.0;  // end_drift_m / path_length_m * 100; NaN for a zero path
  // Steps between consecutive matched poses whose relative error is under kTrackedStepMetres
  // and kTrackedStepDegrees: the share a robot could have used (issue 58's measure).
  std::size_t tracked_steps = 0;
  std::size_t steps = 0;
  std::size_t pairs = 0;
  std::size_t unmatched_gt = 0;
  std::size_t unmatched_est = 0;
  // For plots: matched positions, the estimate after alignment.
  std::vector<Eigen::Vector3d> gt_positions;
  std::vector<Eigen::Vector3d> est_positions_aligned;
};

inline constexpr double kTrackedStepMetres = 0.1;
inline constexpr double kTrackedStepDegrees = 2.0;

// Consecutive matched pairs whose relative pose error is below both tracked-step bounds.
std::size_t TrackedSteps(const MatchedTrajectories& matched);

// T such that T * est ~ gt in the least-squares sense over positions (Umeyama 1991, no scale).
Eigen::Isometry3d AlignUmeyama(const std::vector<Eigen::Vector3d>& est,
                               const std::vector<Eigen::Vector3d>& gt);

// |t_gt_i - t_(T*est)_i| per matched pair.
std::vector<double> ApeTranslationErrors(const MatchedTrajectories& matched,
                                         const Eigen::Isometry3d& T_gt_est);

// trans((Q_i^-1 Q_i+1)^-1 (P_i^-1 P_i+1)) with Q = gt, P = est, per consecutive pair.
std::vector<Eigen::Vector3d> RpeTranslationVectors(const MatchedTrajectories& matched);
// Their norms.
std::vector<double> RpeTranslationErrors(const MatchedTrajectories& matched);

// Throws std::invalid_argument when fewer than 2 poses can be paired.
TrajectoryMetrics EvaluateTrajectories(const std::vector<io::StampedPose>& gt,
                                       const std::vector<io::StampedPose>& est,
                                       const EvaluateOptions& options = {});

}  // namespace dammloam::eval
