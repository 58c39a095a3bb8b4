#include "core/backend/scan_context.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace dammloam::backend {

ScanContext MakeScanContext(const std::vector<Eigen::Vector3d>& points_sensor,
                            const ScanContextConfig& config) {
  ScanContext sc;
  sc.grid = Eigen::MatrixXf::Zero(config.rings, config.sectors);
  const double two_pi = 2.0 * std::numbers::pi;
  for (const Eigen::Vector3d& p : points_sensor) {
    if (!p.allFinite()) continue;
    const double range = std::sqrt(p.x() * p.x() + p.y() * p.y());  // hypot is ~10x slower
    if (range <= 1e-3 || range >= config.max_range) continue;
    double azimuth = std::atan2(p.y(), p.x());
    if (azimuth < 0.0) azimuth += two_pi;
    const int ring = std::min(config.rings - 1, static_cast<int>(range / config.max_range *
                                                                 config.rings));
    const int sector = std::min(config.sectors - 1,
                                static_cast<int>(azimuth / two_pi * config.sectors));
    // Heights below the assumed ground are clamped: a bin with any point must not read as empty.
    const float height = static_cast<float>(std::max(1e-3, p.z() + config.sensor_height));
    float& cell = sc.grid(ring, sector);
    cell = std::max(cell, height);
  }
  sc.ring_key = RingKey(sc.grid);
  return sc;
}

Eigen::VectorXf RingKey(const Eigen::MatrixXf& grid) {
  Eigen::VectorXf key(grid.rows());
  for (Eigen::Index r = 0; r < grid.rows(); ++r) {
    key(r) = static_cast<float>((grid.row(r).array() > 0.0f).count()) /
             static_cast<float>(std::max<Eigen::Index>(1, grid.cols()));
  }
  return key;
}

namespace {

// Mean (1 - cosine similarity) of query columns j against candidate columns (j + shift).
double ShiftedDistance(const Eigen::MatrixXf& query, const Eigen::VectorXf& query_norms,
                       const Eigen::MatrixXf& candidate, const Eigen::VectorXf& candidate_norms,
                       int shift) {
  const int sectors = static_cast<int>(query.cols());
  double sum = 0.0;
  int valid = 0;
  for (int j = 0; j < sectors; ++j) {
    const int k = (j + shift) % sectors;
    if (query_norms(j) <= 0.0f || candidate_norms(k) <= 0.0f) continue;
    const double cosine =
        query.col(j).dot(candidate.col(k)) / (query_norms(j) * candidate_norms(k));
    sum += 1.0 - cosine;
    ++valid;
  }
  // A shift that leaves almost nothing to compare is no evidence of a match.
  if (valid < std::max(1, sectors / 10)) return 1.0;
  return sum / valid;
}

}  // namespace

ScanContextMatch CompareScanContexts(const ScanContext& query, const ScanContext& candidate) {
  ScanContextMatch best;
  if (query.empty() || candidate.empty() || query.grid.rows() != candidate.grid.rows() ||
      query.grid.cols() != candidate.grid.cols()) {
    return best;
  }
  const Eigen::VectorXf query_norms = query.grid.colwise().norm();
  const Eigen::VectorXf candidate_norms = candidate.grid.colwise().norm();
  const int sectors = static_cast<int>(query.grid.cols());
  for (int shift = 0; shift < sectors; ++shift) {
    const double d =
        ShiftedDistance(query.grid, query_norms, candidate.grid, candidate_norms, shift);
    if (d < best.distance) {
      best.distance = d;
      best.shift = shift;
    }
  }
  // Query azimuth theta appears at theta + yaw in the candidate, i.e. T_candidate_query = Rz(yaw).
  double yaw = best.shift * 2.0 * std::numbers::pi / sectors;
  if (yaw > std::numbers::pi) yaw -= 2.0 * std::numbers::pi;
  best.yaw_rad = yaw;
  return best;
}

}  // namespace dammloam::backend
