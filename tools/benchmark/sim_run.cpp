#include "tools/benchmark/sim_run.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <stdexcept>

#include "core/odometry/pipeline.hpp"
#include "core/preprocess/feature_extractor.hpp"
#include "io/sequence_io.hpp"
#include "tools/benchmark/heap_allocations.hpp"
#include "tools/evaluate/associate.hpp"
#include "tools/evaluate/trajectory_metrics.hpp"

namespace dammloam::bench {

SimSequence GenerateSequence(sim::SceneKind scene, const sim::SensorSpec& sensor, int num_scans,
                             std::uint64_t seed) {
  sim::SimOptions options;
  options.seed = seed;
  options.num_scans = num_scans;
  SimSequence sequence = RecordSequence(sim::Simulator(scene, sensor, options), num_scans);
  sequence.scene = std::string(sim::SceneName(scene));
  sequence.sensor = sensor.name;
  return sequence;
}

SimSequence RecordSequence(const sim::Simulator& simulator, int num_scans) {
  SimSequence sequence;
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
  return {at(0.5), at(0.95), at(0.99), values.back()};
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

ScanStream SimulatedStream(const sim::Simulator& simulator, int num_scans) {
  ScanStream stream;
  stream.sensor = simulator.sensor().name;
  stream.model = simulator.sensor_model();
  for (int i = 0; i < num_scans; ++i) {
    const double t = simulator.ScanStartTime(i);
    stream.ground_truth.push_back({t, simulator.PoseAt(t)});
  }
  stream.scan = [&simulator](std::size_t i) { return simulator.SimulateScan(static_cast<int>(i)); };
  if (simulator.has_actors()) {
    stream.labelled_scan = [&simulator](std::size_t i, std::vector<std::uint8_t>& truth) {
      return simulator.SimulateScan(static_cast<int>(i), &truth);
    };
  }
  return stream;
}

ScanStream SequenceStream(const std::string& dir) {
  auto reader = std::make_shared<const io::SequenceReader>(io::SequenceReader::Open(dir));
  auto ground_truth = reader->ReadGroundTruth();
  if (!ground_truth) throw io::IoError(dir + ": no gt.tum");
  if (ground_truth->size() != reader->size()) {
    throw io::IoError(dir + ": gt.tum has " + std::to_string(ground_truth->size()) + " poses for " +
                      std::to_string(reader->size()) + " scans");
  }
  ScanStream stream;
  stream.sensor = reader->meta().sensor;
  stream.model = reader->meta().model;
  stream.ground_truth = std::move(*ground_truth);
  stream.scan = [reader](std::size_t i) { return reader->ReadScan(i); };
  return stream;
}

ScanRecord ToRecord(const OdometryResult& r) {
  ScanRecord record;
  record.stamp = r.stamp;
  record.T_world_sensor = r.T_world_sensor;
  record.status = r.status;
  record.timings = r.timings;
  record.map_points = r.map_points;
  record.iterations = r.iterations;
  record.searched_points = r.searched_points;
  record.num_correspondences = r.num_correspondences;
  record.alpha = r.alpha;
  record.eigenvalues = r.degeneracy.eigenvalues;
  record.degenerate = r.iterations > 0 && r.degeneracy.AnyDegenerate();
  record.class_counts = r.class_counts;
  return record;
}

std::vector<io::StampedPose> ModeTrace::Estimate() const {
  std::vector<io::StampedPose> estimate;
  estimate.reserve(scans.size());
  for (const ScanRecord& r : scans) estimate.push_back({r.stamp, r.T_world_sensor});
  return estimate;
}

MovingLabelScore ModeTrace::MovingLabels() const {
  MovingLabelScore sum;
  for (const ScanRecord& r : scans) sum += r.moving_labels;
  return sum;
}

std::vector<ModeTrace> StreamModes(const ScanStream& stream,
                                   const std::vector<OdometryConfig>& configs,
                                   const std::function<void(const Scan&)>& on_scan,
                                   const std::function<void(std::size_t)>& progress) {
  std::vector<std::unique_ptr<OdometryPipeline>> pipelines;
  std::vector<FeatureExtractor> extractors;  // which points each pipeline keeps
  std::vector<ModeTrace> traces(configs.size());
  for (std::size_t m = 0; m < configs.size(); ++m) {
    pipelines.push_back(std::make_unique<OdometryPipeline>(configs[m], stream.model));
    extractors.emplace_back(configs[m].preprocess, stream.model);
    traces[m].mode = std::string(Name(configs[m].registration.mode));
    traces[m].scans.reserve(stream.size());
  }
  std::vector<std::uint8_t> truth;
  for (std::size_t i = 0; i < stream.size(); ++i) {
    const Scan scan = stream.labelled_scan ? stream.labelled_scan(i, truth) : stream.scan(i);
    for (std::size_t m = 0; m < pipelines.size(); ++m) {
      const std::uint64_t allocations_before = HeapAllocations();
      const OdometryResult result = pipelines[m]->Process(scan);
      const std::uint64_t allocations = HeapAllocations() - allocations_before;
      traces[m].scans.push_back(ToRecord(result));
      traces[m].scans.back().allocations = allocations;
      if (stream.labelled_scan) {
        traces[m].scans.back().moving_labels =
            ScoreMovingLabels(truth, extractors[m].KeptPoints(scan), result.labels);
      }
    }
    if (on_scan) on_scan(scan);
    if (progress) progress(i + 1);
  }
  return traces;
}

TrajectoryErrors EvaluateEstimate(const std::vector<io::StampedPose>& ground_truth,
                                  const std::vector<io::StampedPose>& estimate) {
  const eval::EvaluateOptions options;
  const eval::TrajectoryMetrics metrics = eval::EvaluateTrajectories(ground_truth, estimate, options);
  TrajectoryErrors errors;
  errors.ape_rmse = metrics.ape.rmse;
  errors.ape_max = metrics.ape.max;
  errors.rpe_rmse = metrics.rpe.rmse;
  errors.drift_percent = metrics.drift_percent;
  errors.median_frame_m = metrics.rpe.median;
  errors.noise_worst_ratio = metrics.rpe_tail.gaussian_median;
  errors.noise_worst_ratio_p95 = metrics.rpe_tail.gaussian_p95;
  errors.pairs = metrics.pairs;
  const eval::MatchedTrajectories matched =
      eval::AssociateByTime(ground_truth, estimate, options.max_time_diff);
  errors.frame_errors = eval::RpeTranslationErrors(matched);
  for (std::size_t k = 0; k < errors.frame_errors.size(); ++k) {
    if (errors.frame_errors[k] > errors.worst_frame_m) {
      errors.worst_frame_m = errors.frame_errors[k];
      errors.worst_frame_index = k + 1;
    }
  }
  return errors;
}

double ProcStatusMiB(const char* key) {
  std::ifstream status("/proc/self/status");
  const std::size_t key_length = std::strlen(key);
  std::string line;
  while (std::getline(status, line)) {
    if (line.compare(0, key_length, key) == 0 && line.size() > key_length && line[key_length] == ':') {
      return std::strtod(line.c_str() + key_length + 1, nullptr) / 1024.0;  // "NNN kB"
    }
  }
  return 0.0;
}

}  // namespace dammloam::bench
