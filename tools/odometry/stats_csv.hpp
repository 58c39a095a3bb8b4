#pragma once
#include <fstream>
#include <filesystem>

#include "core/odometry/odometry_result.hpp"

namespace dammloam::tools {

// Per-scan statistics, one CSV row per scan (header written on open).
class StatsCsv {
 public:
  explicit StatsCsv(const std::filesystem::path& file);
  void Write(const OdometryResult& result);

 private:
  std::ofstream out_;
  std::filesystem::path file_;
};

}  // namespace dammloam::tools
