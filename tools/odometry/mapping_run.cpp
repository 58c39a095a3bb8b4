// Mapping mode: odometry, then the loop-closing back-end fed after every scan (offline, so its
// Process() runs inline instead of on a back-end thread).
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include "core/backend/loop_closing_backend.hpp"
#include "core/odometry/pipeline.hpp"
#include "io/backend_config_yaml.hpp"
#include "io/config_yaml.hpp"
#include "io/pcd/labelled_pcd.hpp"
#include "io/bag/scan_source.hpp"
#include "io/mapstore/map_store.hpp"
#include "tools/odometry/inertial_input.hpp"
#include "tools/odometry/loop_event_json.hpp"
#include "tools/odometry/mcap_output.hpp"
#include "tools/odometry/runner.hpp"
#include "tools/odometry/stats_csv.hpp"

namespace dammloam::tools {
namespace {

io::LabelledCloud MapCloud(const VoxelHashMap& map) {
  io::LabelledCloud cloud;
  for (const MapPoint& p : map.Points()) {
    cloud.points.push_back(p.position);
    cloud.labels.push_back(p.label);
    cloud.normals.push_back(p.normal.cast<double>());
  }
  return cloud;
}

// Fail before a long run rather than after it: SaveMap only replaces map directories.
void CheckSaveTarget(const std::filesystem::path& dir) {
  if (dir.empty() || !std::filesystem::exists(dir)) return;
  if (!std::filesystem::is_directory(dir) || !std::filesystem::exists(dir / "map.json")) {
    throw io::IoError(dir.string() + ": exists and is not a map directory (no map.json); " +
                      "refusing to overwrite it");
  }
}

// Writes every loop event as a JSON line and counts them.
class EventLog {
 public:
  explicit EventLog(const std::filesystem::path& file) {
    if (file.empty()) return;
    out_.open(file);
    if (!out_) throw io::IoError(file.string() + ": cannot open for writing");
  }
  void Write(const std::vector<backend::LoopEvent>& events) {
    for (const backend::LoopEvent& e : events) {
      (e.accepted ? accepted : rejected) += 1;
      if (out_.is_open()) out_ << LoopEventJsonLine(e) << '\n';
    }
  }
  std::size_t accepted = 0, rejected = 0;

