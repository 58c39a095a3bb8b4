#pragma once
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "core/inertial/imu_sample.hpp"
#include "core/inertial/wheel_sample.hpp"

// imu.csv and wheel.csv of a sequence directory (/work/shared/formats/sequence.md): a header
// line, then one sample per line, seven comma-separated numbers, stamps strictly increasing.
//   imu.csv   t,wx,wy,wz,ax,ay,az   rad/s and specific force m/s^2, IMU frame
//   wheel.csv t,vx,vy,vz,wx,wy,wz   body twist m/s and rad/s, base frame
//
// Two kinds of trouble. A file that is not this format (missing or wrong header, a row without
// seven numbers, text where a number belongs) is rejected: IoError naming file, line and
// problem. A sample that is well formed but unusable (NaN/inf, a stamp equal to or before the
// last kept one) is what real drivers emit now and then: by default it is dropped and counted
// with its reason and line, so the estimator can fall back and Status can say why; `strict`
// turns the first such sample into an IoError instead.
namespace dammloam::io {

enum class SampleFault { kNonFinite, kDuplicateStamp, kOutOfOrderStamp };
const char* FaultName(SampleFault fault);  // "NaN/inf value", "duplicate stamp", ...

struct DroppedSample {
  int line = 0;  // 1-based line in the file
  SampleFault fault = SampleFault::kNonFinite;
};

struct StreamReadReport {
  std::size_t kept = 0;
  std::size_t non_finite = 0, duplicate_stamp = 0, out_of_order = 0;
  std::vector<DroppedSample> first_dropped;  // the first kMaxListed, in file order
  static constexpr std::size_t kMaxListed = 20;

  std::size_t dropped() const { return non_finite + duplicate_stamp + out_of_order; }
  // "" when nothing was dropped, else e.g. "dropped 3: 1 NaN/inf value, 2 duplicate stamp
  // (first at line 7: duplicate stamp)".
  std::string Summary() const;
};

struct StreamReadOptions {
  bool strict = false;  // a dropped sample is an IoError instead
};

std::vector<ImuSample> ReadImuCsv(const std::filesystem::path& file,
                                  StreamReadReport* report = nullptr,
                                  const StreamReadOptions& options = {});
std::vector<WheelSample> ReadWheelCsv(const std::filesystem::path& file,
                                      StreamReadReport* report = nullptr,
                                      const StreamReadOptions& options = {});

// Exact round trip (shortest text that parses back to the same double). Stamps must be
// strictly increasing and values finite: a writer never produces what a reader would drop.
void WriteImuCsv(const std::filesystem::path& file, const std::vector<ImuSample>& samples);
void WriteWheelCsv(const std::filesystem::path& file, const std::vector<WheelSample>& samples);

inline constexpr const char* kImuCsvHeader = "t,wx,wy,wz,ax,ay,az";
inline constexpr const char* kWheelCsvHeader = "t,vx,vy,vz,wx,wy,wz";

}  // namespace dammloam::io
