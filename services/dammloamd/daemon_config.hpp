#pragma once
// dammloamd configuration: the `dammloamd` section of the YAML file (this struct), the
// `odometry` section (OdometryConfig, parsed by io/config_yaml) and the `backend` section
// (backend::BackendParameters, parsed by io/backend_config_yaml).
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/backend/backend_config.hpp"
#include "core/geometry/scan.hpp"
#include "core/inertial/inertial_config.hpp"
#include "core/odometry/odometry_config.hpp"
#include "io/sequence_meta.hpp"
#include "services/dds/point_cloud.hpp"
#include "services/dds/topics.hpp"

namespace dammloam::daemon {

// The `ros2` section: ROS 2 topics next to the native ones (off unless enabled or --ros2).
// Names are ROS 2 names; the DDS topic is rt + name (dds::Ros2TopicName).
struct Ros2Config {
  bool enabled = false;
  std::string points_topic = "/points";                          // sensor_msgs/PointCloud2 in
  std::string odometry_topic = "/dammloam/odometry";             // nav_msgs/Odometry out
  std::string labelled_cloud_topic = "/dammloam/labelled_cloud"; // sensor_msgs/PointCloud2 out
  std::string imu_topic = "/imu";                                // sensor_msgs/Imu in (imu.enabled)
  std::string wheel_topic = "/odom";  // nav_msgs/Odometry in, its twist (wheel.enabled)
  bool publish_tf = true;                                        // /tf: map->odom, odom->sensor
  std::string map_frame = "map";
  std::string odom_frame = "odom";
  std::string sensor_frame;            // empty: the input cloud's header.frame_id
  // auto: clouds need a per-point time field (deskew); off: times are ignored, no deskew.
  dds::PointTimes deskew = dds::PointTimes::kRequired;
};

// The `commands` section: who may send Command samples and where their directories may be.
// Off unless enabled: any participant on the domain could otherwise write or load maps anywhere.
struct CommandsConfig {
  bool enabled = false;
  // Every save_map / relocalize directory must resolve (symlinks followed) strictly inside this
  // existing directory; relative names are taken relative to it. Required when enabled.
  std::filesystem::path map_root;
  // Non-empty: Command.token must equal it (compared in constant time).
  std::string token;
  // Non-empty: the sending participant's GUID (32 hex digits, as the daemon logs and refusals
  // name it) must start with one of these hex prefixes. Cyclone draws a new random GUID (after
  // its vendor bytes 0110) for every participant, so a prefix only pins a Cyclone sender for one
  // run; Fast DDS derives it from host and process. Without DDS Security a GUID can be forged.
  std::vector<std::string> allowed_participants;
};

// The `imu` section (issue 55): the IMU's gyroscope drives the odometry's rotation (deskew,
// prediction, rotation prior), as in dammloam-odometry with a sequence's imu.csv. Values the
// YAML leaves out come from --sensor-meta's meta.json ("imu_extrinsic", "imu"), else they are
// the Ouster OS1's (ImuDescription's defaults). The extrinsic: imu.extrinsic, else the
// imu_to_sensor_transform of imu.ouster_metadata (--ouster-metadata), else meta.json's.
struct ImuConfig {
  // Subscribe to the Imu topic (and, with ros2, to ros2.imu_topic). The gyro is used from the
  // first sample on; without samples every scan is the LiDAR's alone, bit-identical to off.
  bool enabled = true;
  ImuDescription description;  // T_sensor_imu, noise densities, time offset
  // Which parts of `description` the YAML gave (the rest may come from --sensor-meta).
  bool extrinsic_set = false, noise_set = false, time_offset_set = false;
  // An Ouster sensor's metadata JSON: its imu_to_sensor_transform is the extrinsic unless
  // imu.extrinsic is given (ApplyOusterMetadata).
  std::filesystem::path ouster_metadata;
  // Wall time a scan waits at most for the samples that cover it (up to its end + 20 ms), s;
  // only while an IMU writer is matched. A live IMU sends them within a sample period.
  double max_wait = 0.05;
  // A sample stamped further than this from the scan being registered is on another clock (or
  // its time offset is wrong): dropped and counted (clock_offset), s.
  double max_clock_offset = 1.0;
};

// The `wheel` section (issue 55): wheel odometry's motion between scans is the prediction's
// translation and a translation prior of the registration, as in dammloam-odometry with a
// sequence's wheel.csv. The extrinsic: wheel.extrinsic, else --sensor-meta's meta.json
// "base_extrinsic", else the base at the sensor (identity, with a warning).
struct WheelConfig {
  // Subscribe to the WheelOdometry topic (and, with ros2, to ros2.wheel_topic). Used from the
  // first sample on; without samples every scan is the LiDAR's alone, bit-identical to off.
  bool enabled = true;
  // base frame in the sensor frame: p_sensor = T_sensor_base p_base.
  Eigen::Isometry3d T_sensor_base = Eigen::Isometry3d::Identity();
  bool extrinsic_set = false;    // wheel.extrinsic was given
  bool extrinsic_known = false;  // from wheel.extrinsic or meta.json (else identity, assumed)
  // Wheel stamp minus the LiDAR time of the same instant, s: subtracted from every stamp.
  double time_offset = 0.0;
  // Wall time a scan waits at most for the samples that cover it (up to its end + 40 ms), s;
  // only while a wheel writer is matched.
  double max_wait = 0.05;
  // A sample stamped further than this from the scan being registered is on another clock (or
  // its time offset is wrong): dropped and counted (clock_offset), s.
  double max_clock_offset = 1.0;
  // Readings beyond these are no carrier's motion (a corrupted message, a unit error): dropped
  // and counted (absurd_speed). WheelUseConfig's defaults, which the offline runner uses.
  double max_speed = 20.0;     // m/s
  double max_yaw_rate = 10.0;  // rad/s, any axis
};

struct DaemonConfig {
  std::uint32_t domain = 0;
  std::string node_name = "dammloamd";
  std::string map_frame = "map";
  std::string sensor_name = "os1-64";
  SensorModel sensor;                   // or loaded from sensor_meta (a sequence meta.json)
  std::filesystem::path sensor_meta;
  dds::TopicNames topics;
  int input_depth = 4;                  // DDS reader history of the points topic
  bool input_reliable = true;
  dds::CloudLimits limits;              // max_ring follows sensor.rings
  std::size_t queue_capacity = 8;       // each stage queue
  // Scans allowed to wait behind the one in work. 2 absorbs a 200 ms stall at 10 Hz: the first
  // scans after start (the map and buffers grow, ~130 ms for a 128-beam scan) dropped two
  // OS1-128 x 2048 scans at 1 and none at 2; a sustained overload still drops.
  std::size_t max_backlog = 2;
  int labelled_cloud_every = 1;         // publish every Nth LabelledCloud; 0 = never
  double status_period = 1.0;           // seconds
  bool loop_closure = true;             // run the loop-closure back-end thread
  // Map directory written (atomically) by Stop(); empty = off. Runs the back-end (keyframes only,
  // no loop search) even when loop_closure is false.
  std::filesystem::path save_map_on_shutdown;
  Ros2Config ros2;
  CommandsConfig commands;
  ImuConfig imu;
  WheelConfig wheel;
};

struct FullConfig {
  DaemonConfig daemon;
  OdometryConfig odometry;
  backend::BackendParameters backend;
};

// Reads the YAML file (every section optional; unknown keys and wrong types are errors naming the
// key). Throws std::runtime_error naming the file and key. An empty path gives the defaults.
FullConfig LoadConfig(const std::filesystem::path& file);

// --sensor-meta: the sensor model, the IMU's extrinsic, noise and time offset, and the wheels'
// base extrinsic, where the YAML did not give them.
void ApplySensorMeta(const io::SequenceMeta& meta, DaemonConfig& config);
// imu.ouster_metadata: its imu_to_sensor_transform as the extrinsic unless imu.extrinsic was
// given (then it must agree within 1 mm and 0.1 deg). Call after ApplySensorMeta: the metadata
// wins over meta.json. Throws naming the file when it is unreadable or has no such key.
void ApplyOusterMetadata(DaemonConfig& config);

// Throws std::runtime_error naming the field when a value is out of range.
void ValidateDaemonConfig(const DaemonConfig& config);

}  // namespace dammloam::daemon
