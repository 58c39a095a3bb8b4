#pragma once
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "io/tum.hpp"

// Loop closures judged against the ground truth: a loop's registered relative pose is compared
// with the one the truth gives between the same two stamps (issue 53: a loop is false when it
// is more than 1 m or 5 deg from the truth).
namespace dammloam::eval {

struct LoopToJudge {
  double query_stamp = 0.0, candidate_stamp = 0.0;
  Eigen::Isometry3d T_candidate_query = Eigen::Isometry3d::Identity();  // as registered
  bool accepted = false;
  std::string reason;
};

struct LoopVerdict {
  LoopToJudge loop;
  Eigen::Isometry3d T_truth = Eigen::Isometry3d::Identity();  // candidate -> query, from gt
  double translation_error = 0.0;  // metres, |t(T_truth^-1 T_candidate_query)|
  double rotation_error_deg = 0.0;
  bool is_false = false;           // beyond either limit
};

struct LoopLimits {
  double max_translation = 1.0;   // metres
  double max_rotation_deg = 5.0;
  double max_time_diff = 0.01;    // seconds between a loop's stamp and the nearest gt pose
};

// Reads the `--events` file of dammloam-odometry: one JSON object per line (query_stamp,
// candidate_stamp, T_candidate_query [tx ty tz qx qy qz qw], accepted, reason).
std::vector<LoopToJudge> ReadLoopEvents(const std::string& file);

// Throws std::invalid_argument when a stamp has no gt pose within limits.max_time_diff.
LoopVerdict JudgeLoop(const std::vector<io::StampedPose>& gt, const LoopToJudge& loop,
                      const LoopLimits& limits);

}  // namespace dammloam::eval
