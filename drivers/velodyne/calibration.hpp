#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace dammloam::drivers::velodyne {

enum class Model { kVLP16, kVLP32C, kHDL32E, kVLS128 };

std::optional<Model> ParseModel(std::string_view name);  // "vlp16", "vlp32c", "hdl32e", "vls128"
std::string_view Name(Model m);
int LaserCount(Model m);

// One laser of a ROS-velodyne style calibration file (angles in radians, lengths in metres).
struct Laser {
  int id = 0;
  double rot_correction = 0.0;
  double vert_correction = 0.0;
  double dist_correction = 0.0;
  double horiz_offset_correction = 0.0;
  double vert_offset_correction = 0.0;
  int ring = 0;  // 0 = top beam (highest vert_correction); derived, not read
};

struct Calibration {
  std::vector<Laser> lasers;           // indexed by laser_id
  // Metres per count as the file states it (0 = not stated). The decoder uses the model's packet
  // unit and reports a contradicting value: the unit is fixed by the packet format.
  double distance_resolution = 0.0;
  std::string source;                  // file name (or label) the calibration was read from
};

// Errors throw DriverError naming the file, the laser and the field.
Calibration ParseCalibration(const std::string& yaml_text, const std::string& source = "calibration");
Calibration LoadCalibration(const std::filesystem::path& file);

}  // namespace dammloam::drivers::velodyne
