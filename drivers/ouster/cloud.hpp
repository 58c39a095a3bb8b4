#pragma once
#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "core/geometry/scan.hpp"
#include "drivers/ouster/lidar_frame.hpp"
#include "drivers/ouster/metadata.hpp"

namespace dammloam::drivers::ouster {

struct CloudConfig {
  bool second_return = false;    // dual profiles: also emit the second return's points
  bool signal_intensity = false; // intensity = signal instead of reflectivity
};

// Converts frames to point clouds in the sensor frame, with a precomputed per-pixel ray table
// (direction and origin offset), so a frame costs one multiply-add per point.
class CloudMaker {
 public:
  explicit CloudMaker(const Metadata& meta, CloudConfig config = {});

  // Points in firing order (column by column, beams top to bottom), zero ranges omitted.
  // t_start = earliest column timestamp (s); times from the column timestamps; ring = beam.
  Scan ToScan(const LidarFrame& frame) const;

  // Ray of pixel (beam, column) in the sensor frame: origin (m) + range_m * direction.
  Eigen::Vector3d Direction(int beam, int column) const;
  Eigen::Vector3d Origin(int beam, int column) const;

 private:
  int rows_ = 0;
  int cols_ = 0;
  Profile profile_;
  CloudConfig config_;
  std::vector<Eigen::Vector3d> direction_;  // rows*cols, sensor frame, unit
  std::vector<Eigen::Vector3d> origin_;     // rows*cols, sensor frame, metres
};

// Moves each row right by its pixel_shift_by_row so that a column holds the pixels that look
// in the same direction: out(row, (col + shift[row]) mod W) = in(row, col).
template <typename T>
std::vector<T> Destagger(const std::vector<T>& staggered, int rows, int cols, const std::vector<int>& shift) {
  std::vector<T> out(staggered.size());
  for (int r = 0; r < rows; ++r) {
    const int s = ((shift[static_cast<std::size_t>(r)] % cols) + cols) % cols;
    const std::size_t base = static_cast<std::size_t>(r) * static_cast<std::size_t>(cols);
    for (int c = 0; c < cols; ++c) out[base + static_cast<std::size_t>((c + s) % cols)] = staggered[base + static_cast<std::size_t>(c)];
  }
  return out;
}

}  // namespace dammloam::drivers::ouster
