#include "drivers/ouster/metadata.hpp"

#include <cmath>
#include <limits>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "drivers/diagnostics.hpp"

namespace dammloam::drivers::ouster {
namespace {

using nlohmann::json;

struct Parser {
  const std::string& source;

  [[noreturn]] void Fail(const std::string& field, const std::string& what) const {
    throw DriverError(source + ": field '" + field + "' " + what);
  }

  // Looks a key up in the first of `objects` that has it.
  const json* Find(std::initializer_list<const json*> objects, const char* key) const {
    for (const json* o : objects) {
      if (o != nullptr && o->is_object() && o->contains(key)) return &(*o)[key];
    }
    return nullptr;
  }

  std::vector<double> Numbers(const json* j, const char* name, std::size_t expected) const {
    if (j == nullptr) Fail(name, "is missing");
    if (!j->is_array()) Fail(name, "must be an array of numbers");
    std::vector<double> v;
    for (const auto& x : *j) {
      if (!x.is_number()) Fail(name, "must contain only numbers");
      v.push_back(x.get<double>());
    }
    if (expected != 0 && v.size() != expected) {
      Fail(name, "has " + std::to_string(v.size()) + " entries, expected " + std::to_string(expected));
    }
    return v;
  }

  // Numbers stored as int (truncated as before), which must lie in int's range: casting a
  // larger double (1e300) to int is undefined.
  std::vector<int> Ints(const json* j, const char* name, std::size_t expected) const {
    std::vector<int> out;
    for (double v : Numbers(j, name, expected)) {
      if (!(v > std::numeric_limits<int>::min() - 1.0 && v < std::numeric_limits<int>::max() + 1.0)) {
        Fail(name, "has a value outside the integer range");
      }
      out.push_back(static_cast<int>(v));
    }
    return out;
  }

  Eigen::Matrix4d Transform(const json* j, const char* name) const {
    if (j == nullptr) return Eigen::Matrix4d::Identity();
    const auto v = Numbers(j, name, 16);
    Eigen::Matrix4d T;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) T(r, c) = v[static_cast<std::size_t>(4 * r + c)];
    return T;
  }

  int Int(const json* j, const char* name, int fallback) const {
    if (j == nullptr) return fallback;
    if (!j->is_number_integer()) Fail(name, "must be an integer");
    return j->get<int>();
  }
};

Profile ParseProfile(const std::string& s, const Parser& p) {
  if (s == "LEGACY") return Profile::kLegacy;
  if (s == "RNG19_RFL8_SIG16_NIR16") return Profile::kRng19Rfl8Sig16Nir16;
  if (s == "RNG19_RFL8_SIG16_NIR16_DUAL") return Profile::kRng19Rfl8Sig16Nir16Dual;
  if (s == "RNG15_RFL8_NIR8") return Profile::kRng15Rfl8Nir8;
  if (s == "FUSA_RNG15_RFL8_NIR8_DUAL") return Profile::kFusaRng15Rfl8Nir8Dual;
  p.Fail("udp_profile_lidar", "has unsupported value '" + s + "'");
}

}  // namespace

std::string_view Name(Profile p) {
  switch (p) {
    case Profile::kLegacy: return "LEGACY";
    case Profile::kRng19Rfl8Sig16Nir16: return "RNG19_RFL8_SIG16_NIR16";
    case Profile::kRng19Rfl8Sig16Nir16Dual: return "RNG19_RFL8_SIG16_NIR16_DUAL";
    case Profile::kRng15Rfl8Nir8: return "RNG15_RFL8_NIR8";
    case Profile::kFusaRng15Rfl8Nir8Dual: return "FUSA_RNG15_RFL8_NIR8_DUAL";
  }
  return "?";
}

double Metadata::frequency_hz() const {
  const auto x = lidar_mode.find('x');
  if (x == std::string::npos) return 10.0;
  try {
    return std::stod(lidar_mode.substr(x + 1));
  } catch (...) {
    return 10.0;
  }
}

int Metadata::columns_in_window() const {
  if (column_window_first <= column_window_last) return column_window_last - column_window_first + 1;
  return columns_per_frame - column_window_first + column_window_last + 1;
}

bool Metadata::column_in_window(int c) const {
  if (column_window_first <= column_window_last) return c >= column_window_first && c <= column_window_last;
  return c >= column_window_first || c <= column_window_last;
}

