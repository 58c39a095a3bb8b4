// dammloam-odometry on a bag against the same scans as a sequence directory: the poses must be
// equal bit for bit (the TUM files byte for byte). The bags are written by independent programs
// (@mcap/core under node; Python's sqlite3). The --mcap output of the bag run is read back by
// @mcap/core and every message decoded from its ros2msg schema.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "core/geometry/point_class.hpp"
#include "io/bag/scan_source.hpp"
#include "io/tum.hpp"
#include "tests/bag/bag_fixture.hpp"
#include "tests/bag/simulated_sequence.hpp"
#include "tests/support/temp_dir.hpp"
#include "tests/support/text_file.hpp"
#include "tools/simulate/simulator.hpp"

namespace dammloam {
namespace {

constexpr int kScans = 10;

std::string Binary() { return DAMMLOAM_BIN_DIR "/dammloam-odometry"; }

class BagOdometry : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(Binary())) GTEST_SKIP() << Binary() << " not built";
    test::WriteSimulatedOutdoorSequence(tmp_ / "seq", kScans);
  }
  // Runs the odometry; returns its output (stdout and stderr).
  std::string Run(const std::string& input, const std::string& name, const std::string& extra) {
    const test::CommandResult r = test::RunCommand(
        Binary() + " " + input + " --quiet --out " + (tmp_ / (name + ".tum")).string() +
        " --odometry-out " + (tmp_ / (name + "_raw.tum")).string() + " " + extra + " 2>&1");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return r.output;
  }
  std::string Tum(const std::string& name) { return test::ReadText(tmp_ / (name + ".tum")); }

  test::TempDir tmp_;
};

