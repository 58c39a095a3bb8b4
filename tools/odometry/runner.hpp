#pragma once
#include <optional>
#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "io/bag/scan_source.hpp"
#include "io/tum.hpp"
#include "tools/inputs/scan_input.hpp"

// The two modes of dammloam-odometry. main.cpp only parses the command line.
namespace dammloam::tools {

struct RunnerOptions {
  std::filesystem::path sequence, out, config, map, stats;
  std::filesystem::path backend_config;  // back-end YAML (deploy/config/backend.yaml)
  std::filesystem::path odometry_out;  // raw odometry trajectory (loop closure on)
  std::filesystem::path events;        // JSON lines, one per LoopEvent
  std::filesystem::path save_map, load_map;
  std::string topic;                  // bags: the PointCloud2 topic
  std::string imu_topic;              // bags: the sensor_msgs/Imu topic (empty: the only one)
  std::filesystem::path sensor_meta;  // bags: meta.json with the sensor model
  std::filesystem::path mcap;         // write the outputs as ROS 2 messages into this MCAP
  std::string mcap_compression = "zstd";  // its chunks: zstd or "" (none)
  std::string velodyne_model;                 // bags of raw Velodyne packets: vlp16, ...
  std::filesystem::path velodyne_calibration;  // and the sensor's calibration YAML
  std::filesystem::path ouster_metadata;       // Ouster .pcap: the sensor's metadata JSON
  double scan_period = 0.0;                    // cloud folders: stamps = index x period
  std::size_t max_scans = 0;
  bool loop_closure = true;
  bool localize = false;
  bool quiet = false;
  bool no_imu = false, no_wheel = false;  // ignore the sequence's imu.csv / wheel.csv
};

// Odometry over the sequence, with the loop-closing back-end unless disabled: --out holds the
// corrected trajectory (one pose per scan), --odometry-out the raw one. Returns the exit code.
int RunMapping(const RunnerOptions& options);

// Localization in the map at options.load_map: odometry only deskews, the map never grows;
// --out holds the poses of the scans that were localized, in the map frame.
int RunLocalization(const RunnerOptions& options);

// "<label> vs gt.tum: APE RMSE ..., RPE RMSE ..." through spdlog; returns the APE RMSE, or
// nothing (after a warning) if the trajectories cannot be paired.
std::optional<double> LogMetrics(const std::string& label, const std::vector<io::StampedPose>& gt,
                                 const std::vector<io::StampedPose>& estimate);

double Median(std::vector<double> values);

// The scans of options.sequence: a sequence directory, KITTI folder, rosbag2, .mcap, ROS 1 .bag,
// folder of .pcd / .ply files, or an Ouster or Velodyne .pcap (tools/inputs/scan_input.hpp).
std::unique_ptr<io::ScanSource> OpenSource(const RunnerOptions& options);

}  // namespace dammloam::tools
