#pragma once
#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>

#include "io/bag/scan_source.hpp"

// Every recording a user may hold, behind io::ScanSource, for every tool that reads scans
// (dammloam-odometry, dammloam-replay): the io/ readers plus the packet captures and raw-packet
// bags that need drivers/ as well.
namespace dammloam::tools {

struct ScanInputOptions {
  std::filesystem::path path;  // sequence directory, KITTI folder, bag, .mcap, .pcap, cloud folder
  std::string topic;                          // bags: the PointCloud2 (or packet) topic
  std::filesystem::path sensor_meta;          // bags, cloud folders: meta.json with the model
  std::string velodyne_model;                 // raw Velodyne packets: vlp16, ...
  std::filesystem::path velodyne_calibration; // and the sensor's calibration YAML
  std::filesystem::path ouster_metadata;      // Ouster .pcap: the sensor's metadata JSON
  double scan_period = 0.0;                   // cloud folders: stamps = index x period
  bool quiet = false;                         // no log lines on where the model came from
};

// Opens the input the path names; options that do not fit its kind are refused, naming them.
std::unique_ptr<io::ScanSource> OpenScanInput(const ScanInputOptions& options);
// How many scans a run will see, for progress; 0 when the source cannot tell.
std::size_t ScansToRun(const io::ScanSource& source, std::size_t max_scans);

}  // namespace dammloam::tools
