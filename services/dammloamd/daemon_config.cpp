#include "services/dammloamd/daemon_config.hpp"

#include <yaml-cpp/yaml.h>

#include <unistd.h>

#include <cctype>
#include <set>
#include <stdexcept>

#include "io/backend_config_yaml.hpp"
#include "io/config_yaml.hpp"

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
                                 "command", "command_reply"});
  Read(node, "points", path, t.points);
  Read(node, "odometry", path, t.odometry);
  Read(node, "labelled_cloud", path, t.labelled_cloud);
  Read(node, "loop_closure", path, t.loop_closure);
  Read(node, "status", path, t.status);
  Read(node, "command", path, t.command);
  Read(node, "command_reply", path, t.command_reply);
}

void ReadRos2(const YAML::Node& node, Ros2Config& r) {
  const std::string path = "dammloamd.ros2";
  RejectUnknownKeys(node, path, {"enabled", "points_topic", "odometry_topic",
                                 "labelled_cloud_topic", "publish_tf", "map_frame", "odom_frame",
                                 "sensor_frame", "deskew"});
  Read(node, "enabled", path, r.enabled);
  Read(node, "points_topic", path, r.points_topic);
  Read(node, "odometry_topic", path, r.odometry_topic);
  Read(node, "labelled_cloud_topic", path, r.labelled_cloud_topic);
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
                                 "ros2", "commands"});
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
                                   &c.topics.command_reply}) {
    if (topic->empty()) Fail("dammloamd.topics", "names must not be empty");
  }
  ValidateSaveOnShutdown(c.save_map_on_shutdown);
  ValidateRos2(c.ros2);
  ValidateCommands(c.commands);
}

}  // namespace dammloam::daemon
