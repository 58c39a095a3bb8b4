#include "tools/odometry/runner.hpp"

namespace dammloam::tools {

std::unique_ptr<io::ScanSource> OpenSource(const RunnerOptions& o) {
  return OpenScanInput({o.sequence, o.topic, o.sensor_meta, o.velodyne_model,
                        o.velodyne_calibration, o.ouster_metadata, o.scan_period, o.quiet});
}

}  // namespace dammloam::tools
