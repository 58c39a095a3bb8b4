// dammloamd's YAML configuration: the shipped default loads, mistakes are named.
#include <gtest/gtest.h>

#include <fstream>
#include <vector>

#include "services/dammloamd/command_gate.hpp"
#include "services/dammloamd/daemon_config.hpp"
#include "tests/support/data_dir.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/system/sim_sequence.hpp"

namespace dammloam::daemon {
namespace {

std::string LoadError(const std::string& yaml) {
  const test::TempDir dir("system-config");
  const auto file = dir / "bad.yaml";
  std::ofstream(file) << yaml;
  try {
    ValidateDaemonConfig(LoadConfig(file).daemon);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(DaemonConfig, ShippedDefaultConfigLoadsAndValidates) {
  const FullConfig config =
      LoadConfig(std::string(DAMMLOAM_SOURCE_DIR) + "/deploy/config/dammloamd.yaml");
  EXPECT_NO_THROW(ValidateDaemonConfig(config.daemon));
  EXPECT_EQ(config.daemon.topics.points, "dammloam_points");
  EXPECT_EQ(config.daemon.sensor.rings, 64);
  EXPECT_EQ(config.daemon.max_backlog, 2u);
}

TEST(DaemonConfig, MistakesAreReportedWithTheKey) {
  EXPECT_NE(LoadError("dammloamd:\n  domian: 3\n").find("'dammloamd.domian' is not a known key"),
            std::string::npos);
  EXPECT_NE(LoadError("dammloamd:\n  queues:\n    capacity: many\n")
                .find("'dammloamd.queues.capacity' has the wrong type"),
            std::string::npos);
  EXPECT_NE(LoadError("dammloamd:\n  queues:\n    capacity: 2\n    max_backlog: 1\n")
                .find("'dammloamd.queues.capacity' must be at least max_backlog + 2"),
            std::string::npos);
  EXPECT_NE(LoadError("dammloamd:\n  sensor:\n    rings: 0\n").find("dammloamd.sensor.rings"),
            std::string::npos);
  EXPECT_NE(LoadError("odometry:\n  no_such_section: 1\n").find("no_such_section"),
            std::string::npos);
}

TEST(DaemonConfig, BackendSectionIsReadAndItsMistakesNameTheKey) {
  const FullConfig shipped =
      LoadConfig(std::string(DAMMLOAM_SOURCE_DIR) + "/deploy/config/dammloamd.yaml");
  EXPECT_TRUE(shipped.backend == backend::BackendParameters{}) << "defaults unless set";

  const test::TempDir dir("config-backend");
  const auto file = dir / "backend.yaml";
  std::ofstream(file) << "backend:\n  loop_closing:\n    scan_context:\n      max_range: 30.0\n"
                         "  localizer:\n    track_max_rmse: 0.2\n";
  const FullConfig config = LoadConfig(file);
  EXPECT_DOUBLE_EQ(config.backend.loop_closing.scan_context.max_range, 30.0);
  EXPECT_DOUBLE_EQ(config.backend.localizer.track_max_rmse, 0.2);
  EXPECT_EQ(config.backend.loop_closing.scan_context.rings,
            backend::ScanContextConfig{}.rings);  // absent: default

  EXPECT_NE(LoadError("backend:\n  loop_closing:\n    scan_contxt: {}\n")
                .find("backend.loop_closing.scan_contxt: unknown key"), std::string::npos);
  EXPECT_NE(LoadError("backend:\n  loop_closing:\n    scan_context:\n      rings: -1\n")
                .find("backend.loop_closing.scan_context.rings: must be >= 1"),
            std::string::npos);
  EXPECT_NE(LoadError("backend:\n  localizer:\n    max_registrations: lots\n")
                .find("backend.localizer.max_registrations: expected an integer"),
            std::string::npos);
}

TEST(DaemonConfig, SaveMapOnShutdownIsCheckedAtStartUp) {
  EXPECT_TRUE(LoadConfig(std::string(DAMMLOAM_SOURCE_DIR) + "/deploy/config/dammloamd.yaml")
                  .daemon.save_map_on_shutdown.empty()) << "off by default";
  const test::TempDir dir("system-config-save");
  std::ofstream(dir / "file.txt") << "x\n";
  std::filesystem::create_directories(dir / "foreign");
  std::ofstream(dir / "foreign" / "notes.txt") << "x\n";
  const std::string key = "'dammloamd.save_map_on_shutdown'";
  for (const std::string bad : {"file.txt", "foreign", "missing-parent/map"}) {
    const std::string error =
        LoadError("dammloamd:\n  save_map_on_shutdown: " + (dir / bad).string() + "\n");
    EXPECT_NE(error.find(key), std::string::npos) << bad << ": " << error;
    EXPECT_NE(error.find(bad), std::string::npos) << error;
  }
  // A new directory in an existing writable one is fine (a trailing slash too).
  EXPECT_EQ(LoadError("dammloamd:\n  save_map_on_shutdown: " + (dir / "map").string() + "/\n"), "");
  EXPECT_NE(LoadError("dammloamd:\n  topics:\n    command_reply: \"\"\n")
                .find("names must not be empty"), std::string::npos);
}

TEST(DaemonConfig, CommandsAreOffByDefaultAndAnEnabledSectionIsChecked) {
  const CommandsConfig shipped =
      LoadConfig(std::string(DAMMLOAM_SOURCE_DIR) + "/deploy/config/dammloamd.yaml")
          .daemon.commands;
  EXPECT_FALSE(shipped.enabled) << "off by default";
  EXPECT_TRUE(shipped.token.empty());
  EXPECT_TRUE(shipped.allowed_participants.empty());
  // deploy/dammloamd.service's StateDirectory (test_deploy_unit); not checked while disabled, so
  // the shipped file validates where /var/lib/dammloam does not exist.
  EXPECT_EQ(shipped.map_root, "/var/lib/dammloam");
  EXPECT_FALSE(CommandsConfig{}.enabled);

  const test::TempDir temp_dir("config-commands");
  const std::filesystem::path dir = temp_dir.path();
  const std::string root = dir.string();
  EXPECT_EQ(LoadError("dammloamd:\n  commands:\n    enabled: true\n    map_root: " + root +
                      "\n    token: abc\n    allowed_participants: [0110aBcD]\n"), "");
  const FullConfig parsed = [&] {
    std::ofstream(dir / "ok.yaml") << "dammloamd:\n  commands:\n    enabled: true\n"
                                   << "    map_root: " << root << "\n    token: abc\n";
    return LoadConfig(dir / "ok.yaml");
  }();
  EXPECT_TRUE(parsed.daemon.commands.enabled);
  EXPECT_EQ(parsed.daemon.commands.map_root, dir);
  EXPECT_EQ(parsed.daemon.commands.token, "abc");

  const auto expect_error = [](const std::string& yaml, const std::string& text) {
    const std::string error = LoadError(yaml);
    EXPECT_NE(error.find(text), std::string::npos) << yaml << " -> " << error;
  };
  expect_error("dammloamd:\n  commands:\n    enable: true\n",
               "'dammloamd.commands.enable' is not a known key");
  expect_error("dammloamd:\n  commands:\n    enabled: true\n",
               "'dammloamd.commands.map_root' must be set");
  expect_error("dammloamd:\n  commands:\n    enabled: true\n    map_root: maps\n",
               "must be an absolute path");
  expect_error("dammloamd:\n  commands:\n    enabled: true\n    map_root: " + root + "/none\n",
               "is not an existing directory");
  expect_error("dammloamd:\n  commands:\n    allowed_participants: [not-hex]\n",
               "'dammloamd.commands.allowed_participants' entries must be 1 to 32 hex digits");
  expect_error("dammloamd:\n  commands:\n    token: [a, b]\n",
               "'dammloamd.commands.token' has the wrong type");
}

TEST(CommandGate, TokensMatchOnlyWhenEqual) {
  EXPECT_TRUE(TokenMatches("s3cret", "s3cret"));
  EXPECT_FALSE(TokenMatches("", "s3cret"));
  EXPECT_FALSE(TokenMatches("s3cre", "s3cret"));
  EXPECT_FALSE(TokenMatches("s3cret!", "s3cret"));
  EXPECT_FALSE(TokenMatches(std::string("s3cret\0", 7), "s3cret"));
  EXPECT_FALSE(TokenMatches("S3cret", "s3cret"));
}

// The map root reached through a symlink (as /var/lib/... often is): both spellings work, and
// the spellings of one directory ("run1/", "./run1") name the same place.
TEST(CommandGate, PathsResolveInsideARootReachedThroughASymlink) {
  namespace fs = std::filesystem;
  const test::TempDir temp_dir("config-gate");
  const std::filesystem::path dir = temp_dir.path();
  fs::create_directories(dir / "data" / "maps");
  fs::create_directory_symlink(dir / "data" / "maps", dir / "maps-link");
  CommandsConfig config;
  config.enabled = true;
  config.map_root = dir / "maps-link";
  const CommandGate gate(config);
  const fs::path real = fs::canonical(dir / "data" / "maps");
  EXPECT_EQ(gate.map_root(), real);
  for (const std::string& name : std::vector<std::string>{
           "run1", "run1/", "./run1", (dir / "maps-link" / "run1").string(),
           (dir / "data" / "maps" / "run1").string()}) {
    const ResolvedDirectory resolved = gate.Resolve(name);
    EXPECT_FALSE(resolved.refusal) << name << ": " << resolved.refusal->message;
    EXPECT_EQ(resolved.path, real / "run1") << name;
  }
  EXPECT_EQ(gate.Resolve("a/b/c").path, real / "a" / "b" / "c");  // parents made by the save
  EXPECT_EQ(gate.Resolve((dir / "data").string()).refusal->reason, kRefusedOutsideRoot);
  EXPECT_EQ(gate.Resolve("/").refusal->reason, kRefusedOutsideRoot);
}

TEST(DaemonConfig, Ros2SectionDefaultsParseAndMistakesNameTheKey) {
  const FullConfig shipped =
      LoadConfig(std::string(DAMMLOAM_SOURCE_DIR) + "/deploy/config/dammloamd.yaml");
  const Ros2Config& r = shipped.daemon.ros2;
  EXPECT_FALSE(r.enabled) << "off by default";
  EXPECT_EQ(r.points_topic, "/points");
  EXPECT_EQ(r.odometry_topic, "/dammloam/odometry");
  EXPECT_EQ(r.labelled_cloud_topic, "/dammloam/labelled_cloud");
  EXPECT_TRUE(r.publish_tf);
  EXPECT_EQ(r.map_frame, "map");
  EXPECT_EQ(r.odom_frame, "odom");
  EXPECT_EQ(r.sensor_frame, "");
  EXPECT_EQ(r.deskew, dds::PointTimes::kRequired);

  const test::TempDir dir("system-config-ros2");
  std::ofstream(dir / "ros2.yaml") << "dammloamd:\n  ros2:\n    enabled: true\n"
                                      "    points_topic: /ouster/points\n    deskew: off\n"
                                      "    sensor_frame: os_sensor\n    publish_tf: false\n";
  const Ros2Config parsed = LoadConfig(dir / "ros2.yaml").daemon.ros2;
  EXPECT_TRUE(parsed.enabled);
  EXPECT_EQ(parsed.points_topic, "/ouster/points");
  EXPECT_EQ(parsed.deskew, dds::PointTimes::kIgnored);
  EXPECT_EQ(parsed.sensor_frame, "os_sensor");
  EXPECT_FALSE(parsed.publish_tf);

  const std::vector<std::pair<std::string, std::string>> mistakes = {
      {"    deskew: sometimes\n", "'dammloamd.ros2.deskew' must be auto or off"},
      {"    enabled: maybe\n", "'dammloamd.ros2.enabled' has the wrong type"},
      {"    point_topic: /x\n", "'dammloamd.ros2.point_topic' is not a known key"},
      {"    points_topic: \"/with space\"\n", "'dammloamd.ros2.points_topic'"},
      {"    odometry_topic: /a//b\n", "'dammloamd.ros2.odometry_topic'"},
      {"    labelled_cloud_topic: \"\"\n", "'dammloamd.ros2.labelled_cloud_topic' must not"},
      {"    odom_frame: map\n", "'dammloamd.ros2.odom_frame' must differ from map_frame"},
      {"    sensor_frame: /lidar\n", "'dammloamd.ros2.sensor_frame'"},
      {"    map_frame: \"\"\n", "'dammloamd.ros2.map_frame' must not be empty"},
  };
  for (const auto& [yaml, expected] : mistakes) {
    const std::string error = LoadError("dammloamd:\n  ros2:\n" + yaml);
    EXPECT_NE(error.find(expected), std::string::npos) << yaml << " gave: " << error;
  }
}

// The imu section (issue 55): on by default with the OS1's values; what the YAML leaves out comes
// from --sensor-meta's meta.json, what it gives wins; mistakes name the key.
TEST(DaemonConfig, ImuSectionTakesSensorMetaWhereTheYamlIsSilentAndMistakesNameTheKey) {
  const FullConfig shipped =
      LoadConfig(std::string(DAMMLOAM_SOURCE_DIR) + "/deploy/config/dammloamd.yaml");
  EXPECT_TRUE(shipped.daemon.imu.enabled);
  EXPECT_EQ(shipped.daemon.topics.imu, "dammloam_imu");
  EXPECT_EQ(shipped.daemon.ros2.imu_topic, "/imu");
  EXPECT_TRUE(shipped.daemon.imu.description.T_sensor_imu.isApprox(OusterOs1ImuToSensor()));

  io::SequenceMeta meta;
  meta.sensor = "os0-128";
  meta.model.rings = 128;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.01, 0.02, 0.03);
  meta.T_sensor_imu = T;
  ImuNoise noise;
  noise.gyro_noise_density = 1e-3;
  meta.imu_noise = noise;
  meta.imu_time_offset = 0.004;
  DaemonConfig from_meta = shipped.daemon;
  ApplySensorMeta(meta, from_meta);
  EXPECT_EQ(from_meta.sensor.rings, 128);
  EXPECT_TRUE(from_meta.imu.description.T_sensor_imu.isApprox(T));
  EXPECT_EQ(from_meta.imu.description.noise.gyro_noise_density, 1e-3);
  EXPECT_EQ(from_meta.imu.description.time_offset, 0.004);

  const test::TempDir dir("config-imu");
  const auto file = dir / "imu.yaml";
  std::ofstream(file) << "dammloamd:\n  topics:\n    imu: my_imu\n  imu:\n    time_offset: -0.002\n"
                         "    extrinsic:\n      translation: [0.1, 0, 0]\n"
                         "      quaternion_xyzw: [0, 0, 0.7071068, 0.7071068]\n";
  DaemonConfig given = LoadConfig(file).daemon;
  ApplySensorMeta(meta, given);
  EXPECT_NO_THROW(ValidateDaemonConfig(given));
  EXPECT_EQ(given.topics.imu, "my_imu");
  EXPECT_EQ(given.imu.description.time_offset, -0.002);
  EXPECT_NEAR(given.imu.description.T_sensor_imu.translation().x(), 0.1, 1e-12);
  EXPECT_NEAR(given.imu.description.T_sensor_imu.linear()(1, 0), 1.0, 1e-6);  // 90 deg about z
  EXPECT_EQ(given.imu.description.noise.gyro_noise_density, 1e-3);  // not given: meta.json's

  EXPECT_NE(LoadError("dammloamd:\n  imu:\n    enable: true\n").find("'dammloamd.imu.enable' is not a known key"),
            std::string::npos);
  EXPECT_NE(LoadError("dammloamd:\n  imu:\n    time_offset: soon\n").find("'dammloamd.imu.time_offset' must be a number"),
            std::string::npos);
  EXPECT_NE(LoadError("dammloamd:\n  imu:\n    extrinsic:\n      translation: [6.253, -11.775, 7.645]\n"
                      "      quaternion_xyzw: [0, 0, 0, 1]\n")
                .find("metres, not millimetres?"),
            std::string::npos);
  EXPECT_NE(LoadError("dammloamd:\n  imu:\n    extrinsic:\n      translation: [0, 0, 0]\n"
                      "      quaternion_xyzw: [0, 0, 0, 2]\n")
                .find("'dammloamd.imu.extrinsic.quaternion_xyzw' must be a unit quaternion"),
            std::string::npos);
  EXPECT_NE(LoadError("dammloamd:\n  imu:\n    gyro_noise_density: 0\n").find("'dammloamd.imu.gyro_noise_density' must be a positive number"),
            std::string::npos);
  EXPECT_NE(LoadError("dammloamd:\n  imu:\n    time_offset: 2.0\n").find("'dammloamd.imu.time_offset' must be finite and smaller"),
            std::string::npos);
  EXPECT_NE(LoadError("dammloamd:\n  imu:\n    max_wait: 5\n").find("'dammloamd.imu.max_wait' must be in [0, 1] s"),
            std::string::npos);
  EXPECT_NE(LoadError("dammloamd:\n  ros2:\n    imu_topic: imu//raw\n").find("dammloamd.ros2.imu_topic"),
            std::string::npos);
}

// The wheel section (issue 55): on by default at identity (assumed, not known); the extrinsic
// from the YAML, else meta.json's base_extrinsic; mistakes name the key.
TEST(DaemonConfig, WheelSectionTakesTheBaseExtrinsicFromTheYamlElseSensorMetaAndMistakesNameTheKey) {
  const FullConfig shipped =
      LoadConfig(std::string(DAMMLOAM_SOURCE_DIR) + "/deploy/config/dammloamd.yaml");
  const WheelConfig& w = shipped.daemon.wheel;
  EXPECT_TRUE(w.enabled);
  EXPECT_EQ(shipped.daemon.topics.wheel_odometry, "dammloam_wheel_odometry");
  EXPECT_EQ(shipped.daemon.ros2.wheel_topic, "/odom");
  EXPECT_TRUE(w.T_sensor_base.isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_FALSE(w.extrinsic_known);
  EXPECT_EQ(w.time_offset, 0.0);

  io::SequenceMeta meta;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.0, 0.0, -0.4);
  meta.T_sensor_base = T;
  DaemonConfig from_meta = shipped.daemon;
  ApplySensorMeta(meta, from_meta);
  EXPECT_TRUE(from_meta.wheel.T_sensor_base.isApprox(T));
  EXPECT_TRUE(from_meta.wheel.extrinsic_known);
  DaemonConfig without_base = shipped.daemon;
  ApplySensorMeta(io::SequenceMeta{}, without_base);
  EXPECT_FALSE(without_base.wheel.extrinsic_known);

  const test::TempDir dir("config-wheel");
  const auto file = dir / "wheel.yaml";
  std::ofstream(file) << "dammloamd:\n  topics:\n    wheel_odometry: my_wheels\n"
                         "  ros2:\n    wheel_topic: /base/odom\n"
                         "  wheel:\n    time_offset: 0.01\n    max_wait: 0.02\n"
                         "    max_speed: 3.0\n    max_yaw_rate: 2.0\n"
                         "    extrinsic:\n      translation: [-0.2, 0, -0.5]\n"
                         "      quaternion_xyzw: [0, 0, 0, 1]\n";
  DaemonConfig given = LoadConfig(file).daemon;
  ApplySensorMeta(meta, given);  // the YAML's extrinsic wins
  EXPECT_NO_THROW(ValidateDaemonConfig(given));
  EXPECT_EQ(given.topics.wheel_odometry, "my_wheels");
  EXPECT_EQ(given.ros2.wheel_topic, "/base/odom");
  EXPECT_EQ(given.wheel.time_offset, 0.01);
  EXPECT_EQ(given.wheel.max_wait, 0.02);
  EXPECT_EQ(given.wheel.max_speed, 3.0);
  EXPECT_EQ(given.wheel.max_yaw_rate, 2.0);
  EXPECT_TRUE(given.wheel.T_sensor_base.translation().isApprox(Eigen::Vector3d(-0.2, 0, -0.5)));
  EXPECT_TRUE(given.wheel.extrinsic_known);

  for (const auto& [yaml, expected] : std::vector<std::pair<std::string, std::string>>{
           {"  wheel:\n    enable: true\n", "'dammloamd.wheel.enable' is not a known key"},
           {"  wheel:\n    time_offset: soon\n", "'dammloamd.wheel.time_offset' must be a number"},
           {"  wheel:\n    time_offset: 2.0\n", "'dammloamd.wheel.time_offset' must be finite and smaller"},
           {"  wheel:\n    max_wait: 5\n", "'dammloamd.wheel.max_wait' must be in [0, 1] s"},
           {"  wheel:\n    max_clock_offset: 0\n", "'dammloamd.wheel.max_clock_offset' must be in (0, 10] s"},
           {"  wheel:\n    max_speed: -1\n", "'dammloamd.wheel.max_speed' must be a positive number"},
           {"  wheel:\n    max_yaw_rate: .nan\n", "'dammloamd.wheel.max_yaw_rate' must be a positive number"},
           {"  wheel:\n    extrinsic:\n      translation: [0, 0]\n      quaternion_xyzw: [0, 0, 0, 1]\n",
            "'dammloamd.wheel.extrinsic.translation' must have 3 values"},
           {"  wheel:\n    extrinsic:\n      translation: [0, 0, 0]\n",
            "'dammloamd.wheel.extrinsic' needs translation"},
           {"  ros2:\n    wheel_topic: odom//raw\n", "dammloamd.ros2.wheel_topic"},
           {"  ros2:\n    wheel_topic: /dammloam/odometry\n",
            "'dammloamd.ros2.wheel_topic' ('/dammloam/odometry') must differ from odometry_topic"},
           {"  topics:\n    wheel_odometry: \"\"\n", "'dammloamd.topics' names must not be empty"}}) {
    EXPECT_NE(LoadError("dammloamd:\n" + yaml).find(expected), std::string::npos)
        << yaml << " -> " << LoadError("dammloamd:\n" + yaml);
  }
}

// --ouster-metadata: the imu_to_sensor_transform of real Ouster metadata (top level in firmware
// 2.2, under imu_intrinsics in later files), millimetres to metres.
TEST(DaemonConfig, OusterMetadataGivesTheImuExtrinsicInMetres) {
  const auto dir = test::DataDir() / "ouster_sdk_pcaps";
  const auto flat = dir / "OS-0-32-U1_v2.2.0_1024x10.json";
  const auto nested = dir / "OS-1-128_767798045_1024x10_20230712_120049.json";
  DAMMLOAM_REQUIRE_DATA(flat);
  DAMMLOAM_REQUIRE_DATA(nested);
  DaemonConfig c;
  c.imu.ouster_metadata = flat;
  ApplyOusterMetadata(c);
  EXPECT_TRUE(c.imu.description.T_sensor_imu.translation().isApprox(
      Eigen::Vector3d(0.006253, -0.011775, 0.007645), 1e-12));
  EXPECT_TRUE(c.imu.description.T_sensor_imu.linear().isIdentity());
  c = DaemonConfig{};
  c.imu.ouster_metadata = nested;
  ApplyOusterMetadata(c);
  EXPECT_TRUE(c.imu.description.T_sensor_imu.translation().isApprox(
      Eigen::Vector3d(-0.002441, -0.009725, 0.007533), 1e-12));
  // An extrinsic in the YAML as well that disagrees: one of them is wrong.
  c = DaemonConfig{};
  c.imu.ouster_metadata = nested;
  c.imu.extrinsic_set = true;  // the OS1's default, 9 mm away
  try {
    ApplyOusterMetadata(c);
    ADD_FAILURE() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("give one of them"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace dammloam::daemon
