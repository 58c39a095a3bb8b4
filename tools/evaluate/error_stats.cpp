#include "tools/evaluate/error_stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dammloam::eval {

ErrorStats ComputeStats(std::vector<double> errors) {
  ErrorStats stats;
  stats.count = errors.size();
  if (errors.empty()) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    stats.rmse = stats.mean = stats.median = stats.std = stats.min = stats.max = nan;
    return stats;
  }
  const double n = static_cast<double>(errors.size());
  double sum = 0.0;
  for (const double e : errors) {
    sum += e;
    stats.sse += e * e;
  }
  stats.mean = sum / n;
  stats.rmse = std::sqrt(stats.sse / n);
  double squared_deviation = 0.0;
  for (const double e : errors) squared_deviation += (e - stats.mean) * (e - stats.mean);
  stats.std = std::sqrt(squared_deviation / n);

  std::sort(errors.begin(), errors.end());
  stats.min = errors.front();
  stats.max = errors.back();
  const std::size_t mid = errors.size() / 2;
  stats.median = errors.size() % 2 == 1 ? errors[mid] : 0.5 * (errors[mid - 1] + errors[mid]);
  return stats;
}

}  // namespace dammloam::eval
