#include "tools/evaluate/metrics_report.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <nlohmann/json.hpp>

namespace dammloam::eval {
namespace {

using nlohmann::json;

json StatsJson(const ErrorStats& s) {
  return {{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median}, {"std", s.std},
          {"min", s.min},   {"max", s.max},   {"sse", s.sse},       {"count", s.count}};
}

std::string StatsRow(const char* name, const ErrorStats& s) {
  char line[160];
  std::snprintf(line, sizeof(line), "%-8s %10.4f %10.4f %10.4f %10.4f %10.4f %10.4f %6zu\n", name,
                s.rmse, s.mean, s.median, s.std, s.min, s.max, s.count);
  return line;
}

}  // namespace

std::string FormatTable(const TrajectoryMetrics& m) {
  std::string out;
  char line[200];
  std::snprintf(line, sizeof(line), "pairs: %zu (unmatched: %zu gt, %zu est)\n", m.pairs,
                m.unmatched_gt, m.unmatched_est);
  out += line;
  std::snprintf(line, sizeof(line), "%-8s %10s %10s %10s %10s %10s %10s %6s\n", "[m]", "rmse",
                "mean", "median", "std", "min", "max", "n");
  out += line;
  out += StatsRow("APE", m.ape);
  out += StatsRow("RPE", m.rpe);
  if (m.rpe_tail.frames > 0) {
    std::snprintf(line, sizeof(line),
                  "worst frame: %.2fx the median frame; Gaussian frames of this covariance: %.2fx "
                  "(95%%: %.2fx, %.0f%% of draws at least as far)\n",
                  m.rpe_tail.worst_over_median, m.rpe_tail.gaussian_median, m.rpe_tail.gaussian_p95,
                  100.0 * m.rpe_tail.gaussian_share_at_least);
    out += line;
  }
  std::snprintf(line, sizeof(line), "tracked steps (< %.2g m and %.2g deg): %zu of %zu (%.1f %%)\n",
                kTrackedStepMetres, kTrackedStepDegrees, m.tracked_steps, m.steps,
                m.steps ? 100.0 * double(m.tracked_steps) / double(m.steps) : 0.0);
  out += line;
  std::snprintf(line, sizeof(line), "path length: %.3f m, end drift: %.4f m (%.3f %%)\n",
                m.path_length_m, m.end_drift_m, m.drift_percent);
  out += line;
  const Eigen::Vector3d t = m.alignment.translation();
  const double angle_deg = Eigen::AngleAxisd(m.alignment.rotation()).angle() * 180.0 / std::numbers::pi;
  std::snprintf(line, sizeof(line), "alignment (gt <- est): t = [%.4f, %.4f, %.4f] m, rotation %.4f deg\n",
                t.x(), t.y(), t.z(), angle_deg);
  out += line;
  return out;
}

std::string FormatJson(const TrajectoryMetrics& m) {
  const Eigen::Quaterniond q(m.alignment.rotation());
  const Eigen::Vector3d t = m.alignment.translation();
  const json root = {
      {"ape", StatsJson(m.ape)},
      {"rpe", StatsJson(m.rpe)},
      {"rpe_tail",
       {{"frames", m.rpe_tail.frames},
        {"worst_over_median", m.rpe_tail.worst_over_median},
        {"gaussian_median", m.rpe_tail.gaussian_median},
        {"gaussian_p95", m.rpe_tail.gaussian_p95},
        {"gaussian_share_at_least", m.rpe_tail.gaussian_share_at_least}}},
      {"drift_percent", m.drift_percent},
      {"end_drift_m", m.end_drift_m},
      {"path_length_m", m.path_length_m},
      {"pairs", m.pairs},
      {"tracked_steps", m.tracked_steps},
      {"steps", m.steps},
      {"unmatched_gt", m.unmatched_gt},
      {"unmatched_est", m.unmatched_est},
      {"alignment",
       {{"translation", {t.x(), t.y(), t.z()}}, {"quaternion_xyzw", {q.x(), q.y(), q.z(), q.w()}}}},
  };
  return root.dump(2);
}

}  // namespace dammloam::eval
