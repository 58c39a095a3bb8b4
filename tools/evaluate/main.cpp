// dammloam-evaluate GT.tum EST.tum [--json] [--plot out.svg] [--max-time-diff 0.01]
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <iostream>
#include <stdexcept>

#include "io/io_error.hpp"
#include "io/tum.hpp"
#include "tools/evaluate/metrics_report.hpp"
#include "tools/evaluate/svg_plot.hpp"
#include "tools/evaluate/trajectory_metrics.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Trajectory accuracy: APE (SE(3)-aligned), RPE (1 frame) and end drift, as evo computes them"};
  std::string gt_file, est_file, plot_file;
  bool json = false;
  dammloam::eval::EvaluateOptions options;
  app.add_option("gt", gt_file, "ground-truth trajectory (TUM)")->required();
  app.add_option("est", est_file, "estimated trajectory (TUM)")->required();
  app.add_flag("--json", json, "print the metrics as one JSON object");
  app.add_option("--plot", plot_file, "write an SVG top view of both trajectories (aligned)");
  app.add_option("--max-time-diff", options.max_time_diff,
                 "max timestamp difference (s) when pairing poses")
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);

  // Logs go to stderr so that --json output on stdout stays machine-readable.
  auto log = spdlog::stderr_color_mt("evaluate");
  try {
    const auto gt = dammloam::io::ReadTum(gt_file);
    const auto est = dammloam::io::ReadTum(est_file);
    const auto metrics = dammloam::eval::EvaluateTrajectories(gt, est, options);
    std::cout << (json ? dammloam::eval::FormatJson(metrics) + "\n"
                       : dammloam::eval::FormatTable(metrics));
    if (!plot_file.empty()) {
      dammloam::eval::WriteTopViewSvg(plot_file, metrics.gt_positions,
                                      metrics.est_positions_aligned);
      log->info("wrote {}", plot_file);
    }
  } catch (const dammloam::io::IoError& e) {
    log->error("{}", e.what());
    return 1;
  } catch (const std::invalid_argument& e) {
    log->error("{} and {}: {}", gt_file, est_file, e.what());
    return 1;
  }
  return 0;
}
