#include "core/registration/adaptive_threshold.hpp"

#include <algorithm>
#include <cmath>

namespace dammloam {

AdaptiveThreshold::AdaptiveThreshold(double initial_threshold, double min_motion_threshold,
                                     double reference_range)
    : initial_threshold_(initial_threshold),
      min_motion_threshold_(min_motion_threshold),
      reference_range_(reference_range) {}

void AdaptiveThreshold::UpdateModelDeviation(const Eigen::Isometry3d& model_deviation) {
  const double theta = Eigen::AngleAxisd(model_deviation.linear()).angle();
  const double rotation_error = 2.0 * reference_range_ * std::sin(theta / 2.0);
  // A deviation below the floor counts as the floor: smooth motion in a small scene must not
  // leave sigma at its initial guess (KISS-ICP skips such samples, harmless only when rotations
  // are measured at 100 m, where every deviation exceeds the floor).
  const double error =
      std::max(rotation_error + model_deviation.translation().norm(), min_motion_threshold_);
  model_sse_ += error * error;
  ++num_samples_;
}

double AdaptiveThreshold::Sigma() const {
  return num_samples_ < 1 ? initial_threshold_ : std::sqrt(model_sse_ / num_samples_);
}

}  // namespace dammloam
