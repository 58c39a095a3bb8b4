#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/geometry/scan.hpp"
#include "core/preprocess/preprocess_config.hpp"

namespace dammloam {

// Spherical projection of one scan (paper Sec. III-A.1) into rows x columns pixels.
//
// Row (top = 0):
//   1. the point's ring when the scan has rings (ring 0 = top beam, as in the sequence format);
//   2. else the nearest of the sensor's vertical angles, ranked from the highest down;
//   3. else, for clouds stored ring after ring (KITTI .bin), the ring counted from the azimuth
//      wrap-arounds in point order, if that finds 90-110 % of the configured rows;
//   4. else a uniform bin over the elevation span observed in this scan.
// Column: azimuth a = atan2(y, x) in (-pi, pi], c = floor((a + pi) / (2 pi) * cols) mod cols,
//   i.e. column 0 looks backwards (-x) and columns grow counter-clockwise seen from above
//   (-x, -y, +x, +y). Columns wrap around: column cols-1 neighbours column 0.
// Several points in one pixel: the nearest wins; equal ranges (in single precision): the lower
// point index wins.
class RangeImage {
 public:
  RangeImage(const RangeImageConfig& config, const SensorModel& sensor);

  // Projects the points (rings may be empty, else one per point). Points with a non-finite
  // or zero range, or a ring outside [0, 1024), are not projected. O(N + pixels). Called again,
  // it reuses its buffers: no allocation once a scan as large has been projected.
  void Build(const std::vector<Eigen::Vector3d>& points, const std::vector<std::int16_t>& rings);

  int rows() const { return rows_; }
  int cols() const { return cols_; }
  // Index of the point that owns pixel (r, c), -1 if empty.
  int index(int r, int c) const { return index_[Flat(r, c)]; }
  int index_of_pixel(int pixel) const { return index_[pixel]; }  // the same, by flat pixel
  float range(int r, int c) const { return pixels_[Flat(r, c)].range; }  // 0 if empty
  // The owning point (a single-precision copy, contiguous for the normal map); zero if empty.
  const Eigen::Vector3f& point(int r, int c) const { return pixels_[Flat(r, c)].point; }
  bool empty(int r, int c) const { return index_[Flat(r, c)] < 0; }
  // Flat pixel r * cols + c that point i fell into (whether it won it or not), -1 if none.
  int pixel_of(std::size_t i) const { return pixel_of_[i]; }
  int Flat(int r, int c) const { return r * cols_ + c; }
  // Mean angle between neighbouring rows (from the sensor's vertical angles), 0 if unknown.
  double row_spacing_rad() const {
    if (vertical_angles_rad_.size() < 2) return 0.0;
    return (vertical_angles_rad_.front() - vertical_angles_rad_.back()) /
           static_cast<double>(vertical_angles_rad_.size() - 1);
  }

 private:
  int ColumnOf(const Eigen::Vector3d& p) const;
  void ComputeRowsFromRings(const std::vector<std::int16_t>& rings);
  void ComputeRowsFromAngles(const std::vector<Eigen::Vector3d>& points);
  bool ComputeRowsFromScanOrder(const std::vector<Eigen::Vector3d>& points);
  void ComputeRowsFromSpan(const std::vector<Eigen::Vector3d>& points);
  void BuildAngleTable();

  int configured_rows_;
  int rows_;
  int cols_;
  // Nearest-vertical-angle lookup: elevation bin of table_step_ radians -> row.
  std::vector<int> angle_table_;
  double table_min_ = 0.0;
  double table_step_ = 0.0;

  std::vector<int> point_row_;  // per point, -1 when not projected (scratch)
  std::vector<int> pixel_of_;
  std::vector<int> index_;
  // Point and range side by side: the normal map's stencil walk reads both at every step.
  struct Pixel {
    Eigen::Vector3f point = Eigen::Vector3f::Zero();
    float range = 0.0f;
  };
  std::vector<Pixel> pixels_;
  std::vector<std::uint64_t> owner_;  // per pixel: (range bits, point index) of the nearest (scratch)
  std::vector<double> vertical_angles_rad_;
};

}  // namespace dammloam
