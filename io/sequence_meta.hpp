#pragma once
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "core/geometry/scan.hpp"
#include "core/inertial/inertial_config.hpp"

namespace dammloam::io {

// Point record layouts of scans/NNNNNN.bin (sequence.md): little-endian float32 values.
enum class PointLayout {
  kXYZITR,  // x y z intensity t ring (6 floats, the project's own format)
  kXYZI     // x y z intensity (4 floats, KITTI odometry)
};

std::size_t FloatsPerPoint(PointLayout layout);
std::string_view LayoutName(PointLayout layout);  // "xyzitr" / "xyzi", as in meta.json

struct SequenceMeta {
  std::string sensor;
  SensorModel model;
  PointLayout layout = PointLayout::kXYZITR;
  // Optional, for imu.csv / wheel.csv (sequence.md). "imu_extrinsic": {"T_sensor_imu": ...};
  // "imu": noise densities, bias random walks, time offset (absent keys keep ImuNoise's
  // defaults); "base_extrinsic": {"T_sensor_base": ...}. Each transform is {"translation": [3],
  // "quaternion_xyzw": [4]} with p_sensor = R p_other + translation.
  std::optional<Eigen::Isometry3d> T_sensor_imu = std::nullopt;
  std::optional<ImuNoise> imu_noise = std::nullopt;
  double imu_time_offset = 0.0;  // "imu": {"time_offset_s"}: see ImuDescription::time_offset
  std::optional<Eigen::Isometry3d> T_sensor_base = std::nullopt;
};

// The IMU as meta.json describes it, each absent key at ImuDescription's default (the Ouster
// OS1's extrinsic, the ICM-20948's noise, no time offset): what dammloam-odometry uses with a
// sequence's imu.csv and dammloamd with --sensor-meta.
ImuDescription ImuDescriptionOf(const SequenceMeta& meta);

// What is assumed about a KITTI folder that carries no meta.json: an HDL-64E-like sensor.
SequenceMeta KittiMeta();

// Required keys: sensor, rings, columns, scan_period. Optional: vertical_angles_deg (absent or
// empty = unknown, otherwise exactly `rings` values), min_range, max_range, point_layout
// ("xyzitr" default or "xyzi"), the IMU and wheel keys above. Unknown keys are ignored.
// Throws IoError naming file and key.
SequenceMeta ReadMeta(const std::filesystem::path& meta_json);
void WriteMeta(const std::filesystem::path& meta_json, const SequenceMeta& meta);

}  // namespace dammloam::io
