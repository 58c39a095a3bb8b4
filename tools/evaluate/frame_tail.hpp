#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace dammloam::eval {

// How heavy the tail of a run's frame errors (1-frame RPE vectors) is. The worst frame over the
// median frame is set against the same ratio for Gaussian frame errors with the run's own mean
// and 3x3 covariance, over as many frames: a run inside that band has no outlier frames, its
// worst frames are its noise's tail; a run far above it has frames the registration got wrong.
// Over 850-2500 frames, Gaussian errors alone give 2.7-3x for isotropic noise and more where one
// axis dominates, so a bar of 3x on the raw ratio mostly measures the noise's shape.
struct FrameTail {
  std::size_t frames = 0;
  double worst_over_median = 0.0;
  double gaussian_median = 0.0;  // median of the ratio over the Gaussian draws
  double gaussian_p95 = 0.0;     // its 95th percentile
  // The share of Gaussian draws whose ratio reaches the run's: small (< 0.05) for a run with
  // frames heavier-tailed than its own noise.
  double gaussian_share_at_least = 0.0;
};

// Needs at least 3 frames with a non-zero median; otherwise frames < 3 and the rest stays 0.
// Deterministic for a given seed.
FrameTail AnalyseFrameTail(const std::vector<Eigen::Vector3d>& frame_errors, int draws = 200,
                           std::uint64_t seed = 1);

}  // namespace dammloam::eval
