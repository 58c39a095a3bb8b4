#pragma once
#include <filesystem>
#include <memory>
#include <string>

#include "io/bag/scan_source.hpp"

namespace dammloam::tools {

// A rosbag2 or MCAP of raw Velodyne packets (velodyne_msgs/msg/VelodyneScan, as the velodyne and
// nebula drivers record them) decoded by drivers/velodyne into scans cut at azimuth 0. `topic`:
// empty for the bag's only VelodyneScan topic. `model`: vlp16, vlp32c, hdl32e or vls128.
// Each packet's own stamp is its capture time. Throws on a bag without such a topic, an unknown
// model or a calibration that does not fit it.
std::unique_ptr<io::ScanSource> OpenVelodyneBag(const std::filesystem::path& path,
                                                const std::string& topic, const std::string& model,
                                                const std::filesystem::path& calibration);

}  // namespace dammloam::tools
