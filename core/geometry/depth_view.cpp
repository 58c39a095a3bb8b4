#include "core/geometry/depth_view.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace dammloam {

namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

// Elevation span and spacing of the sensor's beams: from its vertical angles when known, else a
// +-22.5 deg OS1-like span over its ring count.
void ElevationGrid(const SensorModel& sensor, double& el_min, double& el_max, double& step) {
  const auto& angles = sensor.vertical_angles_deg;
  if (angles.size() >= 2) {
    const auto [lo, hi] = std::minmax_element(angles.begin(), angles.end());
    el_min = *lo * kDegToRad;
    el_max = *hi * kDegToRad;
  } else {
    el_min = -22.5 * kDegToRad;
    el_max = 22.5 * kDegToRad;
  }
  const int rings = std::max(2, angles.size() >= 2 ? static_cast<int>(angles.size()) : sensor.rings);
  step = std::max((el_max - el_min) / (rings - 1), 0.1 * kDegToRad);
}

}  // namespace

DepthView::DepthView(const Config& config, const SensorModel& sensor,
                     const std::vector<Eigen::Vector3d>& points_sensor,
                     const Eigen::Isometry3d& T_world_sensor)
    : T_world_sensor_(T_world_sensor), T_sensor_world_(T_world_sensor.inverse()) {
  double el_max = 0.0;
  ElevationGrid(sensor, el_min_, el_max, el_step_);
  // Half a beam spacing of margin at both ends: the outermost rings fall inside the grid.
  el_min_ -= 0.5 * el_step_;
  rows_ = static_cast<int>(std::ceil((el_max + 0.5 * el_step_ - el_min_) / el_step_));
  const double sensor_step = 2.0 * std::numbers::pi / std::max(sensor.columns, 1);
  az_step_ = std::max(config.columns_per_cell * sensor_step, config.min_azimuth_step_deg * kDegToRad);
  cols_ = static_cast<int>(std::ceil(2.0 * std::numbers::pi / az_step_));
  az_step_ = 2.0 * std::numbers::pi / cols_;
  inv_az_step_ = 1.0 / az_step_;
  inv_el_step_ = 1.0 / el_step_;
  nearest_.assign(static_cast<std::size_t>(rows_) * cols_, 0.0f);
  for (const Eigen::Vector3d& q : points_sensor) {
    int r = 0, c = 0;
    if (!CellOf(q, r, c)) continue;
    const float range = static_cast<float>(q.norm());
    if (config.point_radius > 0.0) {
      Spread(r, c, range, config.point_radius);
    } else {
      Fill(r, c, range);
    }
  }
}

void DepthView::Spread(int row, int col, float range, double radius) {
  // Half a cell is always covered; a point nearer than its radius covers at most a quarter turn.
  constexpr int kMaxCells = 24;
  const double angle = std::atan2(radius, static_cast<double>(range));
  const int dr = std::min(kMaxCells, static_cast<int>(angle * inv_el_step_));
  const int dc = std::min({kMaxCells, (cols_ - 1) / 2, static_cast<int>(angle * inv_az_step_)});
  for (int r = std::max(0, row - dr); r <= std::min(rows_ - 1, row + dr); ++r) {
    for (int c = col - dc; c <= col + dc; ++c) Fill(r, WrappedColumn(c), range);
  }
}

// Every point of a scan and every point judged against a view lands here. The arctangents stay
// the C library's: a polynomial one (1e-7 rad) moved a few points across cell boundaries and
// sent one people preset's run from 0.019 m to 79 m (docs/measurements.md, 2026-11-29).
bool DepthView::CellOf(const Eigen::Vector3d& q, int& row, int& col) const {
  const double xy = std::sqrt(q.x() * q.x() + q.y() * q.y());
  if (!(xy > 0.0)) return false;
  row = static_cast<int>(std::floor((std::atan2(q.z(), xy) - el_min_) * inv_el_step_));
  if (row < 0 || row >= rows_) return false;
  // The azimuth plus pi lies in [0, 2 pi]: only its upper end wraps.
  col = static_cast<int>((std::atan2(q.y(), q.x()) + std::numbers::pi) * inv_az_step_);
  col = WrappedColumn(col);
  return true;
}

bool DepthView::SeesThrough(const Eigen::Vector3d& p_world, double margin) const {
  return SeesThroughInViewFrame(T_sensor_world_ * p_world, margin);
}

bool DepthView::SeesThroughInViewFrame(const Eigen::Vector3d& q, double margin) const {
  return Through(q, margin, false);
}

bool DepthView::SeesThroughOrNothingInViewFrame(const Eigen::Vector3d& q, double margin) const {
  return Through(q, margin, true);
}

bool DepthView::Through(const Eigen::Vector3d& q, double margin, bool empty_passes) const {
  int row = 0, col = 0;
  if (!CellOf(q, row, col)) return false;
  const float needed = static_cast<float>(q.norm() + margin);
  for (int dr = -1; dr <= 1; ++dr) {
    const int r = row + dr;
    if (r < 0 || r >= rows_) return false;
    for (int dc = -1; dc <= 1; ++dc) {
      const int c = WrappedColumn(col + dc);
      const float nearest = nearest_[static_cast<std::size_t>(r) * cols_ + c];
      if (nearest == 0.0f ? !empty_passes : nearest <= needed) return false;
    }
  }
  return true;
}

bool DepthView::SeesSurfaceInViewFrame(const Eigen::Vector3d& q, double margin) const {
  int row = 0, col = 0;
  if (!CellOf(q, row, col)) return false;
  const float nearest = nearest_[static_cast<std::size_t>(row) * cols_ + col];
  return nearest > 0.0f && std::abs(static_cast<double>(nearest) - q.norm()) <= margin;
}

bool DepthView::Hides(const Eigen::Vector3d& p_world, double margin) const {
  const Eigen::Vector3d q = T_sensor_world_ * p_world;
  int row = 0, col = 0;
  if (!CellOf(q, row, col)) return false;
  const float nearest = nearest_[static_cast<std::size_t>(row) * cols_ + col];
  return nearest > 0.0f && nearest < static_cast<float>(q.norm() - margin);
}

}  // namespace dammloam
