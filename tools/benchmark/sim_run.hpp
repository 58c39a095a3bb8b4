#pragma once
// Runs the odometry pipeline over an in-memory simulated sequence and summarises accuracy and
// per-stage timings. Shared by the benchmark and the integration tests.
#include <string>
#include <vector>

#include "core/geometry/scan.hpp"
#include "core/odometry/odometry_config.hpp"
#include "core/odometry/odometry_result.hpp"
#include "tools/common/tum.hpp"
#include "tools/simulate/simulator.hpp"

namespace dammloam::bench {

struct SimSequence {
  std::string scene;
  std::string sensor;
  SensorModel model;
  std::vector<Scan> scans;
  std::vector<io::StampedPose> ground_truth;  // sensor pose at each scan start
};

SimSequence GenerateSequence(sim::SceneKind scene, const sim::SensorSpec& sensor, int num_scans,
                             std::uint64_t seed = 1);

struct Percentiles {
  double median = 0.0;
  double p95 = 0.0;
};
Percentiles ComputePercentiles(std::vector<double> values);

struct RunSummary {
  std::string mode;
  double ape_rmse = 0.0;  // metres, SE(3)-aligned
  double rpe_rmse = 0.0;  // metres, frame to frame
  std::size_t registered = 0;
  Percentiles features_ms, deskew_ms, downsample_ms, registration_ms, map_update_ms, total_ms;
  Percentiles projection_ms, normals_ms, classification_ms;  // the feature stage's parts
  double median_iterations = 0.0;
  double degenerate_share = 0.0;  // scans with at least one degenerate direction
  std::vector<OdometryResult> results;  // without the per-point vectors
  std::vector<io::StampedPose> estimate;
};

// Runs a fresh OdometryPipeline over the sequence.
RunSummary RunPipeline(const SimSequence& sequence, const OdometryConfig& config);

}  // namespace dammloam::bench
