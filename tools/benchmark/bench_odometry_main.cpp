// dammloam-bench-odometry: accuracy and per-stage speed of the front end on simulated
// sequences, with the ablation (point-to-point, plane only, classes without degeneracy
// weights, full) in the same run so ratios are measured under the same machine load.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>

#include "tools/benchmark/sim_run.hpp"
#include "tools/common/config_yaml.hpp"

namespace {

using dammloam::RegistrationMode;
using dammloam::bench::Percentiles;
using dammloam::bench::RunSummary;

nlohmann::json ToJson(const Percentiles& p) { return {{"median", p.median}, {"p95", p.p95}}; }

nlohmann::json ToJson(const RunSummary& s) {
  return {{"mode", s.mode},
          {"ape_rmse_m", s.ape_rmse},
          {"rpe_rmse_m", s.rpe_rmse},
          {"registered", s.registered},
          {"median_iterations", s.median_iterations},
          {"degenerate_share", s.degenerate_share},
          {"ms",
           {{"features", ToJson(s.features_ms)},
            {"projection", ToJson(s.projection_ms)},
            {"normals", ToJson(s.normals_ms)},
            {"classification", ToJson(s.classification_ms)},
            {"deskew", ToJson(s.deskew_ms)},
            {"downsample", ToJson(s.downsample_ms)},
            {"registration", ToJson(s.registration_ms)},
            {"map_update", ToJson(s.map_update_ms)},
            {"total", ToJson(s.total_ms)}}}};
}

void PrintRow(const RunSummary& s, const RunSummary& baseline) {
  std::printf("  %-22s APE %7.3f  RPE %6.3f  | ms med/p95: feat %5.1f/%5.1f (%.1f+%.1f+%.1f)  "
              "reg %5.1f/%5.1f  map %4.1f  total %5.1f/%5.1f (x%.2f of p2p)  it %.0f  degen %3.0f%%\n",
              s.mode.c_str(), s.ape_rmse, s.rpe_rmse, s.features_ms.median, s.features_ms.p95,
              s.projection_ms.median, s.normals_ms.median, s.classification_ms.median,
              s.registration_ms.median, s.registration_ms.p95, s.map_update_ms.median,
              s.total_ms.median, s.total_ms.p95,
              baseline.total_ms.median > 0 ? s.total_ms.median / baseline.total_ms.median : 0.0,
              s.median_iterations, 100.0 * s.degenerate_share);
  std::fflush(stdout);
}

// Frame-to-frame motion error per scan, to see where tracking goes wrong.
void PrintPerScan(const dammloam::bench::SimSequence& seq, const RunSummary& run) {
  for (std::size_t i = 1; i < run.results.size(); ++i) {
    const auto& r = run.results[i];
    const Eigen::Isometry3d gt = seq.ground_truth[i - 1].T.inverse() * seq.ground_truth[i].T;
    const Eigen::Isometry3d est = run.estimate[i - 1].T.inverse() * run.estimate[i].T;
    const Eigen::Vector3d e = (gt.inverse() * est).translation();
    std::printf("    %3zu %-12s it %2d corr %5u alpha %.2f  gt dt (%6.3f %6.3f %6.3f)  err (%6.3f "
                "%6.3f %6.3f)  lambda (%.0f %.0f %.0f) classes u%u g%u r%u w%u e%u\n",
                i, std::string(dammloam::Name(r.status)).c_str(), r.iterations,
                r.num_correspondences, r.alpha, gt.translation().x(), gt.translation().y(),
                gt.translation().z(), e.x(), e.y(), e.z(), r.degeneracy.eigenvalues[0],
                r.degeneracy.eigenvalues[1], r.degeneracy.eigenvalues[2], r.class_counts[0],
                r.class_counts[1], r.class_counts[2], r.class_counts[3], r.class_counts[4]);
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Odometry benchmark with ablation on simulated sequences"};
  int scans = 100;
  std::vector<std::string> scenes{"corridor", "zigzag", "outdoor"};
  std::vector<std::string> sensors{"os1-64", "vlp-16"};
  std::vector<std::string> modes{"point_to_point", "plane_only", "classes_no_degeneracy",
                                 "full_remap", "full"};
  std::string json_path;
  std::string config_path;
  app.add_option("--config", config_path, "odometry YAML config (the mode is overridden)");
  std::uint64_t seed = 1;
  bool per_scan = false;
  bool no_remap = false;
  app.add_flag("--no-remap", no_remap, "full mode without solution remapping (weights only)");
  app.add_flag("--per-scan", per_scan, "print every scan's motion error (debugging)");
  app.add_option("--scans", scans, "scans per sequence")->check(CLI::Range(3, 100000));
  app.add_option("--scenes", scenes, "simulated scenes");
  app.add_option("--sensors", sensors, "simulated sensors");
  app.add_option("--modes", modes, "registration modes (first is the timing baseline)");
  app.add_option("--seed", seed, "simulator seed");
  app.add_option("--json", json_path, "write all numbers to this JSON file");
  CLI11_PARSE(app, argc, argv);
  dammloam::OdometryConfig base_config;
  try {
    if (!config_path.empty()) base_config = dammloam::io::LoadOdometryConfig(config_path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }

  nlohmann::json report = nlohmann::json::array();
  for (const std::string& scene_name : scenes) {
    const auto scene = dammloam::sim::ParseSceneKind(scene_name);
    if (!scene) {
      std::fprintf(stderr, "error: unknown scene '%s'\n", scene_name.c_str());
      return 2;
    }
    for (const std::string& sensor_name : sensors) {
      const auto sensor = dammloam::sim::MakeSensorSpec(sensor_name);
      if (!sensor) {
        std::fprintf(stderr, "error: unknown sensor '%s'\n", sensor_name.c_str());
        return 2;
      }
      const auto sequence = dammloam::bench::GenerateSequence(*scene, *sensor, scans, seed);
      std::printf("%s / %s, %d scans\n", scene_name.c_str(), sensor_name.c_str(), scans);
      std::vector<RunSummary> runs;
      for (const std::string& mode_name : modes) {
        const auto mode = dammloam::ParseRegistrationMode(mode_name);
        if (!mode) {
          std::fprintf(stderr, "error: unknown mode '%s'\n", mode_name.c_str());
          return 2;
        }
        dammloam::OdometryConfig config = base_config;
        config.registration.mode = *mode;
        if (no_remap) config.registration.remap_degenerate_directions = false;
        runs.push_back(dammloam::bench::RunPipeline(sequence, config));
        if (per_scan) PrintPerScan(sequence, runs.back());
        PrintRow(runs.back(), runs.front());
      }
      nlohmann::json entry{{"scene", scene_name}, {"sensor", sensor_name}, {"scans", scans}};
      for (const RunSummary& r : runs) entry["runs"].push_back(ToJson(r));
      report.push_back(entry);
    }
  }
  if (!json_path.empty()) {
    std::ofstream out(json_path);
    out << report.dump(2) << "\n";
    if (!out) {
      std::fprintf(stderr, "error: cannot write %s\n", json_path.c_str());
      return 1;
    }
  }
  return 0;
}
