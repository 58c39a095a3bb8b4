#pragma once
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "core/geometry/scan.hpp"

namespace dammloam {

// What space one scan's rays crossed: the nearest return per direction on a coarse spherical
// grid, with the pose the scan was taken from. A point of another scan that lies well short of
// every return around its direction sat in space this scan saw through, so whatever is there
// now was not there then (the visibility test of Removert and of free-space methods such as
// DUFOMap, here against one past scan instead of a volumetric map).
class DepthView {
 public:
  struct Config {
    // Cells a little wider than the sensor's own pixels, so every cell of a scanned row holds
    // a return; never finer than this.
    double min_azimuth_step_deg = 0.5;
    int columns_per_cell = 2;
    // Metres each point stands for. 0: a point fills its own cell. A cloud thinned to one point
    // per voxel (a keyframe's) leaves cells empty between its points; each point then fills
    // the cells its voxel would cover as seen from the sensor, so that the view is as closed as
    // the scan it came from. Spread points only shorten the nearest returns: never more seen
    // through than with the full scan.
    double point_radius = 0.0;
  };

  // points_sensor: the scan in the frame of T_world_sensor (deskewed).
  DepthView(const Config& config, const SensorModel& sensor,
            const std::vector<Eigen::Vector3d>& points_sensor,
            const Eigen::Isometry3d& T_world_sensor);

  // Whether every cell in the 3 x 3 block around the direction of p_world holds a return that
  // lies more than `margin` beyond p_world. Empty cells (sky, absorbed) say nothing, and the
  // block's nearest return decides, so a depth edge never counts as seen through.
  bool SeesThrough(const Eigen::Vector3d& p_world, double margin) const;
  // The same for a point already in this view's sensor frame (q = pose().inverse() * p_world),
  // for callers that moved a whole scan into the view's frame with one composed transform.
  bool SeesThroughInViewFrame(const Eigen::Vector3d& q, double margin) const;
  // The same, but an empty cell counts as seen through too: for a point the caller knows was
  // seen from farther away than it lies from this view, no return means nothing is there.
  bool SeesThroughOrNothingInViewFrame(const Eigen::Vector3d& q, double margin) const;

  // Whether the return in the direction of p_world lies more than `margin` short of it: the
  // place was hidden behind something when this view was taken.
  bool Hides(const Eigen::Vector3d& p_world, double margin) const;
  // Whether the nearest return in the direction of q (this view's sensor frame) lies within
  // `margin` of it: the view saw a surface there.
  bool SeesSurfaceInViewFrame(const Eigen::Vector3d& q, double margin) const;

  const Eigen::Isometry3d& pose() const { return T_world_sensor_; }

 private:
  // Cell of a sensor-frame direction; false when its elevation lies outside the sensor's view.
  bool CellOf(const Eigen::Vector3d& q, int& row, int& col) const;
  // A column index at most one turn outside [0, cols_) brought back into it (no integer division).
  int WrappedColumn(int c) const { return c < 0 ? c + cols_ : (c >= cols_ ? c - cols_ : c); }
  // Keeps `range` as the nearest return of cell (row, col) if it is nearer.
  void Fill(int row, int col, float range) {
    float& cell = nearest_[static_cast<std::size_t>(row) * cols_ + col];
    if (cell == 0.0f || range < cell) cell = range;
  }
  // Fills the cells within `radius` metres of the point (Config::point_radius).
  void Spread(int row, int col, float range, double radius);
  bool Through(const Eigen::Vector3d& q, double margin, bool empty_passes) const;

  Eigen::Isometry3d T_world_sensor_;
  Eigen::Isometry3d T_sensor_world_;
  int rows_ = 0, cols_ = 0;
  double el_min_ = 0.0, el_step_ = 1.0, az_step_ = 1.0;
  double inv_el_step_ = 1.0, inv_az_step_ = 1.0;
  std::vector<float> nearest_;  // rows_ * cols_, 0 = no return
};

}  // namespace dammloam
