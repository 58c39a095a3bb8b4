#include "services/dammloamd/daemon_config.hpp"

#include <yaml-cpp/yaml.h>

#include <unistd.h>

#include <cctype>
#include <cmath>
#include <optional>
#include <utility>
#include <vector>
#include <set>
#include <stdexcept>

#include "io/backend_config_yaml.hpp"
#include "io/config_yaml.hpp"
#include "io/ouster_imu.hpp"

namespace dammloam::daemon {
namespace {

[[noreturn]] void Fail(const std::string& key, const std::string& what) {
  throw std::runtime_error("dammloamd config: '" + key + "' " + what);
}

void RejectUnknownKeys(const YAML::Node& node, const std::string& path,
                       const std::set<std::string>& known) {
  if (!node) return;
  if (!node.IsMap()) Fail(path, "must be a map");
  for (const auto& item : node) {
    // A list or mapping as a key names nothing (as<std::string>() would throw "bad conversion").
    if (!item.first.IsScalar() && !item.first.IsNull()) {
      Fail(path, "has a key that is a list or mapping, not a name (line " +
                     std::to_string(item.first.Mark().line + 1) + ")");
    }
    const auto key = item.first.as<std::string>();
    if (!known.count(key)) Fail(path + "." + key, "is not a known key");
  }
}

template <typename T>
void Read(const YAML::Node& node, const std::string& key, const std::string& path, T& value) {
  if (!node || !node[key]) return;
  try {
    value = node[key].as<T>();
  } catch (const YAML::Exception&) {
    Fail(path + "." + key, "has the wrong type");
  }
}

void ReadSensor(const YAML::Node& node, DaemonConfig& c) {
  const std::string path = "dammloamd.sensor";
  RejectUnknownKeys(node, path, {"name", "rings", "columns", "scan_period", "vertical_angles_deg",
                                 "min_range", "max_range", "meta"});
  Read(node, "name", path, c.sensor_name);
  Read(node, "rings", path, c.sensor.rings);
  Read(node, "columns", path, c.sensor.columns);
  Read(node, "scan_period", path, c.sensor.scan_period);
  Read(node, "vertical_angles_deg", path, c.sensor.vertical_angles_deg);
  Read(node, "min_range", path, c.sensor.min_range);
  Read(node, "max_range", path, c.sensor.max_range);
  std::string meta;
  Read(node, "meta", path, meta);
  if (!meta.empty()) c.sensor_meta = meta;
}

void ReadTopics(const YAML::Node& node, dds::TopicNames& t) {
  const std::string path = "dammloamd.topics";
  RejectUnknownKeys(node, path, {"points", "odometry", "labelled_cloud", "loop_closure", "status",
                                 "command", "command_reply", "imu", "wheel_odometry"});
  Read(node, "points", path, t.points);
  Read(node, "odometry", path, t.odometry);
  Read(node, "labelled_cloud", path, t.labelled_cloud);
  Read(node, "loop_closure", path, t.loop_closure);
  Read(node, "status", path, t.status);
  Read(node, "command", path, t.command);
  Read(node, "command_reply", path, t.command_reply);
  Read(node, "imu", path, t.imu);
  Read(node, "wheel_odometry", path, t.wheel_odometry);
}

void ReadRos2(const YAML::Node& node, Ros2Config& r) {
  const std::string path = "dammloamd.ros2";
  RejectUnknownKeys(node, path, {"enabled", "points_topic", "odometry_topic",
                                 "labelled_cloud_topic", "imu_topic", "wheel_topic", "publish_tf",
                                 "map_frame", "odom_frame", "sensor_frame", "deskew"});
  Read(node, "enabled", path, r.enabled);
  Read(node, "points_topic", path, r.points_topic);
  Read(node, "odometry_topic", path, r.odometry_topic);
  Read(node, "labelled_cloud_topic", path, r.labelled_cloud_topic);
  Read(node, "imu_topic", path, r.imu_topic);
  Read(node, "wheel_topic", path, r.wheel_topic);
  Read(node, "publish_tf", path, r.publish_tf);
  Read(node, "map_frame", path, r.map_frame);
  Read(node, "odom_frame", path, r.odom_frame);
  Read(node, "sensor_frame", path, r.sensor_frame);
  std::string deskew;
  Read(node, "deskew", path, deskew);
  if (deskew == "auto") {
    r.deskew = dds::PointTimes::kRequired;
  } else if (deskew == "off") {
    r.deskew = dds::PointTimes::kIgnored;
  } else if (!deskew.empty() || (node && node["deskew"])) {
    Fail(path + ".deskew", "must be auto or off (is '" + deskew + "')");
  }
}

void ReadCommands(const YAML::Node& node, CommandsConfig& c) {
  const std::string path = "dammloamd.commands";
  RejectUnknownKeys(node, path, {"enabled", "map_root", "token", "allowed_participants"});
  Read(node, "enabled", path, c.enabled);
  std::string map_root;
  Read(node, "map_root", path, map_root);
  c.map_root = map_root;
  Read(node, "token", path, c.token);
  Read(node, "allowed_participants", path, c.allowed_participants);
}

// A number, or an error naming the key.
double ReadNumber(const YAML::Node& node, const std::string& key, const std::string& path) {
  try {
    return node[key].as<double>();
  } catch (const YAML::Exception&) {
    Fail(path + "." + key, "must be a number");
  }
}

// {translation: [x, y, z], quaternion_xyzw: [x, y, z, w]}, as meta.json's "T_sensor_imu":
// p_sensor = R p_imu + translation, metres.
Eigen::Isometry3d ReadTransform(const YAML::Node& node, const std::string& path) {
  RejectUnknownKeys(node, path, {"translation", "quaternion_xyzw"});
  if (!node["translation"] || !node["quaternion_xyzw"]) {
    Fail(path, "needs translation: [x, y, z] and quaternion_xyzw: [x, y, z, w]");
  }
  std::vector<double> t, q;
  Read(node, "translation", path, t);
  Read(node, "quaternion_xyzw", path, q);
  if (t.size() != 3) Fail(path + ".translation", "must have 3 values (metres)");
  if (q.size() != 4) Fail(path + ".quaternion_xyzw", "must have 4 values (x, y, z, w)");
  for (double v : t) {
    if (!std::isfinite(v)) Fail(path + ".translation", "must be finite");
  }
  // An Ouster metadata's imu_to_sensor_transform is in millimetres: 6.253 there is 0.006253 here.
  if (Eigen::Vector3d(t[0], t[1], t[2]).norm() > 5.0) {
    Fail(path + ".translation", "is more than 5 m from the LiDAR: metres, not millimetres?");
  }
  const Eigen::Quaterniond quaternion(q[3], q[0], q[1], q[2]);
  if (!std::isfinite(quaternion.norm()) || std::abs(quaternion.norm() - 1.0) > 1e-3) {
    Fail(path + ".quaternion_xyzw", "must be a unit quaternion (norm 1 within 1e-3)");
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = quaternion.normalized().toRotationMatrix();
  T.translation() = Eigen::Vector3d(t[0], t[1], t[2]);
  return T;
}

void ReadImu(const YAML::Node& node, ImuConfig& c) {
  const std::string path = "dammloamd.imu";
  RejectUnknownKeys(node, path, {"enabled", "extrinsic", "time_offset", "gyro_noise_density",
                                 "accel_noise_density", "gyro_bias_random_walk",
                                 "accel_bias_random_walk", "max_wait", "max_clock_offset",
                                 "ouster_metadata"});
  if (!node) return;
  Read(node, "enabled", path, c.enabled);
  if (node["extrinsic"]) {
    c.description.T_sensor_imu = ReadTransform(node["extrinsic"], path + ".extrinsic");
    c.extrinsic_set = true;
  }
  if (node["time_offset"]) {
    c.description.time_offset = ReadNumber(node, "time_offset", path);
    c.time_offset_set = true;
  }
  ImuNoise& n = c.description.noise;
  for (auto [key, value] : {std::pair{"gyro_noise_density", &n.gyro_noise_density},
                            std::pair{"accel_noise_density", &n.accel_noise_density},
                            std::pair{"gyro_bias_random_walk", &n.gyro_bias_random_walk},
                            std::pair{"accel_bias_random_walk", &n.accel_bias_random_walk}}) {
    if (!node[key]) continue;
    *value = ReadNumber(node, key, path);
    c.noise_set = true;
  }
  std::string ouster_metadata;
  Read(node, "ouster_metadata", path, ouster_metadata);
  if (!ouster_metadata.empty()) c.ouster_metadata = ouster_metadata;
  if (node["max_wait"]) c.max_wait = ReadNumber(node, "max_wait", path);
  if (node["max_clock_offset"]) c.max_clock_offset = ReadNumber(node, "max_clock_offset", path);
}

void ValidateImu(const ImuConfig& c) {
  const std::string path = "dammloamd.imu";
  const ImuNoise& n = c.description.noise;
  for (auto [key, value] : {std::pair{"gyro_noise_density", n.gyro_noise_density},
                            std::pair{"accel_noise_density", n.accel_noise_density},
                            std::pair{"gyro_bias_random_walk", n.gyro_bias_random_walk},
                            std::pair{"accel_bias_random_walk", n.accel_bias_random_walk}}) {
    if (!(std::isfinite(value) && value > 0.0)) {
      Fail(path + "." + key, "must be a positive number (continuous-time density, SI units)");
    }
  }
  if (!(c.max_wait >= 0.0 && c.max_wait <= 1.0)) Fail(path + ".max_wait", "must be in [0, 1] s");
  if (!(c.max_clock_offset > 0.0 && c.max_clock_offset <= 10.0)) {
    Fail(path + ".max_clock_offset", "must be in (0, 10] s");
  }
  if (!(std::isfinite(c.description.time_offset) &&
        std::abs(c.description.time_offset) < c.max_clock_offset)) {
    Fail(path + ".time_offset", "must be finite and smaller in magnitude than max_clock_offset (" +
                                    std::to_string(c.max_clock_offset) + " s)");
  }
}

void ReadWheel(const YAML::Node& node, WheelConfig& c) {
  const std::string path = "dammloamd.wheel";
  RejectUnknownKeys(node, path, {"enabled", "extrinsic", "time_offset", "max_wait",
                                 "max_clock_offset", "max_speed", "max_yaw_rate"});
  if (!node) return;
  Read(node, "enabled", path, c.enabled);
  if (node["extrinsic"]) {
    c.T_sensor_base = ReadTransform(node["extrinsic"], path + ".extrinsic");
    c.extrinsic_set = c.extrinsic_known = true;
  }
  for (auto [key, value] : {std::pair{"time_offset", &c.time_offset},
                            std::pair{"max_wait", &c.max_wait},
                            std::pair{"max_clock_offset", &c.max_clock_offset},
                            std::pair{"max_speed", &c.max_speed},
                            std::pair{"max_yaw_rate", &c.max_yaw_rate}}) {
    if (node[key]) *value = ReadNumber(node, key, path);
  }
}

void ValidateWheel(const WheelConfig& c) {
  const std::string path = "dammloamd.wheel";
  if (!(c.max_wait >= 0.0 && c.max_wait <= 1.0)) Fail(path + ".max_wait", "must be in [0, 1] s");
  if (!(c.max_clock_offset > 0.0 && c.max_clock_offset <= 10.0)) {
    Fail(path + ".max_clock_offset", "must be in (0, 10] s");
  }
  if (!(std::isfinite(c.time_offset) && std::abs(c.time_offset) < c.max_clock_offset)) {
    Fail(path + ".time_offset", "must be finite and smaller in magnitude than max_clock_offset (" +
                                    std::to_string(c.max_clock_offset) + " s)");
  }
  if (!(std::isfinite(c.max_speed) && c.max_speed > 0.0)) {
    Fail(path + ".max_speed", "must be a positive number (m/s)");
  }
  if (!(std::isfinite(c.max_yaw_rate) && c.max_yaw_rate > 0.0)) {
    Fail(path + ".max_yaw_rate", "must be a positive number (rad/s)");
  }
}

// ROS 2 names: [A-Za-z0-9_/], no empty tokens, no trailing slash (what rcl accepts, minus ~ and
// substitutions, which need a node).
void ValidateRos2Name(const std::string& key, const std::string& name) {
  if (name.empty()) Fail(key, "must not be empty");
  for (char c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '/') {
      Fail(key, "('" + name + "') may only contain letters, digits, '_' and '/'");
    }
  }
  if (name.find("//") != std::string::npos || name.back() == '/') {
    Fail(key, "('" + name + "') has an empty name token");
  }
  const std::size_t first = name.find_first_not_of('/');
  if (first != std::string::npos && std::isdigit(static_cast<unsigned char>(name[first]))) {
    Fail(key, "('" + name + "') must not start with a digit");
  }
}

// TF frame ids: no leading slash (tf2 rejects it), no spaces.
void ValidateFrame(const std::string& key, const std::string& frame, bool may_be_empty) {
  if (frame.empty()) {
    if (!may_be_empty) Fail(key, "must not be empty");
    return;
  }
  if (frame.front() == '/') Fail(key, "('" + frame + "') must not start with '/' (tf2 rejects it)");
  if (frame.find_first_of(" \t\n") != std::string::npos) Fail(key, "must not contain whitespace");
}

void ValidateRos2(const Ros2Config& r) {
  ValidateRos2Name("dammloamd.ros2.points_topic", r.points_topic);
  ValidateRos2Name("dammloamd.ros2.odometry_topic", r.odometry_topic);
  ValidateRos2Name("dammloamd.ros2.labelled_cloud_topic", r.labelled_cloud_topic);
  ValidateRos2Name("dammloamd.ros2.imu_topic", r.imu_topic);
  ValidateRos2Name("dammloamd.ros2.wheel_topic", r.wheel_topic);
  // Both are nav_msgs/Odometry: the daemon would take its own poses for wheel odometry.
  if (r.wheel_topic == r.odometry_topic) {
    Fail("dammloamd.ros2.wheel_topic", "('" + r.wheel_topic + "') must differ from odometry_topic "
                                       "(the daemon's own output)");
  }
  ValidateFrame("dammloamd.ros2.map_frame", r.map_frame, false);
  ValidateFrame("dammloamd.ros2.odom_frame", r.odom_frame, false);
  ValidateFrame("dammloamd.ros2.sensor_frame", r.sensor_frame, true);
  if (r.map_frame == r.odom_frame) {
    Fail("dammloamd.ros2.odom_frame", "must differ from map_frame (TF needs two frames)");
  }
  if (r.sensor_frame == r.odom_frame || r.sensor_frame == r.map_frame) {
    Fail("dammloamd.ros2.sensor_frame", "must differ from map_frame and odom_frame");
  }
}

DaemonConfig ParseDaemon(const YAML::Node& node) {
  DaemonConfig c;
  const std::string path = "dammloamd";
  RejectUnknownKeys(node, path, {"domain", "node_name", "map_frame", "sensor", "topics", "input",
                                 "queues", "publish", "loop_closure", "save_map_on_shutdown",
                                 "ros2", "commands", "imu", "wheel"});
  if (!node) return c;
  Read(node, "domain", path, c.domain);
  Read(node, "node_name", path, c.node_name);
  Read(node, "map_frame", path, c.map_frame);
  Read(node, "loop_closure", path, c.loop_closure);
  std::string save_map;
  Read(node, "save_map_on_shutdown", path, save_map);
  c.save_map_on_shutdown = save_map;
  ReadSensor(node["sensor"], c);
  ReadTopics(node["topics"], c.topics);
  ReadRos2(node["ros2"], c.ros2);
  ReadCommands(node["commands"], c.commands);
  ReadImu(node["imu"], c.imu);
  ReadWheel(node["wheel"], c.wheel);

  const YAML::Node input = node["input"];
  RejectUnknownKeys(input, "dammloamd.input",
                    {"reliable", "depth", "max_cloud_bytes", "max_points", "max_point_time"});
  Read(input, "reliable", "dammloamd.input", c.input_reliable);
  Read(input, "depth", "dammloamd.input", c.input_depth);
  Read(input, "max_cloud_bytes", "dammloamd.input", c.limits.max_bytes);
  Read(input, "max_points", "dammloamd.input", c.limits.max_points);
  Read(input, "max_point_time", "dammloamd.input", c.limits.max_point_time);

  const YAML::Node queues = node["queues"];
  RejectUnknownKeys(queues, "dammloamd.queues", {"capacity", "max_backlog"});
  Read(queues, "capacity", "dammloamd.queues", c.queue_capacity);
  Read(queues, "max_backlog", "dammloamd.queues", c.max_backlog);

  const YAML::Node publish = node["publish"];
  RejectUnknownKeys(publish, "dammloamd.publish", {"labelled_cloud_every", "status_period"});
  Read(publish, "labelled_cloud_every", "dammloamd.publish", c.labelled_cloud_every);
  Read(publish, "status_period", "dammloamd.publish", c.status_period);
  return c;
}

// The shutdown save happens when nobody is watching any more: catch what would make it fail
// (a typo in the parent, a file or foreign directory at the target) when the daemon starts.
void ValidateSaveOnShutdown(const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  const std::string key = "dammloamd.save_map_on_shutdown";
  if (dir.empty()) return;
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) Fail(key, "(" + dir.string() + ") exists and is not a directory");
    if (!fs::is_empty(dir, ec) && !fs::exists(dir / "map.json", ec)) {
      Fail(key, "(" + dir.string() + ") is a directory without map.json: refusing to replace it");
    }
  }
  fs::path target = fs::absolute(dir, ec).lexically_normal();
  if (!target.has_filename()) target = target.parent_path();  // "maps/run1/" names run1
  const fs::path parent = target.parent_path();
  if (!fs::is_directory(parent, ec) || ::access(parent.c_str(), W_OK) != 0) {
    Fail(key, "(" + dir.string() + "): parent directory " + parent.string() +
                  " does not exist or is not writable");
  }
}

