#pragma once
#include <cstddef>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/scan.hpp"
#include "io/tum.hpp"

namespace dammloam::io {

struct ScanSourceOptions {
  std::string topic;                  // bags: the PointCloud2 topic (empty: the only one)
  std::filesystem::path sensor_meta;  // bags, cloud folders: a meta.json giving the sensor model
  double scan_period = 0.0;           // cloud folders: stamps = index x period (0: from names)
};

// Scans from whatever the user recorded, in order. The kind is told by the path: a directory
// with metadata.yaml is a rosbag2, a *.mcap file an MCAP, a *.bag file a ROS 1 bag, a directory
// of .pcd / .ply files (io/bag/cloud_folder.hpp) a cloud folder, anything else a sequence
// directory or KITTI folder (io::SequenceReader). Packet captures (.pcap) need drivers/ and are
// opened in tools/ (tools/odometry/pcap_source.hpp).
class ScanSource {
 public:
  virtual ~ScanSource() = default;
  // "sequence", "rosbag2", "mcap", "ros1 bag", "cloud folder", "ouster pcap", ...
  virtual std::string kind() const = 0;
  // One line for the log on where the stamps (and the model) came from; empty: nothing to say.
  virtual std::string Describe() const { return {}; }
  virtual const SensorModel& model() const = 0;
  // Number of scans when known up front (a bag's message count, which may include clouds that
  // turn out empty and are skipped).
  virtual std::optional<std::size_t> size() const = 0;
  // The next scan with its t_start set; nullopt after the last.
  virtual std::optional<Scan> Next() = 0;
  // Ground truth (a sequence's gt.tum), when there is one.
  virtual std::optional<std::vector<StampedPose>> ReadGroundTruth() const = 0;
};

std::unique_ptr<ScanSource> OpenScanSource(const std::filesystem::path& path,
                                           const ScanSourceOptions& options = {});

// A bag carries no sensor model: rings from the first cloud's height (organised clouds) or
// largest ring + 1; columns from an organised cloud's width, else from the median azimuth step
// between consecutive returns of a ring (points per ring when there are too few); the scan
// period from the first two stamps (0.1 s when that is implausible). Exposed for tests.
SensorModel GuessSensorModel(const Scan& first, std::uint64_t cloud_points,
                             std::uint32_t cloud_height, const Scan* second);

}  // namespace dammloam::io
