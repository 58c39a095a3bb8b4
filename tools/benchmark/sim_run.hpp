#pragma once
// Runs the odometry pipeline over an in-memory simulated sequence and summarises accuracy and
// per-stage timings. Shared by the benchmark and the integration tests.
#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/geometry/scan.hpp"
#include "core/odometry/odometry_config.hpp"
#include "core/odometry/odometry_result.hpp"
#include "io/tum.hpp"
#include "tools/benchmark/moving_label_score.hpp"
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
// The first `num_scans` scans of any simulator (a scene or a preset), with ground truth at
// each scan start; scene and sensor names are left to the caller.
SimSequence RecordSequence(const sim::Simulator& simulator, int num_scans);

struct Percentiles {
  double median = 0.0;
  double p95 = 0.0;
  double p99 = 0.0;
  double max = 0.0;
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

// ---- Streaming runs: full-length sequences that are never held in memory as a whole ----

// Scans produced one at a time (simulated on demand or read from a sequence directory) plus the
// ground truth at every scan start (cheap: no ray casting).
struct ScanStream {
  std::string sensor;
  SensorModel model;
  std::vector<io::StampedPose> ground_truth;  // one per scan, stamp = scan start
  std::function<Scan(std::size_t)> scan;      // scan i, t_start = ground_truth[i].t
  // Scan i with its per-point truth (sim::PointLabel); set only where the scene has actors.
  std::function<Scan(std::size_t, std::vector<std::uint8_t>& truth)> labelled_scan;
  std::size_t size() const { return ground_truth.size(); }
};

// The first `num_scans` scans of a simulator's run (the simulator must outlive the stream).
ScanStream SimulatedStream(const sim::Simulator& simulator, int num_scans);
// A sequence directory with gt.tum (io::SequenceReader; throws io::IoError if broken or without
// ground truth). Points come back rounded to float32, as every sequence reader sees them.
ScanStream SequenceStream(const std::string& dir);

// What is kept of one scan of one mode (no points).
struct ScanRecord {
  double stamp = 0.0;
  Eigen::Isometry3d T_world_sensor = Eigen::Isometry3d::Identity();
  OdometryStatus status = OdometryStatus::kOk;
  StageTimings timings;
  std::size_t map_points = 0;
  int iterations = 0;
  std::size_t searched_points = 0;  // map lookups: the search's work, whatever the machine's load
  std::uint32_t num_correspondences = 0;
  double alpha = 0.0;
  Eigen::Vector3d eigenvalues = Eigen::Vector3d::Zero();
  bool degenerate = false;  // registered with at least one degenerate direction
  ClassCounts class_counts{};
  MovingLabelScore moving_labels;  // against the stream's truth (empty without one)
  // Heap allocations during Process (HeapAllocations(); 0 where not counted).
  std::uint64_t allocations = 0;
};
ScanRecord ToRecord(const OdometryResult& result);

struct ModeTrace {
  std::string mode;
  std::vector<ScanRecord> scans;
  std::vector<io::StampedPose> Estimate() const;
  MovingLabelScore MovingLabels() const;  // summed over the scans
};

// Feeds every scan of the stream, produced once, to one fresh OdometryPipeline per config in
// turn (each gets its own copy), so all modes see identical scans under the same machine load.
// `on_scan` (optional) sees each scan after the pipelines, e.g. to write it to disk. `progress`
// (optional) is called after every scan with the number of scans done.
std::vector<ModeTrace> StreamModes(const ScanStream& stream,
                                   const std::vector<OdometryConfig>& configs,
                                   const std::function<void(const Scan&)>& on_scan = {},
                                   const std::function<void(std::size_t)>& progress = {});

// Accuracy of one estimated trajectory against ground truth (eval::EvaluateTrajectories, as
// dammloam-evaluate computes it). A frame error is the translation error of one relative pose
// (scan i-1 to scan i) against the ground truth's: the per-pair RPE.
struct TrajectoryErrors {
  double ape_rmse = 0.0;  // metres, SE(3)-aligned
  double ape_max = 0.0;   // worst single aligned pose
  double rpe_rmse = 0.0;
  double drift_percent = 0.0;
  double median_frame_m = 0.0;
  double worst_frame_m = 0.0;
  std::size_t worst_frame_index = 0;  // the later scan of the worst pair
  // Worst over median frame for Gaussian frame errors of this run's covariance (median and 95th
  // percentile over draws, eval::AnalyseFrameTail): what the frame noise alone gives.
  double noise_worst_ratio = 0.0;
  double noise_worst_ratio_p95 = 0.0;
  std::size_t pairs = 0;
  std::vector<double> frame_errors;   // per consecutive matched pair
};
// Throws std::invalid_argument when fewer than 2 poses pair up by time.
TrajectoryErrors EvaluateEstimate(const std::vector<io::StampedPose>& ground_truth,
                                  const std::vector<io::StampedPose>& estimate);

// Resident set size (VmRSS) and its peak (VmHWM) of this process from /proc/self/status, MiB;
// 0 where unavailable.
double ProcStatusMiB(const char* key);

}  // namespace dammloam::bench
