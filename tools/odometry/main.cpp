// dammloam-odometry INPUT --out poses.tum [--config cfg.yaml] [--topic /points]
//     [--sensor-meta meta.json] [--mcap out.mcap]
// INPUT: sequence directory, KITTI folder, rosbag2 directory, .mcap file, ROS 1 .bag, folder of
//     .pcd/.ply files [--scan-period S], Ouster .pcap [--ouster-metadata M.json] or Velodyne
//     .pcap --velodyne-model M --velodyne-calibration C.yaml.
//     [--backend-config backend.yaml] [--map map.pcd]
//     [--stats stats.csv] [--max-scans N] [--quiet]
//     [--no-loop-closure] [--odometry-out raw.tum] [--events loops.jsonl] [--save-map DIR]
//     [--no-imu] [--no-wheel]
// dammloam-odometry SEQUENCE_DIR --out poses.tum --load-map DIR --localize
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include "io/process_memory.hpp"
#include "tools/odometry/runner.hpp"

int main(int argc, char** argv) {
  CLI::App app{"DAMM-LOAM odometry with loop closure over a sequence directory or bag"};
  dammloam::tools::RunnerOptions o;
  bool no_loop_closure = false;
  app.add_option("sequence", o.sequence,
                 "sequence directory, KITTI-layout folder, rosbag2 directory (metadata.yaml; "
                 "sqlite3 or mcap storage), .mcap file, ROS 1 .bag file, folder of .pcd/.ply files, "
                 "or an Ouster or Velodyne .pcap capture")
      ->required();
  app.add_option("--topic", o.topic,
                 "bags: the sensor_msgs/msg/PointCloud2 topic (default: the only one)");
  app.add_option("--sensor-meta", o.sensor_meta,
                 "bags and cloud folders: meta.json with the sensor model (default: guessed from "
                 "the clouds)")
      ->check(CLI::ExistingFile);
  app.add_option("--out", o.out,
                 "output trajectory (TUM): corrected with loop closure, else odometry; "
                 "localized poses with --localize")
      ->required();
  app.add_option("--config", o.config, "odometry YAML config (see deploy/config/odometry.yaml)");
  app.add_option("--backend-config", o.backend_config,
                 "back-end YAML config: loop closing and localization (see "
                 "deploy/config/backend.yaml)");
  app.add_option("--map", o.map, "write the final odometry local map as labelled PCD");
  app.add_option("--stats", o.stats, "write per-scan odometry statistics CSV");
  app.add_option("--max-scans", o.max_scans, "process at most N scans");
  app.add_flag("--quiet", o.quiet, "no progress, warnings or summary");
  app.add_option("--imu-topic", o.imu_topic,
                 "bags: the sensor_msgs/Imu topic read along (default: the only one, if any)");
  app.add_flag("--no-imu", o.no_imu, "ignore the sequence's imu.csv or the bag's IMU topic");
  app.add_flag("--no-wheel", o.no_wheel, "ignore the sequence's wheel.csv");
  auto* no_lc = app.add_flag("--no-loop-closure", no_loop_closure,
                             "odometry only: no loop detection or pose-graph correction");
  app.add_option("--odometry-out", o.odometry_out, "also write the raw odometry trajectory (TUM)");
  auto* events = app.add_option("--events", o.events,
                                "write every loop candidate as a JSON line (accepted or not)");
  auto* save = app.add_option("--save-map", o.save_map,
                              "save keyframes, descriptors and the global map to this directory");
  app.add_option("--velodyne-model", o.velodyne_model,
                 "Velodyne .pcap or bags of raw packets (velodyne_msgs/msg/VelodyneScan): vlp16, "
                 "vlp32c, hdl32e, vls128; needs --velodyne-calibration");
  app.add_option("--ouster-metadata", o.ouster_metadata,
                 "Ouster .pcap: the sensor's metadata JSON (default: the .json beside the capture "
                 "with the same name or the longest name prefix)")
      ->check(CLI::ExistingFile);
  app.add_option("--scan-period", o.scan_period,
                 "folders of .pcd/.ply: stamps = file index x this period in seconds (default: "
                 "from numeric file names, else 0.1)")
      ->check(CLI::PositiveNumber);
  app.add_option("--velodyne-calibration", o.velodyne_calibration,
                 "the sensor's calibration YAML (drivers/calibration, nebula's format)")
      ->check(CLI::ExistingFile);
  auto* mcap = app.add_option("--mcap", o.mcap,
                              "also write odometry, /tf, labelled clouds and loop closures as "
                              "ROS 2 messages into this MCAP file (Foxglove, ros2 bag play)");
  std::string mcap_compression = "zstd";
  app.add_option("--mcap-compression", mcap_compression, "chunks of --mcap: zstd or none")
      ->check(CLI::IsMember({"zstd", "none"}))
      ->needs(mcap);
  auto* load = app.add_option("--load-map", o.load_map, "map directory for --localize")
                   ->check(CLI::ExistingDirectory);
  auto* localize = app.add_flag("--localize", o.localize,
                                "localization mode in the --load-map map (no map growth)");
  events->excludes(no_lc);
  localize->needs(load);
  load->needs(localize);
  localize->excludes(mcap);
  localize->excludes(save)->excludes(no_lc)->excludes(events)->excludes("--stats")
      ->excludes("--map");
  CLI11_PARSE(app, argc, argv);
  o.loop_closure = !no_loop_closure;
  o.mcap_compression = mcap_compression == "none" ? "" : mcap_compression;
  // The daemon's allocator thresholds: without them glibc maps and faults in a scan's large
  // buffers afresh (~77 more page faults per scan on a VLP-16), and --stats would time another
  // process than the one a robot runs.
  dammloam::io::ReturnFreedMemoryEagerly(dammloam::io::kDaemonKeepFreeBytes);
  try {
    return o.localize ? dammloam::tools::RunLocalization(o) : dammloam::tools::RunMapping(o);
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 1;
  }
}
