#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/geometry/scan.hpp"

namespace dammloam::drivers::ouster {

enum class Profile {
  kLegacy,
  kRng19Rfl8Sig16Nir16,
  kRng19Rfl8Sig16Nir16Dual,
  kRng15Rfl8Nir8,
  kFusaRng15Rfl8Nir8Dual,
};

std::string_view Name(Profile p);

// What the decoder needs from an Ouster sensor's metadata JSON (flat legacy layout or the
// nested layout of newer firmware). Lengths are in millimetres, as the sensor reports them.
struct Metadata {
  std::string prod_line;          // e.g. "OS-1-128"; empty when the file does not say
  std::string lidar_mode = "1024x10";
  int pixels_per_column = 0;      // H, beams
  int columns_per_frame = 0;      // W
  int columns_per_packet = 16;
  int column_window_first = 0;    // inclusive; the window may wrap around W
  int column_window_last = 0;
  std::vector<int> pixel_shift_by_row;     // H entries, destaggering shifts
  Profile profile = Profile::kLegacy;
  std::vector<double> beam_altitude_deg;   // H, top beam first
  std::vector<double> beam_azimuth_deg;    // H
  Eigen::Matrix4d beam_to_lidar = Eigen::Matrix4d::Identity();    // (0,3) = beam origin offset, mm
  Eigen::Matrix4d lidar_to_sensor = Eigen::Matrix4d::Identity();  // translation in mm
  std::uint16_t udp_port_lidar = 7502;
  std::uint16_t udp_port_imu = 7503;

  double frequency_hz() const;  // from lidar_mode ("1024x10" -> 10)
  int columns_in_window() const;
  bool column_in_window(int column) const;
};

// Parse errors throw DriverError naming `source` and the offending field.
Metadata ParseMetadata(std::string_view json_text, const std::string& source = "metadata");
Metadata LoadMetadata(const std::filesystem::path& file);

// Description of the sensor for the core (rings = beams, ring 0 = top beam).
SensorModel ToSensorModel(const Metadata& meta);

}  // namespace dammloam::drivers::ouster
