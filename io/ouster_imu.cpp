#include "io/ouster_imu.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <string>

#include "io/io_error.hpp"

namespace dammloam::io {

std::optional<Eigen::Isometry3d> ReadOusterImuToSensor(const std::filesystem::path& file) {
  using nlohmann::json;
  std::ifstream in(file);
  if (!in) FailIn(file, "cannot open");
  const json root = json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (root.is_discarded() || !root.is_object()) FailIn(file, "not a JSON object");
  const json* matrix = nullptr;
  if (root.contains("imu_intrinsics") && root["imu_intrinsics"].is_object() &&
      root["imu_intrinsics"].contains("imu_to_sensor_transform")) {
    matrix = &root["imu_intrinsics"]["imu_to_sensor_transform"];
  } else if (root.contains("imu_to_sensor_transform")) {
    matrix = &root["imu_to_sensor_transform"];
  }
  if (matrix == nullptr) return std::nullopt;
  const std::string key = "\"imu_to_sensor_transform\"";
  if (!matrix->is_array() || matrix->size() != 16) FailIn(file, key + " must be 16 numbers (row-major 4x4)");
  Eigen::Matrix4d M;
  for (int i = 0; i < 16; ++i) {
    const json& v = (*matrix)[static_cast<std::size_t>(i)];
    if (!v.is_number() || !std::isfinite(v.get<double>())) FailIn(file, key + " must be 16 finite numbers");
    M(i / 4, i % 4) = v.get<double>();
  }
  const Eigen::Matrix3d R = M.topLeftCorner<3, 3>();
  if (!M.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1)) ||
      !(R.transpose() * R).isApprox(Eigen::Matrix3d::Identity(), 1e-4) || R.determinant() < 0.0) {
    FailIn(file, key + " is not a rigid transform (rotation, translation in mm, last row 0 0 0 1)");
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  T.translation() = M.topRightCorner<3, 1>() / 1000.0;  // millimetres -> metres
  return T;
}

}  // namespace dammloam::io
