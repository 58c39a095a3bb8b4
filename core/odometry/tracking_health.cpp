#include "core/odometry/tracking_health.hpp"

#include <algorithm>
#include <vector>

namespace dammloam {

double TrackingHealth::ReferenceShare() const {
  if (recent_shares_.empty()) return 0.0;
  std::vector<double>& sorted = sorted_shares_;
  sorted.assign(recent_shares_.begin(), recent_shares_.end());
  auto mid = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
  std::nth_element(sorted.begin(), mid, sorted.end());
  return *mid;
}

bool TrackingHealth::FewPairs(double paired_share) const {
  const double reference = ReferenceShare();
  return recent_shares_.size() >= 3 && reference > 0.0 &&
         paired_share < config_.degraded_pair_share * reference;
}

Tracking TrackingHealth::Judge(const FitEvidence& fit) const {
  const double reference = ReferenceShare();
  // Until a few scans have been registered there is nothing to compare against.
  const bool judged = recent_shares_.size() >= 3 && reference > 0.0;
  const double share = judged ? fit.paired_share / reference : 1.0;
  if (share < config_.lost_pair_share) return Tracking::kLost;
  const bool few_pairs = share < config_.degraded_pair_share;
  if (few_pairs && !fit.converged) return Tracking::kLost;
  const bool far_from_prediction =
      fit.gate > 0.0 && fit.innovation > config_.max_innovation_gates * fit.gate;
  if (few_pairs || !fit.converged || far_from_prediction) return Tracking::kDegraded;
  return Tracking::kTracking;
}

void TrackingHealth::Record(double paired_share) {
  recent_shares_.push_back(paired_share);
  while (static_cast<int>(recent_shares_.size()) > config_.reference_scans) recent_shares_.pop_front();
}

}  // namespace dammloam