// An enabled command channel needs somewhere to confine paths to; the allow-list entries must be
// hex so that a typo cannot silently admit nobody.
void ValidateCommands(const CommandsConfig& c) {
  namespace fs = std::filesystem;
  const std::string path = "dammloamd.commands";
  for (const std::string& prefix : c.allowed_participants) {
    if (prefix.empty() || prefix.size() > 32 ||
        prefix.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos) {
      Fail(path + ".allowed_participants", "entries must be 1 to 32 hex digits (is '" + prefix +
                                               "')");
    }
  }
  if (!c.enabled) return;
  if (c.map_root.empty()) Fail(path + ".map_root", "must be set when commands are enabled");
  std::error_code ec;
  if (!c.map_root.is_absolute()) {
    Fail(path + ".map_root", "(" + c.map_root.string() + ") must be an absolute path");
  }
  if (!fs::is_directory(c.map_root, ec)) {
    Fail(path + ".map_root", "(" + c.map_root.string() + ") is not an existing directory");
  }
}

}  // namespace

FullConfig LoadConfig(const std::filesystem::path& file) {
  FullConfig config;
  if (file.empty()) return config;
  YAML::Node root;
  try {
    root = YAML::LoadFile(file.string());
  } catch (const YAML::Exception& e) {
    throw std::runtime_error("cannot read config " + file.string() + ": " + e.what());
  }
  try {
    if (root && !root.IsMap()) {
      Fail("<root>", "must be a map with sections dammloamd, odometry, backend");
    }
    RejectUnknownKeys(root, "<root>", {"dammloamd", "odometry", "backend"});
    config.daemon = ParseDaemon(root["dammloamd"]);
    if (root["odometry"]) config.odometry = io::ParseOdometryConfig(root["odometry"]);
    if (root["backend"]) config.backend = io::ParseBackendConfig(root["backend"], "backend");
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(file.string() + ": " + e.what());
  }
  return config;
}

