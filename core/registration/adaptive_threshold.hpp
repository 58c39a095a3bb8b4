#pragma once
#include <Eigen/Geometry>

namespace dammloam {

// KISS-ICP's adaptive threshold: sigma is the RMS of past model deviations (prediction vs.
// registered pose, expressed as the largest point displacement within reference_range), so
// the correspondence gate follows how wrong the motion model has been. Deviations below
// min_motion_threshold count as that floor (KISS-ICP leaves them out).
class AdaptiveThreshold {
 public:
  AdaptiveThreshold(double initial_threshold, double min_motion_threshold, double reference_range);
  void UpdateModelDeviation(const Eigen::Isometry3d& model_deviation);
  double Sigma() const;

 private:
  double initial_threshold_;
  double min_motion_threshold_;
  double reference_range_;
  double model_sse_ = 0.0;
  int num_samples_ = 0;
};

}  // namespace dammloam
