// Where dammloam-odometry's scans come from: every input kind behind io::ScanSource.
#include <algorithm>
#include <spdlog/spdlog.h>

#include "io/bag/bag_reader.hpp"
#include "tools/odometry/runner.hpp"
#include "tools/odometry/velodyne_bag_source.hpp"

namespace dammloam::tools {

std::unique_ptr<io::ScanSource> OpenSource(const RunnerOptions& o) {
  if (!o.velodyne_model.empty() || !o.velodyne_calibration.empty()) {
    if (o.velodyne_model.empty() || o.velodyne_calibration.empty() || !io::IsBagPath(o.sequence)) {
      throw std::runtime_error("raw Velodyne packets need a bag and both --velodyne-model and "
                               "--velodyne-calibration");
    }
    return OpenVelodyneBag(o.sequence, o.topic, o.velodyne_model, o.velodyne_calibration);
  }
  auto source = io::OpenScanSource(o.sequence, {o.topic, o.sensor_meta});
  if (source->kind() == "sequence" && (!o.topic.empty() || !o.sensor_meta.empty())) {
    throw std::runtime_error(o.sequence.string() + ": --topic and --sensor-meta are for bags; " +
                             "a sequence directory has its own meta.json");
  }
  if (!o.quiet && source->kind() != "sequence" && o.sensor_meta.empty()) {
    const SensorModel& m = source->model();
    spdlog::info("{}: sensor model guessed from the first clouds: {} rings, {} columns, {:.3f} s "
                 "per scan (give --sensor-meta meta.json to set it)",
                 o.sequence.string(), m.rings, m.columns, m.scan_period);
  }
  return source;
}

std::size_t ScansToRun(const io::ScanSource& source, std::size_t max_scans) {
  const std::optional<std::size_t> size = source.size();
  if (!size) return max_scans;
  return max_scans > 0 ? std::min(max_scans, *size) : *size;
}

}  // namespace dammloam::tools
