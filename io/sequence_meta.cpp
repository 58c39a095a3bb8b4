#include "io/sequence_meta.hpp"

#include <fstream>
#include <nlohmann/json.hpp>

#include "io/io_error.hpp"
#include "io/meta_inertial.hpp"

namespace dammloam::io {
namespace {

using nlohmann::json;

const json& Require(const json& root, const std::filesystem::path& file, const char* key) {
  const auto it = root.find(key);
  if (it == root.end()) FailIn(file, std::string("missing required key \"") + key + "\"");
  return *it;
}

double NumberAt(const json& value, const std::filesystem::path& file, const char* key) {
  if (!value.is_number()) FailIn(file, std::string("key \"") + key + "\" must be a number");
  return value.get<double>();
}

int PositiveIntAt(const json& value, const std::filesystem::path& file, const char* key) {
  if (!value.is_number_integer() || value.get<long long>() <= 0 ||
      value.get<long long>() > 1'000'000) {
    FailIn(file, std::string("key \"") + key + "\" must be a positive integer");
  }
  return value.get<int>();
}

PointLayout ParseLayout(const json& value, const std::filesystem::path& file) {
  if (value == "xyzitr") return PointLayout::kXYZITR;
  if (value == "xyzi") return PointLayout::kXYZI;
  FailIn(file, "key \"point_layout\" must be \"xyzitr\" or \"xyzi\", got " + value.dump());
}

std::vector<double> ParseAngles(const json& value, const std::filesystem::path& file, int rings) {
  if (!value.is_array()) FailIn(file, "key \"vertical_angles_deg\" must be an array of numbers");
  std::vector<double> angles;
  for (const auto& angle : value) angles.push_back(NumberAt(angle, file, "vertical_angles_deg"));
  if (!angles.empty() && angles.size() != static_cast<std::size_t>(rings)) {
    FailIn(file, "key \"vertical_angles_deg\" has " + std::to_string(angles.size()) +
                   " values but \"rings\" is " + std::to_string(rings));
  }
  return angles;
}

}  // namespace

std::size_t FloatsPerPoint(PointLayout layout) { return layout == PointLayout::kXYZI ? 4 : 6; }

std::string_view LayoutName(PointLayout layout) {
  return layout == PointLayout::kXYZI ? "xyzi" : "xyzitr";
}

SequenceMeta KittiMeta() {
  SequenceMeta meta;
  meta.sensor = "hdl-64e";
  meta.model.rings = 64;
  meta.model.columns = 2048;
  meta.model.scan_period = 0.1;
  meta.model.min_range = 0.3;
  meta.model.max_range = 120.0;
  meta.layout = PointLayout::kXYZI;
  return meta;
}

SequenceMeta ReadMeta(const std::filesystem::path& meta_json) {
  std::ifstream in(meta_json);
  if (!in) FailIn(meta_json, "cannot open (missing meta.json?)");
  json root;
  try {
    root = json::parse(in);
  } catch (const json::exception& e) {
    FailIn(meta_json, std::string("not valid JSON: ") + e.what());
  }
  if (!root.is_object()) FailIn(meta_json, "top level must be a JSON object");

  SequenceMeta meta;
  const json& sensor = Require(root, meta_json, "sensor");
  if (!sensor.is_string()) FailIn(meta_json, "key \"sensor\" must be a string");
  meta.sensor = sensor.get<std::string>();
  meta.model.rings = PositiveIntAt(Require(root, meta_json, "rings"), meta_json, "rings");
  meta.model.columns = PositiveIntAt(Require(root, meta_json, "columns"), meta_json, "columns");
  meta.model.scan_period =
      NumberAt(Require(root, meta_json, "scan_period"), meta_json, "scan_period");
  if (!(meta.model.scan_period > 0.0)) FailIn(meta_json, "key \"scan_period\" must be > 0");
  if (root.contains("vertical_angles_deg")) {
    meta.model.vertical_angles_deg =
        ParseAngles(root["vertical_angles_deg"], meta_json, meta.model.rings);
  }
  if (root.contains("min_range")) {
    meta.model.min_range = NumberAt(root["min_range"], meta_json, "min_range");
  }
  if (root.contains("max_range")) {
    meta.model.max_range = NumberAt(root["max_range"], meta_json, "max_range");
  }
  if (!(meta.model.min_range >= 0.0 && meta.model.min_range < meta.model.max_range)) {
    FailIn(meta_json, "keys \"min_range\"/\"max_range\" must satisfy 0 <= min_range < max_range");
  }
  if (root.contains("point_layout")) meta.layout = ParseLayout(root["point_layout"], meta_json);
  ReadInertialKeys(root, meta_json, &meta);
  return meta;
}

void WriteMeta(const std::filesystem::path& meta_json, const SequenceMeta& meta) {
  json root = {
      {"sensor", meta.sensor},
      {"rings", meta.model.rings},
      {"columns", meta.model.columns},
      {"scan_period", meta.model.scan_period},
      {"vertical_angles_deg", meta.model.vertical_angles_deg},
      {"min_range", meta.model.min_range},
      {"max_range", meta.model.max_range},
      {"point_layout", std::string(LayoutName(meta.layout))},
  };
  WriteInertialKeys(meta, &root);
  std::ofstream out(meta_json);
  out << root.dump(2) << '\n';
  if (!out) FailIn(meta_json, "cannot write");
}

ImuDescription ImuDescriptionOf(const SequenceMeta& meta) {
  ImuDescription imu;
  if (meta.T_sensor_imu) imu.T_sensor_imu = *meta.T_sensor_imu;
  if (meta.imu_noise) imu.noise = *meta.imu_noise;
  imu.time_offset = meta.imu_time_offset;
  return imu;
}

}  // namespace dammloam::io
