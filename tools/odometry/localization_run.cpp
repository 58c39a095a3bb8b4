// Localization mode: each scan is deskewed by the odometry pipeline, then located in a saved map
// (relocalize until found, then track). The saved map is never modified.
#include <cstdio>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include "core/backend/localizer.hpp"
#include "core/odometry/pipeline.hpp"
#include "io/backend_config_yaml.hpp"
#include "io/config_yaml.hpp"
#include "io/bag/scan_source.hpp"
#include "io/mapstore/map_store.hpp"
#include "tools/odometry/runner.hpp"

namespace dammloam::tools {

int RunLocalization(const RunnerOptions& o) {
  // Load the map first: a corrupt map should fail before anything else happens.
  const backend::MapData map = mapstore::LoadMap(o.load_map);
  const std::unique_ptr<io::ScanSource> source = OpenSource(o);
  const OdometryConfig config =
      o.config.empty() ? OdometryConfig{} : io::LoadOdometryConfig(o.config);
  io::ValidateOdometryConfig(config);
  const backend::BackendParameters backend_parameters =
      o.backend_config.empty() ? backend::BackendParameters{}
                               : io::LoadBackendConfig(o.backend_config);
  const std::size_t n = ScansToRun(*source, o.max_scans);

  OdometryPipeline pipeline(config, source->model());
  backend::Localizer localizer(map, backend_parameters.localizer);
  const bool progress = !o.quiet && isatty(STDERR_FILENO);

  std::vector<io::StampedPose> odometry, localized;
  std::vector<double> inlier_ratios;
  std::size_t i = 0;
  for (std::optional<Scan> scan; (o.max_scans == 0 || i < o.max_scans) && (scan = source->Next());
       ++i) {
    const double t_start = scan->t_start;
    const OdometryResult result = pipeline.Process(std::move(*scan));
    odometry.push_back({t_start, result.T_world_sensor});
    if (result.deskewed_points.empty()) continue;
    if (const auto pose = localizer.Localize(result.deskewed_points)) {
      localized.push_back({t_start, pose->T_map_sensor});
      inlier_ratios.push_back(pose->inlier_ratio);
    }
    if (progress && n > 0) {
      std::fprintf(stderr, "\r%zu/%zu scans, %zu localized  ", i + 1, n, localized.size());
    } else if (progress) {  // a source that cannot tell its length (raw packet bags)
      std::fprintf(stderr, "\r%zu scans, %zu localized  ", i + 1, localized.size());
    }
  }
  if (progress) std::fprintf(stderr, "\n");
  if (i == 0) throw std::runtime_error(o.sequence.string() + ": no scans");

  io::WriteTum(o.out, localized);
  if (!o.odometry_out.empty()) io::WriteTum(o.odometry_out, odometry);
  if (localized.empty()) {
    throw std::runtime_error("no scan of " + o.sequence.string() + " could be localized in map " +
                             o.load_map.string());
  }
  if (o.quiet) return 0;
  spdlog::info("localization: {} of {} scans localized in {} ({} map points), median inlier "
               "ratio {:.2f} -> {}", localized.size(), i, o.load_map.string(),
               localizer.NumMapPoints(), Median(inlier_ratios), o.out.string());
  if (const auto gt = source->ReadGroundTruth()) {
    LogMetrics("odometry", *gt, odometry);
    LogMetrics("localized", *gt, localized);
  }
  return 0;
}

}  // namespace dammloam::tools