void ValidateDaemonConfig(const DaemonConfig& c) {
  if (c.domain > 232) Fail("dammloamd.domain", "must be in [0, 232]");
  if (c.sensor.rings < 1 || c.sensor.rings > 1024) Fail("dammloamd.sensor.rings", "must be in [1, 1024]");
  if (c.sensor.columns < 1) Fail("dammloamd.sensor.columns", "must be positive");
  if (!(c.sensor.scan_period > 0.0)) Fail("dammloamd.sensor.scan_period", "must be positive");
  if (!c.sensor.vertical_angles_deg.empty() &&
      static_cast<int>(c.sensor.vertical_angles_deg.size()) != c.sensor.rings) {
    Fail("dammloamd.sensor.vertical_angles_deg", "must be empty or have `rings` values");
  }
  if (!(c.sensor.min_range >= 0.0 && c.sensor.max_range > c.sensor.min_range)) {
    Fail("dammloamd.sensor.min_range/max_range", "must satisfy 0 <= min_range < max_range");
  }
  if (c.input_depth < 1) Fail("dammloamd.input.depth", "must be at least 1");
  if (c.limits.max_bytes < 1024) Fail("dammloamd.input.max_cloud_bytes", "must be at least 1024");
  if (c.limits.max_points < 1) Fail("dammloamd.input.max_points", "must be at least 1");
  if (!(c.limits.max_point_time > 0.0)) Fail("dammloamd.input.max_point_time", "must be positive");
  if (c.max_backlog < 1) Fail("dammloamd.queues.max_backlog", "must be at least 1");
  if (c.queue_capacity < c.max_backlog + 2) {
    Fail("dammloamd.queues.capacity", "must be at least max_backlog + 2");
  }
  if (c.labelled_cloud_every < 0) Fail("dammloamd.publish.labelled_cloud_every", "must be >= 0");
  if (!(c.status_period > 0.0)) Fail("dammloamd.publish.status_period", "must be positive");
  for (const std::string* topic : {&c.topics.points, &c.topics.odometry, &c.topics.labelled_cloud,
                                   &c.topics.loop_closure, &c.topics.status, &c.topics.command,
                                   &c.topics.command_reply, &c.topics.imu,
                                   &c.topics.wheel_odometry}) {
    if (topic->empty()) Fail("dammloamd.topics", "names must not be empty");
  }
  ValidateSaveOnShutdown(c.save_map_on_shutdown);
  ValidateRos2(c.ros2);
  ValidateCommands(c.commands);
  ValidateImu(c.imu);
  ValidateWheel(c.wheel);
}