Metadata ParseMetadata(std::string_view text, const std::string& source) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {
    throw DriverError(source + ": not valid JSON: " + e.what());
  }
  if (!root.is_object()) throw DriverError(source + ": top level must be a JSON object");
  const Parser p{source};

  // The nested layout groups keys; the flat one keeps them at the top. Search both.
  const json* beams = p.Find({&root}, "beam_intrinsics");
  const json* lidar_intr = p.Find({&root}, "lidar_intrinsics");
  const json* format = p.Find({&root}, "lidar_data_format");
  if (format == nullptr) format = p.Find({&root}, "data_format");
  const json* config = p.Find({&root}, "config_params");
  const json* info = p.Find({&root}, "sensor_info");

  Metadata m;
  m.beam_altitude_deg = p.Numbers(p.Find({beams, &root}, "beam_altitude_angles"), "beam_altitude_angles", 0);
  const std::size_t H = m.beam_altitude_deg.size();
  if (H == 0) p.Fail("beam_altitude_angles", "is empty");
  // Like columns_per_frame below: the ray table and every frame hold beams x columns entries.
  // 1024 is also dammloamd's limit on rings.
  if (H > 1024) p.Fail("beam_altitude_angles", "has " + std::to_string(H) + " entries, more than 1024 beams");
  m.beam_azimuth_deg = p.Numbers(p.Find({beams, &root}, "beam_azimuth_angles"), "beam_azimuth_angles", H);

  if (const json* mode = p.Find({config, &root}, "lidar_mode")) {
    if (!mode->is_string()) p.Fail("lidar_mode", "must be a string like \"1024x10\"");
    m.lidar_mode = mode->get<std::string>();
  }
  int mode_columns = 0;
  try {
    mode_columns = std::stoi(m.lidar_mode.substr(0, m.lidar_mode.find('x')));
  } catch (...) {
    p.Fail("lidar_mode", "'" + m.lidar_mode + "' is not of the form <columns>x<hz>");
  }
  if (m.frequency_hz() <= 0.0) p.Fail("lidar_mode", "'" + m.lidar_mode + "' has no positive rate");

  if (const json* prod = p.Find({info, &root}, "prod_line"); prod != nullptr && prod->is_string()) {
    m.prod_line = prod->get<std::string>();
  }

  m.pixels_per_column = p.Int(p.Find({format}, "pixels_per_column"), "pixels_per_column", static_cast<int>(H));
  m.columns_per_frame = p.Int(p.Find({format}, "columns_per_frame"), "columns_per_frame", mode_columns);
  m.columns_per_packet = p.Int(p.Find({format}, "columns_per_packet"), "columns_per_packet", 16);
  if (m.pixels_per_column != static_cast<int>(H)) {
    p.Fail("pixels_per_column", "is " + std::to_string(m.pixels_per_column) + " but there are " +
                                    std::to_string(H) + " beam angles");
  }
  if (m.columns_per_frame <= 0 || m.columns_per_frame > 4096) p.Fail("columns_per_frame", "out of range");
  if (m.columns_per_packet <= 0 || m.columns_per_packet > 64) p.Fail("columns_per_packet", "out of range");

  m.column_window_first = 0;
  m.column_window_last = m.columns_per_frame - 1;
  if (const json* w = p.Find({format}, "column_window")) {
    const auto v = p.Ints(w, "column_window", 2);
    m.column_window_first = v[0];
    m.column_window_last = v[1];
    if (m.column_window_first < 0 || m.column_window_last >= m.columns_per_frame ||
        m.column_window_last < 0 || m.column_window_first >= m.columns_per_frame) {
      p.Fail("column_window", "lies outside [0, columns_per_frame)");
    }
  }

  if (const json* s = p.Find({format}, "pixel_shift_by_row")) {
    m.pixel_shift_by_row = p.Ints(s, "pixel_shift_by_row", H);
  } else {
    // Older metadata lacks it: derive the shift from each beam's azimuth offset, which is what
    // the sensor's own table encodes (columns per degree times the offset).
    for (double az : m.beam_azimuth_deg) {
      m.pixel_shift_by_row.push_back(static_cast<int>(std::lround(az * m.columns_per_frame / 360.0)));
    }
  }

  if (const json* prof = p.Find({format, config}, "udp_profile_lidar")) {
    if (!prof->is_string()) p.Fail("udp_profile_lidar", "must be a string");
    m.profile = ParseProfile(prof->get<std::string>(), p);
  }

  // Beam origin: the nested layout has beam_to_lidar_transform; the flat one only the offset.
  m.beam_to_lidar = p.Transform(p.Find({beams}, "beam_to_lidar_transform"), "beam_to_lidar_transform");
  if (const json* n = p.Find({beams, &root}, "lidar_origin_to_beam_origin_mm")) {
    if (!n->is_number()) p.Fail("lidar_origin_to_beam_origin_mm", "must be a number");
    if (p.Find({beams}, "beam_to_lidar_transform") == nullptr) m.beam_to_lidar(0, 3) = n->get<double>();
  }
  m.lidar_to_sensor = p.Transform(p.Find({lidar_intr, &root}, "lidar_to_sensor_transform"),
                                  "lidar_to_sensor_transform");

  m.udp_port_lidar = static_cast<std::uint16_t>(p.Int(p.Find({config, &root}, "udp_port_lidar"), "udp_port_lidar", 7502));
  m.udp_port_imu = static_cast<std::uint16_t>(p.Int(p.Find({config, &root}, "udp_port_imu"), "udp_port_imu", 7503));
  if (m.udp_port_lidar == 0) m.udp_port_lidar = 7502;
  if (m.udp_port_imu == 0) m.udp_port_imu = 7503;
  return m;
}

Metadata LoadMetadata(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw DriverError("cannot open Ouster metadata " + file.string());
  std::stringstream ss;
  ss << in.rdbuf();
  return ParseMetadata(ss.str(), file.string());
}

SensorModel ToSensorModel(const Metadata& meta) {
  SensorModel model;
  model.rings = meta.pixels_per_column;
  model.columns = meta.columns_per_frame;
  model.scan_period = 1.0 / meta.frequency_hz();
  model.vertical_angles_deg = meta.beam_altitude_deg;
  // Nominal ranges per product line (OS0 short range, OS2 long range).
  model.min_range = 0.3;
  model.max_range = 120.0;
  if (meta.prod_line.rfind("OS-0", 0) == 0) model.max_range = 75.0;
  if (meta.prod_line.rfind("OS-2", 0) == 0) model.max_range = 240.0;
  return model;
}

}  // namespace dammloam::drivers::ouster
