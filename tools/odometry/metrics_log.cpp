#include <algorithm>
#include <spdlog/spdlog.h>
#include <stdexcept>

#include "tools/evaluate/trajectory_metrics.hpp"
#include "tools/odometry/runner.hpp"

namespace dammloam::tools {

std::optional<double> LogMetrics(const std::string& label, const std::vector<io::StampedPose>& gt,
                                 const std::vector<io::StampedPose>& estimate) {
  try {
    const eval::TrajectoryMetrics m = eval::EvaluateTrajectories(gt, estimate);
    spdlog::info("{} vs gt.tum: APE RMSE {:.4f} m, RPE RMSE {:.4f} m, drift {:.2f} %", label,
                 m.ape.rmse, m.rpe.rmse, m.drift_percent);
    return m.ape.rmse;
  } catch (const std::invalid_argument& e) {
    spdlog::warn("{} vs gt.tum: not evaluated: {}", label, e.what());
    return std::nullopt;
  }
}

double Median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

}  // namespace dammloam::tools
