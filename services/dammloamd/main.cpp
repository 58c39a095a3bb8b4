// dammloamd: subscribes to PointCloud, Imu, WheelOdometry and Command, publishes Odometry,
// LabelledCloud, Status, CommandReply and LoopClosure over Cyclone DDS; with --ros2 also ROS 2
// PointCloud2, Imu and wheel nav_msgs/Odometry in and nav_msgs/Odometry, PointCloud2 and /tf out
// (no ROS library).
#include <CLI/CLI.hpp>
#include <spdlog/spdlog.h>

#include <csignal>
#include <optional>

#include "services/dammloamd/daemon.hpp"
#include "services/dds/network_guard.hpp"
#include "io/backend_config_yaml.hpp"
#include "io/config_yaml.hpp"
#include "io/io_error.hpp"
#include "io/process_memory.hpp"
#include "io/sequence_meta.hpp"

namespace {

struct Options {
  std::string config_file;
  std::string odometry_config_file;
  std::string backend_config_file;
  std::optional<std::uint32_t> domain;
  std::string sensor_meta;
  std::string ouster_metadata;
  std::string points_topic;
  std::optional<int> labelled_cloud_every;
  bool no_loop_closure = false;
  bool ros2 = false;
  bool no_imu = false;
  bool no_wheel = false;
  bool allow_default_network = false;
  bool check_config = false;
  std::string log_level = "info";
};

dammloam::daemon::FullConfig BuildConfig(const Options& o) {
  using namespace dammloam;
  daemon::FullConfig config = daemon::LoadConfig(o.config_file);
  if (!o.odometry_config_file.empty()) {
    config.odometry = io::LoadOdometryConfig(o.odometry_config_file);
  }
  if (!o.backend_config_file.empty()) {
    config.backend = io::LoadBackendConfig(o.backend_config_file);
  }
  daemon::DaemonConfig& d = config.daemon;
  if (o.domain) d.domain = *o.domain;
  if (!o.sensor_meta.empty()) d.sensor_meta = o.sensor_meta;
  if (!o.points_topic.empty()) d.topics.points = o.points_topic;
  if (o.labelled_cloud_every) d.labelled_cloud_every = *o.labelled_cloud_every;
  if (o.no_loop_closure) d.loop_closure = false;
  if (o.ros2) d.ros2.enabled = true;
  if (o.no_imu) d.imu.enabled = false;
  if (o.no_wheel) d.wheel.enabled = false;
  if (!d.sensor_meta.empty()) daemon::ApplySensorMeta(io::ReadMeta(d.sensor_meta), d);
  if (!o.ouster_metadata.empty()) d.imu.ouster_metadata = o.ouster_metadata;
  daemon::ApplyOusterMetadata(d);
  daemon::ValidateDaemonConfig(d);
  return config;
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  CLI::App app{"dammloamd: DAMM-LOAM LiDAR odometry daemon over Cyclone DDS"};
  app.add_option("--config", o.config_file, "YAML config (sections dammloamd, odometry, backend)")
      ->check(CLI::ExistingFile);
  app.add_option("--odometry-config", o.odometry_config_file,
                 "odometry YAML (as dammloam-odometry --config); replaces the odometry section")
      ->check(CLI::ExistingFile);
  app.add_option("--backend-config", o.backend_config_file,
                 "back-end YAML (as dammloam-odometry --backend-config, see "
                 "deploy/config/backend.yaml); replaces the backend section")
      ->check(CLI::ExistingFile);
  app.add_option("--domain", o.domain, "DDS domain id (overrides dammloamd.domain)");
  app.add_option("--sensor-meta", o.sensor_meta, "sensor from a sequence meta.json")
      ->check(CLI::ExistingFile);
  app.add_option("--ouster-metadata", o.ouster_metadata,
                 "Ouster metadata JSON: its imu_to_sensor_transform is the IMU extrinsic "
                 "(dammloamd.imu.ouster_metadata)")
      ->check(CLI::ExistingFile);
  app.add_option("--points-topic", o.points_topic, "input PointCloud topic");
  app.add_option("--labelled-cloud-every", o.labelled_cloud_every,
                 "publish every Nth LabelledCloud (0 = never)");
  app.add_flag("--no-loop-closure", o.no_loop_closure, "do not run the loop-closure back-end");
  app.add_flag("--no-imu", o.no_imu,
               "take no IMU samples (dammloamd.imu.enabled: false): the LiDAR alone");
  app.add_flag("--no-wheel", o.no_wheel,
               "take no wheel odometry (dammloamd.wheel.enabled: false): the LiDAR alone");
  app.add_flag("--ros2", o.ros2,
               "also speak ROS 2 (dammloamd.ros2.enabled): PointCloud2 in, Odometry, labelled "
               "PointCloud2 and /tf out; the ros2 section's values or its defaults");
  app.add_flag("--allow-default-network", o.allow_default_network,
               "run without CYCLONEDDS_URI (uses the default network interface)");
  app.add_flag("--check-config", o.check_config, "validate the configuration and exit");
  app.add_option("--log-level", o.log_level, "trace, debug, info, warn, error")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error"}));
  CLI11_PARSE(app, argc, argv);
  spdlog::set_level(spdlog::level::from_str(o.log_level));

  dammloam::daemon::FullConfig config;
  try {
    config = BuildConfig(o);
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 2;
  }
  if (o.check_config) {
    spdlog::info("configuration OK");
    return 0;
  }
  if (const std::string problem = dammloam::dds::NetworkConfigProblem(o.allow_default_network);
      !problem.empty()) {
    spdlog::error("{}", problem);
    return 2;
  }

  // A save's copy of the map or a loop check's clouds must not stay resident for the
  // daemon's lifetime.
  dammloam::io::ReturnFreedMemoryEagerly(dammloam::io::kDaemonKeepFreeBytes);

  // Block the stop signals in every thread (Cyclone's included); main waits for them below.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  try {
    const auto& d = config.daemon;
    dammloam::daemon::Daemon daemon(d, config.odometry, config.backend);
    daemon.Start();
    spdlog::info("dammloamd on domain {}: {} -> {}, {}, {}; sensor {} ({}x{}); loop closure {}",
                 d.domain, d.topics.points, d.topics.odometry, d.topics.labelled_cloud,
                 d.topics.status, d.sensor_name, d.sensor.rings, d.sensor.columns,
                 d.loop_closure ? "on" : "off");
    if (d.commands.enabled) {
      spdlog::info("commands on {} (save_map, relocalize) in {}, replies on {}; token {}, "
                   "{} allowed participant prefixes", d.topics.command,
                   d.commands.map_root.string(), d.topics.command_reply,
                   d.commands.token.empty() ? "off" : "required",
                   d.commands.allowed_participants.size());
    } else {
      spdlog::info("commands disabled (dammloamd.commands.enabled): every Command is refused");
    }
    spdlog::info("map saved on shutdown: {}",
                 d.save_map_on_shutdown.empty() ? "no" : d.save_map_on_shutdown.string());
    if (d.imu.enabled) {
      const Eigen::Vector3d t = d.imu.description.T_sensor_imu.translation();
      const Eigen::Quaterniond q(d.imu.description.T_sensor_imu.linear());
      spdlog::info("IMU on {}{}: T_sensor_imu t [{:.6f} {:.6f} {:.6f}] m q_xyzw [{:.6f} {:.6f} {:.6f} "
                   "{:.6f}], time offset {:.6f} s, gyro noise {:.3g} rad/s/sqrt(Hz); the gyro is "
                   "used once samples arrive", d.topics.imu,
                   d.ros2.enabled ? " and " + d.ros2.imu_topic : std::string(), t.x(), t.y(), t.z(),
                   q.x(), q.y(), q.z(), q.w(), d.imu.description.time_offset,
                   d.imu.description.noise.gyro_noise_density);
    } else {
      spdlog::info("IMU off (--no-imu or dammloamd.imu.enabled: false): the LiDAR alone");
    }
    if (d.wheel.enabled) {
      const Eigen::Vector3d t = d.wheel.T_sensor_base.translation();
      const Eigen::Quaterniond q(d.wheel.T_sensor_base.linear());
      spdlog::info("wheel odometry on {}{}: T_sensor_base t [{:.4f} {:.4f} {:.4f}] m q_xyzw [{:.6f} "
                   "{:.6f} {:.6f} {:.6f}], time offset {:.6f} s; used once samples arrive",
                   d.topics.wheel_odometry, d.ros2.enabled ? " and " + d.ros2.wheel_topic : std::string(),
                   t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w(), d.wheel.time_offset);
      if (!d.wheel.extrinsic_known) {
        // A wrong lever arm turns every turn into a sideways slide of the sensor.
        spdlog::warn("wheel odometry: no extrinsic (dammloamd.wheel.extrinsic, or --sensor-meta's "
                     "base_extrinsic): assuming the base frame at the sensor (identity)");
      }
    } else {
      spdlog::info("wheel odometry off (--no-wheel or dammloamd.wheel.enabled: false)");
    }
    if (d.ros2.enabled) {
      spdlog::info("ROS 2: {} -> {}, {}{}; frames {} -> {} -> {}; deskew {}", d.ros2.points_topic,
                   d.ros2.odometry_topic, d.ros2.labelled_cloud_topic,
                   d.ros2.publish_tf ? ", /tf" : "", d.ros2.map_frame, d.ros2.odom_frame,
                   d.ros2.sensor_frame.empty() ? "<cloud frame_id>" : d.ros2.sensor_frame,
                   d.ros2.deskew == dammloam::dds::PointTimes::kIgnored ? "off" : "auto");
    }
    int signal_number = 0;
    sigwait(&stop_signals, &signal_number);
    spdlog::info("signal {} received, stopping", signal_number);
    daemon.Stop();
    const auto s = daemon.Stats();
    spdlog::info("stopped: {} received, {} processed, {} dropped, {} rejected", s.received,
                 s.processed, s.dropped, s.rejected);
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    spdlog::shutdown();
    return 1;
  }
  spdlog::shutdown();
  return 0;
}
