#include "core/preprocess/point_times.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace dammloam {

namespace {

// Time slices of the scan's span whose directions are compared: 32 slices are 11 degrees of a
// revolution each, where the mean horizontal direction of a slice's points has length ~0.99;
// points of random times give ~0 (1 / sqrt(n)).
constexpr int kSlices = 32;
constexpr double kMinConcentration = 0.5;
constexpr int kMinPointsPerSlice = 8;
constexpr std::size_t kSampleStride = 4;  // every 4th point is plenty and keeps this < 0.3 ms

bool FollowsFiringOrder(const Scan& scan, float t_min, float t_max) {
  std::array<Eigen::Vector2d, kSlices> direction_sum;
  direction_sum.fill(Eigen::Vector2d::Zero());
  std::array<int, kSlices> count{};
  const double scale = kSlices / (double{t_max} - double{t_min});
  for (std::size_t i = 0; i < scan.size(); i += kSampleStride) {
    const Eigen::Vector2d xy = scan.points[i].head<2>();
    const double r = xy.norm();
    if (!(r > 1e-6) || !std::isfinite(r)) continue;
    const int slice = std::min(kSlices - 1, static_cast<int>((scan.times[i] - t_min) * scale));
    direction_sum[slice] += xy / r;
    ++count[slice];
  }
  std::array<double, kSlices> concentration;
  std::size_t judged = 0;
  for (int s = 0; s < kSlices; ++s) {
    if (count[s] >= kMinPointsPerSlice) concentration[judged++] = direction_sum[s].norm() / count[s];
  }
  // Too few points to judge (a cropped or nearly empty scan): nothing says the times are wrong.
  if (judged < 4) return true;
  auto mid = concentration.begin() + judged / 2;
  std::nth_element(concentration.begin(), mid, concentration.begin() + judged);
  return *mid >= kMinConcentration;
}

}  // namespace

PointTimeCheck CheckPointTimes(const Scan& scan, double scan_period) {
  if (!scan.has_times()) return PointTimeCheck::kAbsent;
  float t_min = scan.times.front(), t_max = scan.times.front();
  for (float t : scan.times) {
    if (!std::isfinite(t)) return PointTimeCheck::kNotFinite;
    t_min = std::min(t_min, t);
    t_max = std::max(t_max, t);
  }
  if (!(double{t_max} - double{t_min} >= kMinTimeSpan * scan_period)) return PointTimeCheck::kConstant;
  return FollowsFiringOrder(scan, t_min, t_max) ? PointTimeCheck::kUsable
                                                : PointTimeCheck::kNotFiringOrder;
}

}  // namespace dammloam
