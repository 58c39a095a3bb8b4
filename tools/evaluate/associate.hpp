#pragma once
#include <vector>

#include "io/tum.hpp"

namespace dammloam::eval {

using io::StampedPose;

// Poses of two trajectories paired by timestamp, both sorted by time: gt[i] belongs to est[i].
struct MatchedTrajectories {
  std::vector<StampedPose> gt;
  std::vector<StampedPose> est;
};

// Like evo's `associate`: every pose of the shorter trajectory takes the nearest-in-time pose of
// the longer one when |dt| <= max_time_diff. Each pose is used at most once.
MatchedTrajectories AssociateByTime(std::vector<StampedPose> gt, std::vector<StampedPose> est,
                                    double max_time_diff);

}  // namespace dammloam::eval
