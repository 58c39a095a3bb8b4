#include "tools/benchmark/sim_run.hpp"

#include <algorithm>
#include <cmath>

#include "core/odometry/pipeline.hpp"
#include "tools/evaluate/trajectory_metrics.hpp"

namespace dammloam::bench {

SimSequence GenerateSequence(sim::SceneKind scene, const sim::SensorSpec& sensor, int num_scans,
                             std::uint64_t seed) {
  sim::SimOptions options;
  options.seed = seed;
  options.num_scans = num_scans;
  const sim::Simulator simulator(scene, sensor, options);
  SimSequence sequence;
  sequence.scene = std::string(sim::SceneName(scene));
  sequence.sensor = sensor.name;
  sequence.model = simulator.sensor_model();
  for (int i = 0; i < num_scans; ++i) {
    sequence.scans.push_back(simulator.SimulateScan(i));
    const double t = simulator.ScanStartTime(i);
    sequence.ground_truth.push_back({t, simulator.PoseAt(t)});
  }
  return sequence;
}

Percentiles ComputePercentiles(std::vector<double> values) {
  if (values.empty()) return {};
  std::sort(values.begin(), values.end());
  const auto at = [&](double q) {
    const auto i = static_cast<std::size_t>(std::lround(q * static_cast<double>(values.size() - 1)));
    return values[i];
  };
  return {at(0.5), at(0.95)};
}

RunSummary RunPipeline(const SimSequence& sequence, const OdometryConfig& config) {
  OdometryPipeline pipeline(config, sequence.model);
  RunSummary summary;
  summary.mode = std::string(Name(config.registration.mode));
  std::vector<double> projection, normals, classification;
  std::vector<double> features, deskew, downsample, registration, map_update, total, iterations;
  std::size_t degenerate = 0;
  for (const Scan& scan : sequence.scans) {
    OdometryResult r = pipeline.Process(scan);
    r.deskewed_points.clear();
    r.labels.clear();
    r.normals.clear();
    summary.estimate.push_back({r.stamp, r.T_world_sensor});
    if (Registered(r.status)) ++summary.registered;
    const StageTimings& t = r.timings;
    projection.push_back(t.projection_ms);
    normals.push_back(t.normals_ms);
    classification.push_back(t.classification_ms);
    features.push_back(t.projection_ms + t.normals_ms + t.classification_ms);
    deskew.push_back(t.deskew_ms);
    downsample.push_back(t.downsample_ms);
    registration.push_back(t.registration_ms);
    map_update.push_back(t.map_update_ms);
    total.push_back(t.total_ms);
    iterations.push_back(r.iterations);
    const auto& d = r.degeneracy.degenerate;
    if (r.iterations > 0 && (d[0] || d[1] || d[2])) ++degenerate;
    summary.results.push_back(std::move(r));
  }
  summary.projection_ms = ComputePercentiles(projection);
  summary.normals_ms = ComputePercentiles(normals);
  summary.classification_ms = ComputePercentiles(classification);
  summary.features_ms = ComputePercentiles(features);
  summary.deskew_ms = ComputePercentiles(deskew);
  summary.downsample_ms = ComputePercentiles(downsample);
  summary.registration_ms = ComputePercentiles(registration);
  summary.map_update_ms = ComputePercentiles(map_update);
  summary.total_ms = ComputePercentiles(total);
  summary.median_iterations = ComputePercentiles(iterations).median;
  summary.degenerate_share =
      sequence.scans.empty() ? 0.0 : static_cast<double>(degenerate) / sequence.scans.size();
  const eval::TrajectoryMetrics metrics =
      eval::EvaluateTrajectories(sequence.ground_truth, summary.estimate);
  summary.ape_rmse = metrics.ape.rmse;
  summary.rpe_rmse = metrics.rpe.rmse;
  return summary;
}

}  // namespace dammloam::bench
