#include "core/odometry/unclassified_scan.hpp"

#include <algorithm>

namespace dammloam {

namespace {
template <typename T>
void KeepIf(std::vector<T>& values, const std::vector<bool>& keep) {
  if (values.size() != keep.size()) {
    values.clear();  // optional field of another length: meaningless, drop it
    return;
  }
  std::size_t out = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (keep[i]) values[out++] = values[i];
  }
  values.resize(out);
}
}  // namespace

ClassifiedScan UnclassifiedScan(Scan scan, const PreprocessConfig& config,
                                const SensorModel& sensor) {
  const double min_range = std::max(config.min_range, sensor.min_range);
  const double max_range = std::min(config.max_range, sensor.max_range);
  std::vector<bool> keep(scan.size());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double r = scan.points[i].norm();
    keep[i] = scan.points[i].allFinite() && r >= min_range && r <= max_range;
  }
  ClassifiedScan out;
  const std::size_t before = scan.size();
  const bool had_times = scan.times.size() == before;
  const bool had_rings = scan.rings.size() == before;
  const bool had_intensities = scan.intensities.size() == before;
  KeepIf(scan.points, keep);
  if (had_times) KeepIf(scan.times, keep); else scan.times.clear();
  if (had_rings) KeepIf(scan.rings, keep); else scan.rings.clear();
  if (had_intensities) KeepIf(scan.intensities, keep); else scan.intensities.clear();
  out.dropped_invalid = before - scan.size();
  out.labels.assign(scan.size(), PointClass::Unknown);
  out.normals.assign(scan.size(), Eigen::Vector3f::Zero());
  out.class_counts[Index(PointClass::Unknown)] = static_cast<std::uint32_t>(scan.size());
  out.scan = std::move(scan);
  return out;
}

}  // namespace dammloam
