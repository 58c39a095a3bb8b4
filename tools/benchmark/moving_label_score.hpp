#pragma once
// How well the odometry's Moving class matches the simulator's per-point truth
// (sim::PointLabel: static, moving = moved more than 0.3 m in the last second, resting actor).
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/geometry/point_class.hpp"

namespace dammloam::bench {

struct MovingLabelScore {
  std::size_t moving_found = 0;   // truth moving, labelled Moving
  std::size_t moving_missed = 0;  // truth moving, labelled otherwise
  std::size_t static_flagged = 0;  // truth static, labelled Moving
  std::size_t static_points = 0;
  std::size_t resting_flagged = 0;  // an actor at rest, labelled Moving (neither right nor wrong)
  std::size_t resting_points = 0;
  std::size_t mismatched_scans = 0;  // truth and result of different sizes: not scored

  // Of the points labelled Moving, the share on truly moving or static things: resting actors
  // are left out (a person who just stopped may still be called moving, or not).
  double Precision() const;
  double Recall() const;
  double StaticFlaggedShare() const;  // of the static points
  MovingLabelScore& operator+=(const MovingLabelScore& other);
};

// Scores one scan. `truth`: one label per point of the input scan; `kept`: 1 where the
// preprocessing kept that point (FeatureExtractor::KeptPoints); `labels`: the result's labels,
// one per kept point, in order.
MovingLabelScore ScoreMovingLabels(const std::vector<std::uint8_t>& truth,
                                   const std::vector<std::uint8_t>& kept,
                                   const std::vector<PointClass>& labels);

}  // namespace dammloam::bench