TEST_F(BagOdometry, PosesFromMcapAndRosbag2EqualPosesFromTheSequenceBitForBit) {
  DAMMLOAM_REQUIRE_NODE();
  const std::string meta = " --sensor-meta " + (tmp_ / "seq" / "meta.json").string();
  test::RunNode("write_mcap.cjs", "{\"sequence\": \"" + (tmp_ / "seq").string() +
                                      "\", \"out\": \"" + (tmp_ / "in.mcap").string() +
                                      "\", \"extra\": true}");
  const auto py = test::RunCommand("python3 " + (test::BagTestDir() / "write_rosbag2_sqlite.py").string() +
                                   " " + (tmp_ / "seq").string() + " " + (tmp_ / "bag").string() + " 2>&1");
  ASSERT_EQ(py.exit_code, 0) << py.output;

  Run((tmp_ / "seq").string(), "seq", "");
  Run((tmp_ / "in.mcap").string(), "mcap",
      "--topic /points --mcap " + (tmp_ / "out.mcap").string() + " --mcap-compression none" + meta);
  Run((tmp_ / "bag").string(), "rosbag2", meta);

  const std::string expected = Tum("seq");
  ASSERT_EQ(std::count(expected.begin(), expected.end(), '\n'), kScans);
  EXPECT_EQ(Tum("mcap"), expected);
  EXPECT_EQ(Tum("rosbag2"), expected);
  EXPECT_EQ(Tum("mcap_raw"), Tum("seq_raw"));
  EXPECT_EQ(Tum("rosbag2_raw"), Tum("seq_raw"));

  // The MCAP we wrote, through @mcap/core's indexed and streaming readers.
  const std::string json = test::RunCommand("node " + (test::BagTestDir() / "node" / "read_mcap.cjs").string() +
                                            " " + (tmp_ / "out.mcap").string()).output;
  const auto mcap = nlohmann::json::parse(json, nullptr, false);
  ASSERT_FALSE(mcap.is_discarded()) << json.substr(0, 2000);
  EXPECT_EQ(mcap["profile"], "ros2");
  std::map<std::string, std::string> schema_of;
  for (const auto& c : mcap["channels"]) {
    EXPECT_EQ(c["encoding"], "cdr");
    EXPECT_TRUE(c["metadata"].contains("offered_qos_profiles"));
    schema_of[c["topic"]] = c["schema"];
  }
  EXPECT_EQ(schema_of, (std::map<std::string, std::string>{
                           {"/dammloam/odometry", "nav_msgs/msg/Odometry"},
                           {"/tf", "tf2_msgs/msg/TFMessage"},
                           {"/dammloam/labelled_cloud", "sensor_msgs/msg/PointCloud2"},
                           {"/dammloam/loop_closures", "visualization_msgs/msg/MarkerArray"}}));
  for (const auto& s : mcap["schemas"]) EXPECT_EQ(s["encoding"], "ros2msg");
  EXPECT_GE(mcap["chunkIndexes"].get<int>(), 1);

  const auto raw = io::ReadTum(tmp_ / "mcap_raw.tum");
  const auto& odometry = mcap["topics"]["/dammloam/odometry"];
  const auto& tf = mcap["topics"]["/tf"];
  const auto& clouds = mcap["topics"]["/dammloam/labelled_cloud"];
  ASSERT_EQ(odometry.size(), raw.size());
  ASSERT_EQ(tf.size(), 2 * raw.size());  // odom -> lidar and map -> odom per scan
  EXPECT_EQ(clouds.size(), raw.size());
  std::size_t messages = odometry.size() + tf.size() + clouds.size();
  if (mcap["topics"].contains("/dammloam/loop_closures")) messages += mcap["topics"]["/dammloam/loop_closures"].size();
  EXPECT_EQ(mcap["statistics"]["messages"], std::to_string(messages));
  EXPECT_EQ(mcap["streamedMessages"].get<std::size_t>(), messages);
  for (std::size_t i = 0; i < raw.size(); ++i) {
    const auto& o = odometry[i]["value"];
    const auto& stamp = o["header"]["stamp"];
    EXPECT_NEAR(stamp["sec"].get<double>() + stamp["nanosec"].get<double>() * 1e-9, raw[i].t, 1e-6);
    EXPECT_EQ(o["header"]["frame_id"], "odom");
    EXPECT_EQ(o["child_frame_id"], "lidar");
    const auto& p = o["pose"]["pose"]["position"];
    const Eigen::Vector3d position(p["x"], p["y"], p["z"]);
    EXPECT_LT((position - raw[i].T.translation()).norm(), 1e-6) << "scan " << i;
    const auto& q = o["pose"]["pose"]["orientation"];
    const Eigen::Quaterniond orientation(q["w"], q["x"], q["y"], q["z"]);
    EXPECT_LT(orientation.angularDistance(Eigen::Quaterniond(raw[i].T.linear())), 1e-6);
    const auto& covariance = o["pose"]["covariance"];
    ASSERT_EQ(covariance.size(), 36u);
    for (int d = 0; d < 6; ++d) EXPECT_GT(covariance[7 * d].get<double>(), 0.0);
    const auto& transform = tf[2 * i]["value"]["transforms"][0];
    EXPECT_EQ(transform["header"]["frame_id"], "odom");
    EXPECT_EQ(transform["child_frame_id"], "lidar");
    EXPECT_EQ(transform["transform"]["translation"]["x"], p["x"]);
    // Too short a run for a loop: the map frame is the odometry's.
    const auto& map_odom = tf[2 * i + 1]["value"]["transforms"][0];
    EXPECT_EQ(map_odom["header"]["frame_id"], "map");
    EXPECT_EQ(map_odom["child_frame_id"], "odom");
    EXPECT_NEAR(map_odom["transform"]["translation"]["x"].get<double>(), 0.0, 1e-9);
    EXPECT_NEAR(map_odom["transform"]["rotation"]["w"].get<double>(), 1.0, 1e-9);
    const auto& cloud = clouds[i];
    EXPECT_EQ(cloud["value"]["fields"].size(), 7u);
    EXPECT_GT(cloud["value"]["width"].get<int>(), 1000);
    int labelled = 0;
    for (const auto& [label, count] : cloud["labels"].items()) {
      EXPECT_LT(static_cast<std::size_t>(std::stoi(label)), kNumPointClasses);
      labelled += count.get<int>();
    }
    EXPECT_EQ(labelled, cloud["value"]["width"].get<int>());
  }
}

// Without --sensor-meta the model of an unorganised cloud is guessed from its rings and the
// azimuth steps of its returns: a simulated VLP-16 turned into 900 columns.
TEST(GuessSensorModel, ColumnsOfAnUnorganisedVlp16CloudFromItsAzimuthSteps) {
  sim::SensorSpec sensor = sim::Vlp16();
  sensor.columns = 900;
  sim::SimOptions options;
  options.num_scans = 3;
  const sim::Simulator simulator(sim::SceneKind::Outdoor, sensor, options);
  const Scan first = simulator.SimulateScan(1);
  const Scan second = simulator.SimulateScan(2);
  const SensorModel m = io::GuessSensorModel(first, first.size(), 1, &second);
  EXPECT_EQ(m.rings, 16);
  EXPECT_EQ(m.columns, 900);
  EXPECT_NEAR(m.scan_period, simulator.sensor_model().scan_period, 1e-6);
}

}  // namespace
}  // namespace dammloam
