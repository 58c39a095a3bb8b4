#pragma once
#include <cstddef>
#include <filesystem>

#include "core/geometry/scan.hpp"
#include "io/sequence_meta.hpp"

namespace dammloam::io {

struct ScanReadReport {
  std::size_t dropped_nonfinite = 0;  // points with a NaN/inf value, left out of the scan
};

// Reads one scans/NNNNNN.bin. Points with a non-finite value are dropped and counted (IoError
// when strict). In kXYZITR every t must lie in [0, scan_period) and every ring be an integer in
// [0, rings): anything else is a broken file (IoError naming file and point index), not clamped.
// kXYZI scans have no times or rings (empty vectors). t_start is left 0 for the caller.
Scan ReadScanFile(const std::filesystem::path& file, PointLayout layout, const SensorModel& model,
                  bool strict, ScanReadReport* report = nullptr);

// Writes a scan in the given layout. kXYZITR needs per-point times and rings that pass the
// checks above (IoError otherwise); missing intensities are written as 0.
void WriteScanFile(const std::filesystem::path& file, const Scan& scan, PointLayout layout,
                   const SensorModel& model);

}  // namespace dammloam::io
