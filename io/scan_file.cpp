#include "io/scan_file.hpp"

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "io/io_error.hpp"
#include "io/number_text.hpp"

namespace dammloam::io {
namespace {

// The file format is little-endian float32; we copy bytes straight into floats.
static_assert(std::endian::native == std::endian::little, "big-endian hosts need byte swapping");

// Why (t, ring) cannot belong to a scan of this sensor, or nullopt when they are fine.
// Compared in float because that is what the file stores: a t written as float(period - eps)
// may round up to float(period), which is then correctly rejected.
std::optional<std::string> TimeRingProblem(float t, float ring, const SensorModel& model) {
  const float period = static_cast<float>(model.scan_period);
  if (!(t >= 0.0f && t < period)) {
    return "time " + FormatExact(t) + " s outside [0, scan_period=" +
           FormatExact(model.scan_period) + ")";
  }
  if (!(ring >= 0.0f && ring < static_cast<float>(model.rings) && ring == std::floor(ring))) {
    return "ring " + FormatExact(ring) + " is not an integer in [0, rings=" +
           std::to_string(model.rings) + ")";
  }
  return std::nullopt;
}

std::vector<float> ReadFloats(const std::filesystem::path& file, std::size_t floats_per_point) {
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(file, ec);
  if (ec) throw IoError(file.string() + ": cannot read scan file (" + ec.message() + ")");
  const std::size_t record = floats_per_point * sizeof(float);
  if (bytes % record != 0) {
    throw IoError(file.string() + ": size " + std::to_string(bytes) +
                  " bytes is not a multiple of the " + std::to_string(record) +
                  "-byte point record (" + std::to_string(floats_per_point) + " float32 values)");
  }
  std::vector<float> values(bytes / sizeof(float));
  std::ifstream in(file, std::ios::binary);
  in.read(reinterpret_cast<char*>(values.data()), static_cast<std::streamsize>(bytes));
  if (!in) throw IoError(file.string() + ": read failed");
  return values;
}

}  // namespace

Scan ReadScanFile(const std::filesystem::path& file, PointLayout layout, const SensorModel& model,
                  bool strict, ScanReadReport* report) {
  const std::size_t stride = FloatsPerPoint(layout);
  const std::vector<float> values = ReadFloats(file, stride);
  const std::size_t count = values.size() / stride;
  const bool with_time_ring = layout == PointLayout::kXYZITR;

  Scan scan;
  scan.points.reserve(count);
  scan.intensities.reserve(count);
  if (with_time_ring) {
    scan.times.reserve(count);
    scan.rings.reserve(count);
  }
  std::size_t dropped = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const float* v = values.data() + i * stride;
    bool finite = true;
    for (std::size_t k = 0; k < stride; ++k) finite = finite && std::isfinite(v[k]);
    if (!finite) {
      if (strict) throw IoError(file.string() + ": point " + std::to_string(i) + " has a NaN/inf value");
      ++dropped;
      continue;
    }
    scan.points.emplace_back(v[0], v[1], v[2]);
    scan.intensities.push_back(v[3]);
    if (!with_time_ring) continue;
    if (const auto problem = TimeRingProblem(v[4], v[5], model)) {
      throw IoError(file.string() + ": point " + std::to_string(i) + ": " + *problem);
    }
    scan.times.push_back(v[4]);
    scan.rings.push_back(static_cast<std::int16_t>(v[5]));
  }
  if (report) report->dropped_nonfinite = dropped;
  return scan;
}

void WriteScanFile(const std::filesystem::path& file, const Scan& scan, PointLayout layout,
                   const SensorModel& model) {
  const std::size_t n = scan.size();
  const bool with_time_ring = layout == PointLayout::kXYZITR;
  if (with_time_ring && n > 0 && !(scan.has_times() && scan.has_rings())) {
    throw IoError(file.string() + ": layout xyzitr needs per-point times and rings for all " +
                  std::to_string(n) + " points");
  }
  const bool has_intensity = scan.intensities.size() == n;
  const std::size_t stride = FloatsPerPoint(layout);
  std::vector<float> values(n * stride);
  for (std::size_t i = 0; i < n; ++i) {
    float* v = values.data() + i * stride;
    v[0] = static_cast<float>(scan.points[i].x());
    v[1] = static_cast<float>(scan.points[i].y());
    v[2] = static_cast<float>(scan.points[i].z());
    v[3] = has_intensity ? scan.intensities[i] : 0.0f;
    if (!with_time_ring) continue;
    v[4] = scan.times[i];
    v[5] = static_cast<float>(scan.rings[i]);
    if (const auto problem = TimeRingProblem(v[4], v[5], model)) {
      throw IoError(file.string() + ": cannot write point " + std::to_string(i) + ": " + *problem);
    }
  }
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(values.data()),
            static_cast<std::streamsize>(values.size() * sizeof(float)));
  if (!out) throw IoError(file.string() + ": cannot write scan file");
}

}  // namespace dammloam::io
