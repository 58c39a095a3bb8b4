#include "drivers/ouster/cloud.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "drivers/ouster/packet_decoder.hpp"

namespace dammloam::drivers::ouster {

CloudMaker::CloudMaker(const Metadata& meta, CloudConfig config)
    : rows_(meta.pixels_per_column), cols_(meta.columns_per_frame), profile_(meta.profile), config_(config) {
  const Eigen::Matrix3d R = meta.lidar_to_sensor.topLeftCorner<3, 3>();
  const Eigen::Vector3d t_mm = meta.lidar_to_sensor.topRightCorner<3, 1>();
  const double n_mm = meta.beam_to_lidar(0, 3);  // beam origin distance from the lidar axis
  const double z_mm = meta.beam_to_lidar(2, 3);
  direction_.resize(static_cast<std::size_t>(rows_) * static_cast<std::size_t>(cols_));
  origin_.resize(direction_.size());
  for (int r = 0; r < rows_; ++r) {
    const double az = meta.beam_azimuth_deg[static_cast<std::size_t>(r)] * M_PI / 180.0;
    const double alt = meta.beam_altitude_deg[static_cast<std::size_t>(r)] * M_PI / 180.0;
    for (int c = 0; c < cols_; ++c) {
      // Encoder angle of this measurement id; the sensor spins clockwise seen from above.
      const double theta_e = 2.0 * M_PI * (1.0 - static_cast<double>(c) / cols_);
      const double theta = theta_e - az;
      const Eigen::Vector3d dir(std::cos(theta) * std::cos(alt), std::sin(theta) * std::cos(alt), std::sin(alt));
      // The range is measured from the beam origin, which sits n_mm off the axis.
      const Eigen::Vector3d beam_origin(n_mm * std::cos(theta_e), n_mm * std::sin(theta_e), z_mm);
      const std::size_t i = static_cast<std::size_t>(r) * static_cast<std::size_t>(cols_) + static_cast<std::size_t>(c);
      direction_[i] = R * dir;
      // point_mm = beam_origin + (range - n) * dir; fold the -n*dir term into the origin.
      origin_[i] = (R * (beam_origin - n_mm * dir) + t_mm) * 1e-3;
    }
  }
}

Eigen::Vector3d CloudMaker::Direction(int beam, int column) const {
  return direction_[static_cast<std::size_t>(beam) * static_cast<std::size_t>(cols_) + static_cast<std::size_t>(column)];
}
Eigen::Vector3d CloudMaker::Origin(int beam, int column) const {
  return origin_[static_cast<std::size_t>(beam) * static_cast<std::size_t>(cols_) + static_cast<std::size_t>(column)];
}

Scan CloudMaker::ToScan(const LidarFrame& f) const {
  Scan scan;
  if (f.rows != rows_ || f.cols != cols_) return scan;
  std::uint64_t t0 = std::numeric_limits<std::uint64_t>::max();
  for (int c = 0; c < cols_; ++c) {
    const auto cu = static_cast<std::size_t>(c);
    if (f.column_received[cu] != 0 && ColumnValid(profile_, f.status[cu])) t0 = std::min(t0, f.timestamp[cu]);
  }
  if (t0 == std::numeric_limits<std::uint64_t>::max()) return scan;
  scan.t_start = static_cast<double>(t0) * 1e-9;

  const bool dual = config_.second_return && (profile_ == Profile::kRng19Rfl8Sig16Nir16Dual ||
                                              profile_ == Profile::kFusaRng15Rfl8Nir8Dual);
  const std::size_t reserve = static_cast<std::size_t>(rows_) * static_cast<std::size_t>(cols_) * (dual ? 2 : 1);
  scan.points.reserve(reserve);
  scan.intensities.reserve(reserve);
  scan.times.reserve(reserve);
  scan.rings.reserve(reserve);

  auto add = [&](std::size_t i, std::uint32_t range_mm, float intensity, float t, int r) {
    if (range_mm == 0) return;
    scan.points.push_back(origin_[i] + (range_mm * 1e-3) * direction_[i]);
    scan.intensities.push_back(intensity);
    scan.times.push_back(t);
    scan.rings.push_back(static_cast<std::int16_t>(r));
  };
  for (int c = 0; c < cols_; ++c) {
    const auto cu = static_cast<std::size_t>(c);
    if (f.column_received[cu] == 0 || !ColumnValid(profile_, f.status[cu])) continue;
    const float t = static_cast<float>(static_cast<double>(f.timestamp[cu] - t0) * 1e-9);
    for (int r = 0; r < rows_; ++r) {
      const std::size_t i = static_cast<std::size_t>(r) * static_cast<std::size_t>(cols_) + cu;
      const float intensity = config_.signal_intensity ? static_cast<float>(f.signal[i]) : static_cast<float>(f.reflectivity[i]);
      add(i, f.range[i], intensity, t, r);
      if (dual) add(i, f.range2[i], static_cast<float>(f.reflectivity2[i]), t, r);
    }
  }
  return scan;
}

}  // namespace dammloam::drivers::ouster