void ApplySensorMeta(const io::SequenceMeta& meta, DaemonConfig& c) {
  c.sensor = meta.model;
  c.sensor_name = meta.sensor;
  // The same description dammloam-odometry takes from a sequence's meta.json.
  const ImuDescription from_meta = io::ImuDescriptionOf(meta);
  ImuDescription& imu = c.imu.description;
  if (!c.imu.extrinsic_set) imu.T_sensor_imu = from_meta.T_sensor_imu;
  if (!c.imu.noise_set) imu.noise = from_meta.noise;
  if (!c.imu.time_offset_set) imu.time_offset = from_meta.time_offset;
  // The base as dammloam-odometry places it for a sequence's wheel.csv.
  if (!c.wheel.extrinsic_set && meta.T_sensor_base) {
    c.wheel.T_sensor_base = *meta.T_sensor_base;
    c.wheel.extrinsic_known = true;
  }
}

void ApplyOusterMetadata(DaemonConfig& c) {
  if (c.imu.ouster_metadata.empty()) return;
  const std::string key = "dammloamd.imu.ouster_metadata";
  const std::optional<Eigen::Isometry3d> T = io::ReadOusterImuToSensor(c.imu.ouster_metadata);
  if (!T) Fail(key, "(" + c.imu.ouster_metadata.string() + ") has no imu_to_sensor_transform");
  if (!c.imu.extrinsic_set) {
    c.imu.description.T_sensor_imu = *T;
    return;
  }
  // Both given: one of them is a mistake unless they agree.
  const Eigen::Isometry3d& given = c.imu.description.T_sensor_imu;
  const double mm = (given.translation() - T->translation()).norm() * 1000.0;
  const double deg = Eigen::AngleAxisd(given.linear().transpose() * T->linear()).angle() * 180.0 / M_PI;
  if (mm > 1.0 || deg > 0.1) {
    Fail("dammloamd.imu.extrinsic", "differs from " + c.imu.ouster_metadata.string() +
                                        "'s imu_to_sensor_transform by " + std::to_string(mm) +
                                        " mm, " + std::to_string(deg) + " deg: give one of them");
  }
}

}  // namespace dammloam::daemon
