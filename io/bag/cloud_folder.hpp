#pragma once
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "io/bag/scan_source.hpp"

namespace dammloam::io {

// A directory holding .pcd or .ply files (and no meta.json, metadata.yaml or KITTI layout).
bool IsCloudFolder(const std::filesystem::path& dir);

// The stamps of files named by numbers, in seconds (correctly rounded to the nanosecond):
// names with a decimal point are seconds; integer names are taken in the unit among s, ms, us, ns
// that puts their median step in [0.02, 0.5] s (2-50 Hz). Nullopt when the names are not all
// numbers, or are integers no unit fits (frame indices 000000, 000001, ...), or there is one
// integer name. `unit` gets "s", "ms", "us" or "ns".
std::optional<std::vector<double>> StampsFromNames(const std::vector<std::string>& stems,
                                                   std::string* unit = nullptr);

// The files in name order, one scan each (PCD through io/pcd: x y z [intensity]; PLY through
// io/ply.hpp). Points exactly at the origin or not finite are dropped. Stamps from the names
// (StampsFromNames), else file index x options.scan_period (0.1 s when 0); a given
// options.scan_period always wins. The sensor model comes from options.sensor_meta or is guessed
// like a bag's; for clouds without a ring field the beams are taken from the elevations of the
// first cloud's returns (clusters more than 0.3 deg apart: VLP-16, HDL-32E), which gives the
// rings, their vertical angles and columns = points / rings. Describe() says which.
std::unique_ptr<ScanSource> OpenCloudFolder(const std::filesystem::path& dir,
                                            const ScanSourceOptions& options);

}  // namespace dammloam::io
