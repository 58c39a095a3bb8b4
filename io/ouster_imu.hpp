#pragma once
#include <Eigen/Geometry>
#include <filesystem>
#include <optional>

// The IMU extrinsic of an Ouster sensor's metadata JSON (issue 55), for dammloamd
// --ouster-metadata: the packet decoder (drivers/ouster) reads the beams, this only the IMU's
// place, so that the daemon needs no driver library.
namespace dammloam::io {

// "imu_to_sensor_transform" (top level, or under "imu_intrinsics" since firmware 2.x): a
// row-major 4x4 with the translation in millimetres, returned in metres as T_sensor_imu
// (p_sensor = R p_imu + t). Empty when the file has no such key; IoError when the file is not
// JSON or the matrix is not 16 numbers of a rigid transform.
std::optional<Eigen::Isometry3d> ReadOusterImuToSensor(const std::filesystem::path& metadata_json);

}  // namespace dammloam::io
