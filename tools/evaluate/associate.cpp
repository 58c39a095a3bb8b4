#include "tools/evaluate/associate.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace dammloam::eval {
namespace {

void SortByTime(std::vector<StampedPose>& poses) {
  std::stable_sort(poses.begin(), poses.end(),
                   [](const StampedPose& a, const StampedPose& b) { return a.t < b.t; });
}

// Index of the pose in `sorted` nearest to t, if within max_diff.
std::optional<std::size_t> Nearest(const std::vector<StampedPose>& sorted, double t,
                                   double max_diff) {
  const auto after = std::lower_bound(sorted.begin(), sorted.end(), t,
                                      [](const StampedPose& p, double value) { return p.t < value; });
  std::optional<std::size_t> best;
  double best_diff = max_diff;
  const auto consider = [&](std::vector<StampedPose>::const_iterator it) {
    const double diff = std::abs(it->t - t);
    if (diff <= best_diff) {
      best_diff = diff;
      best = static_cast<std::size_t>(it - sorted.begin());
    }
  };
  if (after != sorted.end()) consider(after);
  if (after != sorted.begin()) consider(std::prev(after));
  return best;
}

}  // namespace

MatchedTrajectories AssociateByTime(std::vector<StampedPose> gt, std::vector<StampedPose> est,
                                    double max_time_diff) {
  SortByTime(gt);
  SortByTime(est);
  const bool gt_is_short = gt.size() <= est.size();
  const std::vector<StampedPose>& shorter = gt_is_short ? gt : est;
  const std::vector<StampedPose>& longer = gt_is_short ? est : gt;

  MatchedTrajectories matched;
  std::vector<bool> used(longer.size(), false);
  for (const StampedPose& pose : shorter) {
    const auto index = Nearest(longer, pose.t, max_time_diff);
    if (!index || used[*index]) continue;
    used[*index] = true;
    matched.gt.push_back(gt_is_short ? pose : longer[*index]);
    matched.est.push_back(gt_is_short ? longer[*index] : pose);
  }
  return matched;
}

}  // namespace dammloam::eval
