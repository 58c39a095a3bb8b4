#include "tools/benchmark/moving_label_score.hpp"

#include <algorithm>

#include "tools/simulate/actors.hpp"

namespace dammloam::bench {
namespace {

double Share(std::size_t part, std::size_t whole) {
  return whole == 0 ? 0.0 : static_cast<double>(part) / static_cast<double>(whole);
}

}  // namespace

double MovingLabelScore::Precision() const {
  // Nothing labelled Moving: no wrong label either.
  const std::size_t flagged = moving_found + static_flagged;
  return flagged == 0 ? 1.0 : Share(moving_found, flagged);
}

double MovingLabelScore::Recall() const {
  const std::size_t moving = moving_found + moving_missed;
  return moving == 0 ? 1.0 : Share(moving_found, moving);
}

double MovingLabelScore::StaticFlaggedShare() const { return Share(static_flagged, static_points); }

MovingLabelScore& MovingLabelScore::operator+=(const MovingLabelScore& o) {
  moving_found += o.moving_found;
  moving_missed += o.moving_missed;
  static_flagged += o.static_flagged;
  static_points += o.static_points;
  resting_flagged += o.resting_flagged;
  resting_points += o.resting_points;
  mismatched_scans += o.mismatched_scans;
  return *this;
}

MovingLabelScore ScoreMovingLabels(const std::vector<std::uint8_t>& truth,
                                   const std::vector<std::uint8_t>& kept,
                                   const std::vector<PointClass>& labels) {
  MovingLabelScore score;
  const auto num_kept = static_cast<std::size_t>(std::count(kept.begin(), kept.end(), 1));
  if (truth.size() != kept.size() || num_kept != labels.size()) {
    score.mismatched_scans = 1;
    return score;
  }
  std::size_t j = 0;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (kept[i] == 0) continue;
    const bool flagged = labels[j++] == PointClass::Moving;
    switch (static_cast<sim::PointLabel>(truth[i])) {
      case sim::PointLabel::Moving:
        ++(flagged ? score.moving_found : score.moving_missed);
        break;
      case sim::PointLabel::Resting:
        ++score.resting_points;
        score.resting_flagged += flagged ? 1 : 0;
        break;
      case sim::PointLabel::Static:
      default:
        ++score.static_points;
        score.static_flagged += flagged ? 1 : 0;
        break;
    }
  }
  return score;
}

}  // namespace dammloam::bench
