// dammloam-odometry SEQUENCE_DIR --out poses.tum [--config cfg.yaml] [--map map.pcd]
//                   [--stats stats.csv] [--max-scans N] [--quiet]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include "core/odometry/pipeline.hpp"
#include "tools/common/config_yaml.hpp"
#include "tools/common/pcd/labelled_pcd.hpp"
#include "tools/common/sequence_io.hpp"
#include "tools/evaluate/trajectory_metrics.hpp"
#include "tools/odometry/stats_csv.hpp"

namespace {

struct Options {
  std::filesystem::path sequence, out, config, map, stats;
  std::size_t max_scans = 0;
  bool quiet = false;
};

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

dammloam::io::LabelledCloud MapCloud(const dammloam::VoxelHashMap& map) {
  dammloam::io::LabelledCloud cloud;
  for (const dammloam::MapPoint& p : map.Points()) {
    cloud.points.push_back(p.position);
    cloud.labels.push_back(p.label);
    cloud.normals.push_back(p.normal.cast<double>());
  }
  return cloud;
}

int Run(const Options& o) {
  using namespace dammloam;
  const io::SequenceReader reader = io::SequenceReader::Open(o.sequence);
  const OdometryConfig config =
      o.config.empty() ? OdometryConfig{} : io::LoadOdometryConfig(o.config);
  io::ValidateOdometryConfig(config);
  const std::size_t n = o.max_scans > 0 ? std::min(o.max_scans, reader.size()) : reader.size();
  if (n == 0) throw std::runtime_error(o.sequence.string() + ": sequence has no scans");

  OdometryPipeline pipeline(config, reader.meta().model);
  std::optional<tools::StatsCsv> stats;
  if (!o.stats.empty()) stats.emplace(o.stats);
  const bool progress = !o.quiet && isatty(STDERR_FILENO);

  std::vector<io::StampedPose> trajectory;
  std::vector<double> total_ms;
  std::size_t not_registered = 0;
  for (std::size_t i = 0; i < n; ++i) {
    Scan scan = reader.ReadScan(i);
    scan.t_start = reader.times()[i];
    const OdometryResult result = pipeline.Process(std::move(scan));
    trajectory.push_back({reader.times()[i], result.T_world_sensor});
    total_ms.push_back(result.timings.total_ms);
    if (!Registered(result.status)) {
      ++not_registered;
      if (!o.quiet) spdlog::warn("scan {}: {}", i, Name(result.status));
    }
    if (stats) stats->Write(result);
    if (progress) {
      std::fprintf(stderr, "\r%zu/%zu scans  %.1f ms  ", i + 1, n, result.timings.total_ms);
    }
  }
  if (progress) std::fprintf(stderr, "\n");

  io::WriteTum(o.out, trajectory);
  if (!o.map.empty()) io::WriteLabelledPcd(o.map, MapCloud(pipeline.odometry().local_map()));
  if (!o.quiet) {
    spdlog::info("{} scans, {} not registered, median {:.1f} ms per scan -> {}", n,
                 not_registered, Median(total_ms), o.out.string());
  }
  if (const auto gt = reader.ReadGroundTruth(); gt && !o.quiet) {
    const eval::TrajectoryMetrics m = eval::EvaluateTrajectories(*gt, trajectory);
    spdlog::info("vs gt.tum: APE RMSE {:.3f} m, RPE RMSE {:.3f} m, drift {:.2f} %", m.ape.rmse,
                 m.rpe.rmse, m.drift_percent);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"DAMM-LOAM odometry over a sequence directory"};
  Options o;
  app.add_option("sequence", o.sequence, "sequence directory (or KITTI-layout folder)")->required();
  app.add_option("--out", o.out, "output trajectory (TUM)")->required();
  app.add_option("--config", o.config, "odometry YAML config (see deploy/config/odometry.yaml)");
  app.add_option("--map", o.map, "write the final local map as labelled PCD");
  app.add_option("--stats", o.stats, "write per-scan statistics CSV");
  app.add_option("--max-scans", o.max_scans, "process at most N scans");
  app.add_flag("--quiet", o.quiet, "no progress, warnings or summary");
  CLI11_PARSE(app, argc, argv);
  try {
    return Run(o);
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}