 private:
  std::ofstream out_;
};

// One corrected pose per odometry pose. Scans the back-end never saw (not registered) get the
// correction of the scan before them, so the output still has one pose per scan.
std::vector<io::StampedPose> CorrectedTrajectory(const backend::LoopClosingBackend& backend,
                                                 const std::vector<io::StampedPose>& odometry,
                                                 const std::vector<std::uint64_t>& scan_indices) {
  std::vector<io::StampedPose> corrected;
  corrected.reserve(odometry.size());
  Eigen::Isometry3d correction = Eigen::Isometry3d::Identity();
  for (std::size_t i = 0; i < odometry.size(); ++i) {
    if (const auto T = backend.CorrectedPoseOf(scan_indices[i], odometry[i].T)) {
      correction = *T * odometry[i].T.inverse();
      corrected.push_back({odometry[i].t, *T});
    } else {
      corrected.push_back({odometry[i].t, Normalized(correction * odometry[i].T)});
    }
  }
  return corrected;
}

}  // namespace

int RunMapping(const RunnerOptions& o) {
  CheckSaveTarget(o.save_map);
  const std::unique_ptr<io::ScanSource> source = OpenSource(o);
  const OdometryConfig config =
      o.config.empty() ? OdometryConfig{} : io::LoadOdometryConfig(o.config);
  io::ValidateOdometryConfig(config);
  const backend::BackendParameters backend_parameters =
      o.backend_config.empty() ? backend::BackendParameters{}
                               : io::LoadBackendConfig(o.backend_config);
  const std::size_t n = ScansToRun(*source, o.max_scans);
  // The IMU's gyroscope drives the odometry's rotation, the wheel odometry its translation
  // (issue 55).
  const InertialInput inertial = ReadInertialInput(o);

  OdometryPipeline pipeline(config, source->model());
  ImuFeed imu_feed(inertial, pipeline.odometry());
  WheelFeed wheel_feed(inertial, pipeline.odometry());
  // Without loop closure the back-end is only needed to build a map for --save-map; it then
  // keeps keyframes but verifies no loop candidate.
  std::unique_ptr<backend::LoopClosingBackend> backend;
  if (o.loop_closure || !o.save_map.empty()) {
    backend::BackendConfig backend_config = backend_parameters.loop_closing;
    if (!o.loop_closure) backend_config.max_verifications_per_keyframe = 0;
    backend = std::make_unique<backend::LoopClosingBackend>(backend_config);
    backend->SetSensor(source->model());
  }
  EventLog events(o.events);
  std::optional<McapOutput> mcap;
  if (!o.mcap.empty()) mcap.emplace(o.mcap, source->model().scan_period, o.mcap_compression);
  const auto handle_loops = [&](const std::vector<backend::LoopEvent>& found) {
    events.Write(found);
    if (mcap) mcap->AddLoops(found);
  };
  std::optional<StatsCsv> stats;
  if (!o.stats.empty()) stats.emplace(o.stats);
  const bool progress = !o.quiet && isatty(STDERR_FILENO);

  std::vector<io::StampedPose> odometry;
  std::vector<std::uint64_t> scan_indices;
  std::vector<double> total_ms;
  std::size_t not_registered = 0;
  std::size_t i = 0;
  for (std::optional<Scan> scan; (o.max_scans == 0 || i < o.max_scans) && (scan = source->Next());
       ++i) {
    const double t_start = scan->t_start;
    imu_feed.Through(t_start + source->model().scan_period);
    wheel_feed.Through(t_start + source->model().scan_period);
    const OdometryResult result = pipeline.Process(std::move(*scan));
    imu_feed.Count(result);
    wheel_feed.Count(result);
    odometry.push_back({t_start, result.T_world_sensor});
    scan_indices.push_back(result.scan_index);
    total_ms.push_back(result.timings.total_ms);
    if (!Registered(result.status)) {
      ++not_registered;
      if (!o.quiet) spdlog::warn("scan {}: {}", i, Name(result.status));
    } else if (backend) {
      backend->AddScan(result);
    }
    if (backend && Registered(result.status)) handle_loops(backend->Process());
    if (mcap) {
      mcap->AddScan(result, backend && o.loop_closure ? backend->MapFromOdom()
                                                      : Eigen::Isometry3d::Identity());
    }
    if (stats) stats->Write(result);
    if (progress) {
      // n is 0 when the source cannot tell its length (raw packet bags).
      if (n > 0) {
        std::fprintf(stderr, "\r%zu/%zu scans  %.1f ms  ", i + 1, n, result.timings.total_ms);
      } else {
        std::fprintf(stderr, "\r%zu scans  %.1f ms  ", i + 1, result.timings.total_ms);
      }
    }
  }
  if (progress) std::fprintf(stderr, "\n");
  if (i == 0) throw std::runtime_error(o.sequence.string() + ": no scans");

  std::vector<io::StampedPose> corrected;
  if (backend) {
    handle_loops(backend->Process());
    corrected = CorrectedTrajectory(*backend, odometry, scan_indices);
  }
  if (mcap) mcap->Close();
  io::WriteTum(o.out, o.loop_closure ? corrected : odometry);
  if (!o.odometry_out.empty()) io::WriteTum(o.odometry_out, odometry);
  if (!o.map.empty()) io::WriteLabelledPcd(o.map, MapCloud(pipeline.odometry().local_map()));
  if (!o.save_map.empty()) {
    const backend::MapData map = backend->ExportMap();
    mapstore::SaveMap(o.save_map, map);
    if (!o.quiet) {
      spdlog::info("map: {} keyframes, {} loops, {} points ({} left out as vacated) -> {}",
                   map.keyframes.size(), map.loops.size(), map.global_points.size(), map.vacated_points,
                   o.save_map.string());
    }
  }
  if (o.quiet) return 0;
  spdlog::info("{} scans, {} not registered, median {:.1f} ms per scan -> {}", i, not_registered,
               Median(total_ms), o.out.string());
  imu_feed.Log();
  wheel_feed.Log();
  if (o.loop_closure) {
    spdlog::info("loop closure: {} keyframes, {} loop candidates, {} accepted, {} pose-graph "
                 "solves", backend->NumKeyframes(), events.accepted + events.rejected,
                 events.accepted, backend->NumOptimizations());
  }
  if (const auto gt = source->ReadGroundTruth()) {
    const auto before = LogMetrics("odometry", *gt, odometry);
    const auto after = o.loop_closure ? LogMetrics("corrected", *gt, corrected) : std::nullopt;
    if (before && after && *before > 0.0) {
      spdlog::info("loop closure changed APE RMSE by {:+.1f} % ({:.4f} -> {:.4f} m)",
                   100.0 * (*after / *before - 1.0), *before, *after);
    }
  }
  return 0;
}

}  // namespace dammloam::tools
