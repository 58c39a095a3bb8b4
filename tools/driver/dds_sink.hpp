#pragma once
#include <memory>
#include <string>

#include "tools/driver/scan_sink.hpp"

namespace dammloam::driver {

struct DdsOptions {
  int domain = 0;
  std::string topic;          // empty = the project's default points topic
  std::string frame_id = "lidar";
  bool allow_default_network = false;
  double wait_for_subscriber_s = 0.0;  // before the first sample: wait this long for a reader
};

// Whether this build can publish on DDS (dammloam_dds was available).
bool DdsAvailable();
// Publishes every scan as a PointCloud sample. Throws std::runtime_error with the reason when
// DDS is unavailable or refused (no CYCLONEDDS_URI, see NetworkConfigProblem).
std::unique_ptr<ScanSink> MakeDdsSink(const DdsOptions& options);

}  // namespace dammloam::driver
