#include "io/meta_inertial.hpp"

#include <cmath>
#include <string>

#include "io/io_error.hpp"

namespace dammloam::io {
namespace {

using nlohmann::json;

std::vector<double> Numbers(const json& value, std::size_t count, const std::filesystem::path& file,
                            const std::string& key) {
  if (!value.is_array() || value.size() != count) {
    FailIn(file, "key \"" + key + "\" must be an array of " + std::to_string(count) + " numbers");
  }
  std::vector<double> out;
  for (const json& v : value) {
    if (!v.is_number() || !std::isfinite(v.get<double>())) {
      FailIn(file, "key \"" + key + "\" must be an array of " + std::to_string(count) + " numbers");
    }
    out.push_back(v.get<double>());
  }
  return out;
}

// {"<outer>": {"<inner>": {"translation": [x, y, z], "quaternion_xyzw": [x, y, z, w]}}}
Eigen::Isometry3d ReadTransform(const json& root, const std::filesystem::path& file, const char* outer,
                                const char* inner) {
  const std::string key = std::string(outer) + "." + inner;
  const json& o = root.at(outer);
  if (!o.is_object() || !o.contains(inner) || !o.at(inner).is_object()) {
    FailIn(file, "key \"" + std::string(outer) + "\" must hold an object \"" + inner + "\"");
  }
  const json& T = o.at(inner);
  for (const char* part : {"translation", "quaternion_xyzw"}) {
    if (!T.contains(part)) FailIn(file, "missing required key \"" + key + "." + part + "\"");
  }
  const std::vector<double> t = Numbers(T.at("translation"), 3, file, key + ".translation");
  const std::vector<double> q = Numbers(T.at("quaternion_xyzw"), 4, file, key + ".quaternion_xyzw");
  const Eigen::Quaterniond quaternion(q[3], q[0], q[1], q[2]);
  // A unit quaternion written with six or more digits; anything further off is a mistake.
  if (std::abs(quaternion.norm() - 1.0) > 1e-3) {
    FailIn(file, "key \"" + key + ".quaternion_xyzw\" is not a unit quaternion (norm " +
                   std::to_string(quaternion.norm()) + ")");
  }
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = quaternion.normalized().toRotationMatrix();
  out.translation() = Eigen::Vector3d(t[0], t[1], t[2]);
  return out;
}

json TransformJson(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.linear());
  const Eigen::Vector3d& t = T.translation();
  return {{"translation", {t.x(), t.y(), t.z()}}, {"quaternion_xyzw", {q.x(), q.y(), q.z(), q.w()}}};
}

// Optional non-negative number `key` of the "imu" object into `value`.
void ReadNoise(const json& imu, const std::filesystem::path& file, const char* key, double* value) {
  if (!imu.contains(key)) return;
  const json& v = imu.at(key);
  if (!v.is_number() || !(v.get<double>() >= 0.0) || !std::isfinite(v.get<double>())) {
    FailIn(file, std::string("key \"imu.") + key + "\" must be a number >= 0");
  }
  *value = v.get<double>();
}

constexpr const char* kGyroNoise = "gyro_noise_density_rad_s_sqrtHz";
constexpr const char* kAccelNoise = "accel_noise_density_m_s2_sqrtHz";
constexpr const char* kGyroWalk = "gyro_bias_random_walk_rad_s2_sqrtHz";
constexpr const char* kAccelWalk = "accel_bias_random_walk_m_s3_sqrtHz";
constexpr const char* kTimeOffset = "time_offset_s";

}  // namespace

void ReadInertialKeys(const json& root, const std::filesystem::path& file, SequenceMeta* meta) {
  if (root.contains("imu_extrinsic")) {
    meta->T_sensor_imu = ReadTransform(root, file, "imu_extrinsic", "T_sensor_imu");
  }
  if (root.contains("base_extrinsic")) {
    meta->T_sensor_base = ReadTransform(root, file, "base_extrinsic", "T_sensor_base");
  }
  if (root.contains("imu")) {
    const json& imu = root.at("imu");
    if (!imu.is_object()) FailIn(file, "key \"imu\" must be an object");
    ImuNoise noise;
    ReadNoise(imu, file, kGyroNoise, &noise.gyro_noise_density);
    ReadNoise(imu, file, kAccelNoise, &noise.accel_noise_density);
    ReadNoise(imu, file, kGyroWalk, &noise.gyro_bias_random_walk);
    ReadNoise(imu, file, kAccelWalk, &noise.accel_bias_random_walk);
    meta->imu_noise = noise;
    if (imu.contains(kTimeOffset)) {
      const json& v = imu.at(kTimeOffset);
      if (!v.is_number() || !std::isfinite(v.get<double>()) || std::abs(v.get<double>()) > 1.0) {
        FailIn(file, std::string("key \"imu.") + kTimeOffset + "\" must be a number of seconds in [-1, 1]");
      }
      meta->imu_time_offset = v.get<double>();
    }
  }
}

void WriteInertialKeys(const SequenceMeta& meta, json* root) {
  if (meta.T_sensor_imu) (*root)["imu_extrinsic"] = {{"T_sensor_imu", TransformJson(*meta.T_sensor_imu)}};
  if (meta.T_sensor_base) (*root)["base_extrinsic"] = {{"T_sensor_base", TransformJson(*meta.T_sensor_base)}};
  if (meta.imu_noise) {
    (*root)["imu"] = {{kGyroNoise, meta.imu_noise->gyro_noise_density},
                      {kAccelNoise, meta.imu_noise->accel_noise_density},
                      {kGyroWalk, meta.imu_noise->gyro_bias_random_walk},
                      {kAccelWalk, meta.imu_noise->accel_bias_random_walk},
                      {kTimeOffset, meta.imu_time_offset}};
  }
}

}  // namespace dammloam::io
